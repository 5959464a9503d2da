#!/usr/bin/env python3
"""Markdown table of what decides whether an evaluation tells SG#1 from SG#2: per run and
statistic, the gap between the SG#1 and SG#2 mean ERR against the width of one realization's
90 % interval, whether the intervals are apart, and ERR_REAL's verdicts.

Usage: scripts/experiments/sample_separation_table.py LABEL=OUT_DIR [LABEL=OUT_DIR ...]
   (OUT_DIR holds the evaluation.json of `graftnav evaluate`; e.g. tactical-ekf=out/tactical)
"""
import json
import os
import sys

STATS = ["horizontal_m", "vertical_m", "roll_deg", "pitch_deg", "heading_deg"]


def rows(label, out_dir):
    with open(os.path.join(out_dir, "evaluation.json")) as f:
        j = json.load(f)
    p = j["predictive"]
    for s in STATS:
        a, b = p["SG1"][s], p["SG2"][s]
        gap = abs(b["mean"] - a["mean"]) / a["mean"]
        width = (b["p95"] - b["p05"]) / b["mean"]
        apart = not (a["p05"] <= b["p95"] and b["p05"] <= a["p95"])
        verdict = j.get("verdict", {})
        v1 = verdict.get("SG1", {}).get(s, "-")
        v2 = verdict.get("SG2", {}).get(s, "-")
        real = j["err"].get("REAL", {}).get(s)
        yield (f"| {label} | {j['outages']['count']} | {s} | {a['mean']:.4g} [{a['p05']:.4g}, {a['p95']:.4g}] | "
               f"{b['mean']:.4g} [{b['p05']:.4g}, {b['p95']:.4g}] | {100 * gap:.0f} % | {100 * width:.0f} % | "
               f"{'yes' if apart else 'no'} | {real:.4g} | {v1} / {v2} |" if real is not None else
               f"| {label} | {j['outages']['count']} | {s} | {a['mean']:.4g} | {b['mean']:.4g} | {100 * gap:.0f} % | "
               f"{100 * width:.0f} % | {'yes' if apart else 'no'} | - | - |")


def main(argv):
    if not argv or any("=" not in a for a in argv):
        sys.exit(__doc__)
    print("| run | outages | statistic | ERR_1 [p05, p95] | ERR_2 [p05, p95] | mean gap | SG#2 interval width | apart | ERR_REAL | verdict SG#1 / SG#2 |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for arg in argv:
        label, out_dir = arg.split("=", 1)
        for r in rows(label, out_dir):
            print(r)


if __name__ == "__main__":
    main(sys.argv[1:])
