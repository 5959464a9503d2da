#!/usr/bin/env python3
"""How does the outage error change with the GNSS noise floor, per estimator?

Navigates the tested IMU of each bundled sample (data/sample_mems, data/sample_tactical) with
ekf, rts, fgo and fgo-window through the outages of configs/navigate.yaml, at three values of
the run config's GNSS noise floors (ekf.gnss_std_floor_m for ekf and rts, fgo.gnss_min_std_m for
the factor graphs), two navigations at a time on threads (graftnav releases the GIL). Prints one
table and writes estimator_study.png.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/estimator_study.py [--out DIR]
"""
import argparse
import os
import time
from concurrent.futures import ThreadPoolExecutor

import graftnav

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SAMPLES = ("sample_mems", "sample_tactical")
ESTIMATORS = ("ekf", "rts", "fgo", "fgo-window")
FLOORS_M = (0.005, 0.05, 0.5)  # GNSS 1-sigma floors: RTK-fixed, RTK-float, code-level
RUN_CONFIG = os.path.join(ROOT, "configs", "navigate.yaml")


def floor_options(floor_m):
    """The same noise floor for both estimator families."""
    return {"ekf": {"gnss_std_floor_m": floor_m}, "fgo": {"gnss_min_std_m": floor_m}}


def run(case, estimator, floor_m):
    r = graftnav.navigate(case, estimator, run_config=RUN_CONFIG, imu="tested",
                          options=floor_options(floor_m), output_rate_hz=1.0)
    return r.statistics


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(SAMPLES), figsize=(11, 4), sharey=False)
    for ax, sample in zip(axes, SAMPLES):
        for estimator in ESTIMATORS:
            ys = [rows[(sample, estimator, f)]["outage"]["horizontal_m"] for f in FLOORS_M]
            ax.plot(FLOORS_M, ys, marker="o", label=estimator)
        ax.set_xscale("log")
        ax.set_xlabel("GNSS noise floor (m, 1-sigma)")
        ax.set_ylabel("horizontal RMS inside outages (m)")
        ax.set_title(sample.replace("sample_", "") + " tested IMU, 60 s outages")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=".", help="folder for estimator_study.png")
    parser.add_argument("--threads", type=int, default=2, help="navigations at a time")
    args = parser.parse_args()
    cases = {s: graftnav.load_case(os.path.join(ROOT, "data", s)) for s in SAMPLES}
    jobs = [(s, e, f) for s in SAMPLES for e in ESTIMATORS for f in FLOORS_M]
    t0 = time.monotonic()
    with ThreadPoolExecutor(args.threads) as pool:
        stats = pool.map(lambda j: run(cases[j[0]], j[1], j[2]), jobs)
        rows = dict(zip(jobs, stats))
    wall = time.monotonic() - t0
    print("| case | estimator | floor (m) | outage horizontal RMS (m) | outage vertical RMS (m) "
          "| outage heading RMS (deg) | overall horizontal RMS (m) |")
    print("|---|---|---|---|---|---|---|")
    for (s, e, f), st in rows.items():
        o = st["outage"]
        print(f"| {s.replace('sample_', '')} | {e} | {f:g} | {o['horizontal_m']:.3f} | "
              f"{o['vertical_m']:.3f} | {o['heading_deg']:.4f} | "
              f"{st['overall']['horizontal_rms_m']:.3f} |")
    print(f"\n{len(jobs)} navigations in {wall:.0f} s wall on {args.threads} threads")
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "estimator_study.png")
    plot(rows, path)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
