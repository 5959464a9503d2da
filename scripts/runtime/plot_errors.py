#!/usr/bin/env python3
"""Error plots of a `graftnav navigate` run (seed Figs. 7-12 style), outages shaded.

Usage: plot_errors.py OUT_DIR
Reads OUT_DIR/errors.csv (written by graftnav navigate) and writes
OUT_DIR/errors_position.png, errors_velocity.png, errors_attitude.png.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    cols = {k: [] for k in rows[0].keys()} if rows else {}
    for r in rows:
        for k, v in r.items():
            try:
                cols[k].append(float(v))
            except ValueError:
                cols[k].append(float("nan"))
    return cols


def outage_spans(t, outage):
    spans, start, cur = [], None, -1
    for ti, o in zip(t, outage):
        if o >= 0 and start is None:
            start, cur = ti, o
        elif start is not None and (o < 0 or o != cur):
            spans.append((start, prev))
            start = ti if o >= 0 else None
            cur = o
        prev = ti
    if start is not None:
        spans.append((start, prev))
    return spans


def figure(c, t, spans, keys, labels, unit, title, path):
    fig, axes = plt.subplots(len(keys), 1, sharex=True, figsize=(10, 2.4 * len(keys)))
    for ax, k, lab in zip(axes, keys, labels):
        for a, b in spans:
            ax.axvspan(a, b, color="c", alpha=0.25, lw=0)
        ax.plot(t, c[k], lw=0.8, color="k")
        ax.set_ylabel(f"{lab} ({unit})")
        ax.grid(True, lw=0.3)
    axes[-1].set_xlabel("time since start (s)")
    axes[0].set_title(title + ("  (cyan: GNSS outages)" if spans else ""))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    c = read(os.path.join(out, "errors.csv"))
    if not c or not c["t_s"]:
        sys.exit("errors.csv is empty")
    t0 = c["t_s"][0]
    t = [x - t0 for x in c["t_s"]]
    spans = [(a - t0, b - t0) for a, b in outage_spans(c["t_s"], c["outage"])]
    figure(c, t, spans, ["north_m", "east_m", "down_m"], ["north", "east", "down"], "m",
           "Position error", os.path.join(out, "errors_position.png"))
    figure(c, t, spans, ["vn_m_s", "ve_m_s", "vd_m_s"], ["north", "east", "down"], "m/s",
           "Velocity error", os.path.join(out, "errors_velocity.png"))
    figure(c, t, spans, ["roll_deg", "pitch_deg", "heading_deg"], ["roll", "pitch", "heading"],
           "deg", "Attitude error", os.path.join(out, "errors_attitude.png"))


if __name__ == "__main__":
    main()
