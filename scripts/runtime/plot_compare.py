#!/usr/bin/env python3
"""Plot of `graftnav compare` output: horizontal, vertical and heading errors of every estimator
against time, outages shaded. Usage: python3 scripts/runtime/plot_compare.py OUT_DIR [--png FILE]
Reads OUT_DIR/compare_errors.csv and OUT_DIR/compare_outages.csv; writes OUT_DIR/compare.png."""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"plot_compare: {path} has no rows")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("out_dir")
    ap.add_argument("--png", default=None)
    a = ap.parse_args()
    rows = read_csv(os.path.join(a.out_dir, "compare_errors.csv"))
    outages = read_csv(os.path.join(a.out_dir, "compare_outages.csv")) if os.path.exists(
        os.path.join(a.out_dir, "compare_outages.csv")) else []
    t0 = float(rows[0]["t_s"])
    t = [float(r["t_s"]) - t0 for r in rows]
    names = [c[: -len("_horizontal_m")] for c in rows[0] if c.endswith("_horizontal_m")]
    quantities = [("horizontal_m", "horizontal error (m)"), ("vertical_m", "vertical error (m)"),
                  ("heading_deg", "heading error (deg)")]
    fig, axes = plt.subplots(len(quantities), 1, figsize=(11, 8), sharex=True)
    for ax, (key, label) in zip(axes, quantities):
        for w in outages:
            ax.axvspan(float(w["start_s"]) - t0, float(w["end_s"]) - t0, color="0.9", lw=0)
        for n in names:
            y = [abs(float(r[f"{n}_{key}"])) for r in rows]
            ax.plot(t, y, lw=0.8, label=n)
        ax.set_ylabel(label)
        ax.set_yscale("log")
        ax.grid(True, which="both", lw=0.3)
    axes[0].legend(loc="upper left", ncol=len(names), fontsize=8)
    axes[-1].set_xlabel("time since start (s); outages shaded")
    fig.suptitle(f"graftnav compare: {a.out_dir}")
    fig.tight_layout()
    png = a.png or os.path.join(a.out_dir, "compare.png")
    fig.savefig(png, dpi=120)
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
