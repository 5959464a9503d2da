#!/usr/bin/env python3
"""Tables of the interval calibration (scripts/experiments/sg_calibration.sh) from the evaluation.json files.

Usage: scripts/experiments/sg_calibration_table.py RUNS_DIR [RUNS_DIR ...] [--out FILE.md] [--inject DOC.md]
                                       [--estimator E] [--command CMD]

--inject replaces the block between "<!-- sg_calibration:begin -->" and
"<!-- sg_calibration:end -->" in DOC.md with the tables, so the page cannot drift from the runs.

For each case (run folders <case>_s<seed>): per statistic, the share of seeds whose ERR_REAL lies
inside SG#1's and SG#2's 90 % predictive interval with its 95 % Wilson score interval, the paired
comparison of SG#1 and SG#2 over the same seeds (exact two-sided sign test on the seeds where one
covers REAL and the other does not), and the mean percentile of REAL and width of SG#2's interval.
Null cases (name starting with "null") are marked against the 80-97 % target.
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


def wilson(k, n, z=1.959964):
    """95 % Wilson score interval of a binomial proportion k/n."""
    if n == 0:
        return float("nan"), float("nan")
    p = k / n
    den = 1.0 + z * z / n
    mid = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return max(0.0, mid - half), min(1.0, mid + half)


def sign_test(a, b):
    """Exact two-sided binomial test of a successes against b, p = 1/2 (McNemar's exact test)."""
    n = a + b
    if n == 0:
        return 1.0
    k = min(a, b)
    tail = sum(math.comb(n, i) for i in range(k + 1)) / 2.0 ** n
    return min(1.0, 2.0 * tail)


def paired(runs, stat):
    """Seeds where SG#2 covers REAL and SG#1 does not, and the other way round."""
    only2 = only1 = 0
    for r in runs:
        v = r.get("verdict", {})
        c1 = v.get("SG1", {}).get(stat) == "consistent"
        c2 = v.get("SG2", {}).get(stat) == "consistent"
        only2 += c2 and not c1
        only1 += c1 and not c2
    return only2, only1


def cell(runs, label, stat, target=False):
    i, n = coverage(runs, label, stat)
    if not n:
        return "n/a"
    lo, hi = wilson(i, n)
    mark = ""
    if target:
        mark = " ok" if 0.80 <= i / n <= 0.97 else " **out**"
    return f"{100.0 * i / n:.0f} % ({i}/{n}; {100 * lo:.0f}-{100 * hi:.0f}){mark}"


def table(cases):
    lines = ["Coverage: share of seeds with ERR_REAL inside the 90 % interval, (covered/seeds; 95 % Wilson "
             "interval in %). On the null cases \"ok\" marks the 80-97 % target.", ""]
    for label, name in (("SG2", "SG#2"), ("SG1", "SG#1")):
        lines.append(f"| case | seeds | K | " + " | ".join(f"{name} covers REAL: {s}" for s in SHORT) + " |")
        lines.append("|---|---|---|" + "---|" * 5)
        for case, runs in cases.items():
            k = runs[0].get("realizations", "?")
            target = label == "SG2" and case.startswith("null")
            cells = [cell(runs, label, s, target) for s in STATS]
            lines.append(f"| {case} | {len(runs)} | {k} | " + " | ".join(cells) + " |")
        lines.append("")
    lines.append("Paired over the same seeds: seeds where only SG#2 covers REAL / only SG#1 does, and the exact "
                 "two-sided sign test (McNemar) p-value of \"both cover equally often\":")
    lines.append("")
    lines.append("| case | " + " | ".join(SHORT) + " |")
    lines.append("|---|" + "---|" * 5)
    for case, runs in cases.items():
        cells = []
        for s in STATS:
            a, b = paired(runs, s)
            cells.append(f"{a} / {b}, p = {sign_test(a, b):.2g}")
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
    ap.add_argument("runs_dir", nargs="+")
    ap.add_argument("--out")
    ap.add_argument("--inject")
    ap.add_argument("--estimator", default="ekf")
    ap.add_argument("--command", default="scripts/experiments/sg_calibration.sh OUT")
    a = ap.parse_args()
    cases = {}
    for d in a.runs_dir:
        for case, runs in load(d).items():
            cases.setdefault(case, []).extend(runs)
    if not cases:
        print(f"sg_calibration_table: no <case>_s<seed>/evaluation.json under {a.runs_dir}", file=sys.stderr)
        return 1
    md = (f"# Predictive-interval calibration ({a.estimator})\n\nWritten by scripts/experiments/sg_calibration_table.py from "
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
