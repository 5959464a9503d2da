#!/usr/bin/env python3
"""The table of the window-length study (configs/batch/study_window.yaml) from its results
database. Usage: batch_window_study.py OUT_DIR [--docs docs/batch.md]
Prints the table; with --docs, rewrites the block between the study markers of that page (the
query, the table and the drives left out), so the page cannot drift from the run."""
import argparse
import os
import sqlite3
import sys

# The query the page shows: horizontal errors of every finished task, with its window length.
QUERY = """
SELECT t.case_name, t.estimator,
       json_extract(t.options_json, '$."fgo.window_nodes"') AS window_nodes,
       s.scope, s.measure, s.value
FROM statistics s JOIN tasks t USING (task_id) JOIN runs r USING (task_id)
WHERE r.status = 'ok' AND s.statistic = 'horizontal_m' AND s.solution = s.estimator
  AND s.measure IN ('rms', 'max_rms')
ORDER BY t.case_name, t.estimator, window_nodes
""".strip()

ROWS = [("outage", "rms", "outage RMS h vs truth (m)"),
        ("outage", "max_rms", "RMS of outage max h vs truth (m)"),
        ("checkpoint", "rms", "check point RMS h (m)"),
        ("checkpoint", "max_rms", "check point RMS of max h (m)"),
        ("reference", "rms", "outage RMS h vs reference.nav (m)")]
BEGIN, END = "<!-- window-study:begin -->", "<!-- window-study:end -->"


def configurations(db):
    """(estimator, window) pairs in a fixed order: ekf, rts, fgo, then fgo-window by length."""
    order = {"ekf": 0, "rts": 1, "fgo": 2, "fgo-window": 3}
    found = db.execute("SELECT DISTINCT estimator, json_extract(options_json, "
                       "'$.\"fgo.window_nodes\"') FROM tasks").fetchall()
    return sorted(found, key=lambda c: (order.get(c[0], 9), c[1] or 0))


def complete_cases(db):
    """Cases whose every task finished, and for the others the failures."""
    kept, left_out = [], {}
    for (case,) in db.execute("SELECT DISTINCT case_name FROM tasks ORDER BY case_name"):
        bad = db.execute(
            "SELECT t.estimator, coalesce(r.error, 'no record') FROM tasks t LEFT JOIN runs r "
            "USING (task_id) WHERE t.case_name = ? AND coalesce(r.status, '') <> 'ok'",
            (case,)).fetchall()
        if bad:
            left_out[case] = bad
        else:
            kept.append(case)
    return kept, left_out


def table(db):
    values = {}
    for case, est, window, scope, measure, value in db.execute(QUERY):
        values[(case, est, window, scope, measure)] = value
    configs = configurations(db)
    kept, left_out = complete_cases(db)
    head = ["case", "statistic"] + [e if w is None else f"{e} {w}" for e, w in configs]
    md = "| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n"
    for case in kept:
        for scope, measure, label in ROWS:
            cells = [values.get((case, e, w, scope, measure)) for e, w in configs]
            if all(c is None for c in cells):
                continue
            md += f"| {case} | {label} | " + " | ".join(
                "-" if c is None else f"{c:.3f}" for c in cells) + " |\n"
    notes = ""
    for case, bad in left_out.items():
        by_message = {}
        for est, msg in bad:
            by_message.setdefault(msg.splitlines()[-1][:200], []).append(est)
        what = "; ".join(f"{', '.join(sorted(set(es)))} ({len(es)} task{'s' * (len(es) > 1)}): "
                         f"`{m}`" for m, es in by_message.items())
        notes += f"\nLeft out, not every estimator ran on `{case}`: {what}\n"
    return md, notes, kept


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("out_dir")
    ap.add_argument("--docs", help="page whose study block is rewritten")
    a = ap.parse_args()
    path = os.path.join(a.out_dir, "results.sqlite")
    if not os.path.exists(path):
        sys.exit(f"batch_window_study: {path} not found: run the batch first")
    db = sqlite3.connect(path)
    md, notes, kept = table(db)
    print(md + notes)
    if not a.docs:
        return
    block = ("```python\nimport sqlite3\n"
             "db = sqlite3.connect(\"out/batch_window_study/results.sqlite\")\n"
             f"rows = db.execute(\"\"\"\n{QUERY}\n\"\"\").fetchall()\n```\n\n"
             f"The table below is these rows, one column per estimator and window length, for "
             f"the cases where every estimator ran ({', '.join(kept)}):\n\n{md}{notes}")
    text = open(a.docs).read()
    if BEGIN not in text or END not in text:
        sys.exit(f"batch_window_study: {a.docs} has no {BEGIN} ... {END} block")
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    with open(a.docs, "w") as f:
        f.write(head + BEGIN + "\n" + block + END + tail)
    print(f"batch_window_study: table written into {a.docs}")


if __name__ == "__main__":
    main()
