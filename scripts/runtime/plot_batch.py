#!/usr/bin/env python3
"""Plots of the fleet reports of `graftnav batch` (run by the command after every local run,
--collect and --report). Usage: python3 plot_batch.py OUT_DIR
Reads OUT_DIR/report_estimators.csv, report_options.csv and report_crosscheck.csv and writes
  report_estimators.png  per group and configuration: the outage RMS horizontal error across the
                         cases (median, interquartile box, min-max whiskers), one panel per scope
  report_options.png     per swept option: that statistic against the option value, mean +- SD
                         over cases and seeds, min-max as a band
  report_crosscheck.png  per compare case and estimator pair: the largest |difference| / sigma of
                         the difference inside the outages, with the 3-sigma line
A plot whose CSV has no rows is not drawn (and an old one is removed)."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(s):
    return float(s) if s not in ("", None) else float("nan")


def finish(fig, path, drawn):
    if drawn:
        fig.tight_layout()
        fig.savefig(path, dpi=110)
    elif os.path.exists(path):
        os.remove(path)
    plt.close(fig)


def label_of(r):
    opts = "" if r["options"] == "{}" else " " + r["options"]
    sol = "" if r["solution"] == r["estimator"] else " " + r["solution"]
    return f"{r['group']}: {r['estimator']}{sol}{opts}"


def plot_estimators(out_dir):
    rows = [r for r in read_csv(os.path.join(out_dir, "report_estimators.csv"))
            if r["statistic"] == "horizontal_m" and r["measure"] == "rms" and int(r["n"]) > 0]
    scopes = sorted({r["scope"] for r in rows})
    fig, axes = plt.subplots(max(1, len(scopes)), 1, figsize=(11, 2.2 + 0.45 * len(rows)),
                             squeeze=False)
    for ax, scope in zip(axes[:, 0], scopes):
        sel = [r for r in rows if r["scope"] == scope]
        for i, r in enumerate(sel):
            lo, q1, med, q3, hi = (num(r[k]) for k in ("min", "p25", "median", "p75", "max"))
            ax.plot([lo, hi], [i, i], color="0.4", lw=1)
            ax.barh(i, q3 - q1, left=q1, height=0.5, color="tab:blue", alpha=0.5)
            ax.plot([med, med], [i - 0.25, i + 0.25], color="k", lw=2)
            ax.text(hi, i, f"  n={r['n']}", va="center", fontsize=7)
        ax.set_yticks(range(len(sel)))
        ax.set_yticklabels([label_of(r) for r in sel], fontsize=7)
        ax.invert_yaxis()
        # Estimators differ by orders of magnitude (a smoother's decimetres beside a filter's
        # metres): a log axis then, else a linear one from 0; room on the right for "n=".
        ends = [v for r in sel for v in (num(r["min"]), num(r["max"])) if v == v and v > 0]
        if ends and max(ends) / min(ends) > 20:
            ax.set_xscale("log")
            ax.set_xlim(min(ends) / 1.5, max(ends) * 2.5)
        elif ends:
            ax.set_xlim(0, max(ends) * 1.15)
        ax.set_xlabel(f"RMS horizontal error over the {scope} epochs across cases (m)")
        ax.grid(axis="x", alpha=0.3)
    axes[0, 0].set_title("Per estimator: median, interquartile range and min-max over the cases")
    finish(fig, os.path.join(out_dir, "report_estimators.png"), bool(rows))


def plot_options(out_dir):
    rows = [r for r in read_csv(os.path.join(out_dir, "report_options.csv"))
            if r["statistic"] == "horizontal_m" and r["measure"] == "rms" and int(r["n"]) > 0]
    panels = []
    for r in rows:
        key = (r["group"], r["option"], r["scope"])
        if key not in panels:
            panels.append(key)
    fig, axes = plt.subplots(max(1, len(panels)), 1, figsize=(8, 3.2 * max(1, len(panels))),
                             squeeze=False)
    for ax, (group, option, scope) in zip(axes[:, 0], panels):
        sel = [r for r in rows if (r["group"], r["option"], r["scope"]) == (group, option, scope)]
        lines = []
        for r in sel:
            if (r["estimator"], r["solution"]) not in lines:
                lines.append((r["estimator"], r["solution"]))
        for est, sol in lines:
            pts = [r for r in sel if (r["estimator"], r["solution"]) == (est, sol)]
            values = [r["value"] for r in pts]
            try:
                x = [float(v) for v in values]
            except ValueError:
                x = list(range(len(values)))
                ax.set_xticks(x)
                ax.set_xticklabels(values)
            mean = [num(r["mean"]) for r in pts]
            sd = [num(r["sd"]) for r in pts]
            ax.fill_between(x, [num(r["min"]) for r in pts], [num(r["max"]) for r in pts],
                            alpha=0.15)
            ax.errorbar(x, mean, yerr=sd, marker="o", capsize=3,
                        label=est if sol == est else f"{est} {sol}")
        ax.set_xlabel(option)
        ax.set_ylabel(f"{scope} RMS horizontal (m)")
        ax.set_title(f"{group}: mean +- SD over cases and seeds, band min-max")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    finish(fig, os.path.join(out_dir, "report_options.png"), bool(rows))


def plot_crosscheck(out_dir):
    rows = [r for r in read_csv(os.path.join(out_dir, "report_crosscheck.csv"))
            if r["max_normalized"] != ""]
    cases = []
    for r in rows:
        if (r["group"], r["case"]) not in cases:
            cases.append((r["group"], r["case"]))
    series = []
    for r in rows:
        key = (r["a"], r["b"], r["statistic"])
        if key not in series:
            series.append(key)
    fig, ax = plt.subplots(figsize=(max(6, 0.6 * len(cases) * max(1, len(series)) + 3), 4))
    width = 0.8 / max(1, len(series))
    for k, (a, b, stat) in enumerate(series):
        x, z = [], []
        for i, c in enumerate(cases):
            for r in rows:
                if (r["group"], r["case"], r["a"], r["b"], r["statistic"]) == (*c, a, b, stat):
                    x.append(i + (k - (len(series) - 1) / 2) * width)
                    z.append(num(r["max_normalized"]))
        ax.bar(x, z, width=width, label=f"{a} - {b} {stat.split('_')[0]}")
    ax.axhline(3.0, color="r", ls="--", lw=1, label="3 sigma")
    ax.set_xticks(range(len(cases)))
    ax.set_xticklabels([c[1] for c in cases], rotation=30, ha="right", fontsize=8)
    ax.set_ylabel("max |difference| / sigma in outages")
    ax.set_title("Fleet cross-check: estimator pairs inside the GNSS outages")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    finish(fig, os.path.join(out_dir, "report_crosscheck.png"), bool(rows))


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out_dir = sys.argv[1]
    plot_estimators(out_dir)
    plot_options(out_dir)
    plot_crosscheck(out_dir)


if __name__ == "__main__":
    main()
