#!/usr/bin/env python3
"""Tables of the interval calibration (scripts/sg_calibration.sh) from the evaluation.json files.

Usage: scripts/sg_calibration_table.py RUNS_DIR [--out FILE.md] [--inject DOC.md] [--estimator E]
                                       [--command CMD]

--inject replaces the block between "<!-- sg_calibration:begin -->" and
"<!-- sg_calibration:end -->" in DOC.md with the tables, so the page cannot drift from the runs.

For each case (run folders <case>_s<seed>): per statistic, the share of seeds whose ERR_REAL lies
inside SG#1's and SG#2's 90 % predictive interval, the mean percentile of REAL, and the spread of
the single-realization DIFF_2 next to the DIFF of the means.
"""
import argparse, collections, json, math, os, re, sys

STATS = ["horizontal_m", "vertical_m", "roll_deg", "pitch_deg", "heading_deg"]
SHORT = ["horizontal", "vertical", "roll", "pitch", "heading"]


def load(runs_dir):
    cases = collections.defaultdict(list)
    for name in sorted(os.listdir(runs_dir)):
        m = re.match(r"(.+)_s(\d+)$", name)
        path = os.path.join(runs_dir, name, "evaluation.json")
        if not m or not os.path.exists(path):
            continue
        with open(path) as f:
            cases[m.group(1)].append(json.load(f))
    return cases


def coverage(runs, label, stat):
    inside = n = 0
    for r in runs:
        v = r.get("verdict", {}).get(label, {}).get(stat)
        if v is None:
            continue
        n += 1
        inside += v == "consistent"
    return inside, n


def verdict_counts(runs, label, stat):
    c = collections.Counter(r["verdict"][label][stat] for r in runs if r.get("verdict", {}).get(label, {}).get(stat))
    return c


def table(cases):
    lines = []
    lines.append("| case | seeds | K | " + " | ".join(f"SG#2 covers REAL: {s}" for s in SHORT) + " |")
    lines.append("|---|---|---|" + "---|" * 5)
    for case, runs in cases.items():
        k = runs[0].get("realizations", "?")
        cells = []
        for s in STATS:
            i, n = coverage(runs, "SG2", s)
            cells.append(f"{100.0 * i / n:.0f} % ({i}/{n})" if n else "n/a")
        lines.append(f"| {case} | {len(runs)} | {k} | " + " | ".join(cells) + " |")
    lines.append("")
    lines.append("| case | " + " | ".join(f"SG#1 covers REAL: {s}" for s in SHORT) + " |")
    lines.append("|---|" + "---|" * 5)
    for case, runs in cases.items():
        cells = []
        for s in STATS:
            i, n = coverage(runs, "SG1", s)
            c = verdict_counts(runs, "SG1", s)
            extra = f"; opt {c['optimistic']}, pess {c['pessimistic']}" if n and i < n else ""
            cells.append(f"{100.0 * i / n:.0f} % ({i}/{n}{extra})" if n else "n/a")
        lines.append(f"| {case} | " + " | ".join(cells) + " |")
    lines.append("")
    lines.append("Mean over seeds of REAL's percentile in SG#2 (50 % expected on a null case) and of the width of "
                 "SG#2's interval relative to its mean:")
    lines.append("")
    lines.append("| case | " + " | ".join(SHORT) + " |")
    lines.append("|---|" + "---|" * 5)
    for case, runs in cases.items():
        cells = []
        for s in STATS:
            p = [r["real_percentile"]["SG2"][s] for r in runs if r.get("real_percentile", {}).get("SG2", {}).get(s) is not None]
            w = [(r["predictive"]["SG2"][s]["p95"] - r["predictive"]["SG2"][s]["p05"]) / r["predictive"]["SG2"][s]["mean"]
                 for r in runs if r["predictive"]["SG2"][s]["mean"] > 0]
            cells.append(f"{100 * sum(p) / len(p):.0f} %, width {100 * sum(w) / len(w):.0f} %" if p and w else "n/a")
        lines.append(f"| {case} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs_dir")
    ap.add_argument("--out")
    ap.add_argument("--inject")
    ap.add_argument("--estimator", default="ekf")
    ap.add_argument("--command", default="scripts/sg_calibration.sh OUT")
    a = ap.parse_args()
    cases = load(a.runs_dir)
    if not cases:
        print(f"sg_calibration_table: no <case>_s<seed>/evaluation.json under {a.runs_dir}", file=sys.stderr)
        return 1
    md = (f"# Predictive-interval calibration ({a.estimator})\n\nWritten by scripts/sg_calibration_table.py from "
          f"`{a.command}`. A cell is the share of seeds whose ERR_REAL lies inside the 90 % predictive interval "
          f"[p05, p95] of the grafted realizations (`verdict` = consistent).\n\n" + table(cases))
    print(md)
    if a.out:
        with open(a.out, "w") as f:
            f.write(md)
    if a.inject:
        begin, end = "<!-- sg_calibration:begin -->", "<!-- sg_calibration:end -->"
        with open(a.inject) as f:
            doc = f.read()
        if begin not in doc or end not in doc:
            print(f"sg_calibration_table: {a.inject} has no {begin} ... {end} block", file=sys.stderr)
            return 1
        body = md.split("\n", 2)[2]  # without the page title
        doc = doc[: doc.index(begin) + len(begin)] + "\n" + body + doc[doc.index(end):]
        with open(a.inject, "w") as f:
            f.write(doc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
