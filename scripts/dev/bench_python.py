#!/usr/bin/env python3
"""Benchmark of the Python module (docs/BENCHMARKS.md, "Python module"): the cost of navigate
from Python against the `graftnav navigate` command on the same case, and two navigate calls on
two threads against one (the GIL is released while C++ runs). Prints the table rows.

    PYTHONPATH=build/python nice -n 10 /usr/bin/python3 scripts/dev/bench_python.py \\
        CASE_DIR OUT_DIR [--estimator ekf] [--imu tested]
"""
import argparse
import os
import resource
import subprocess
import threading
import time

import graftnav


def cpu_s(who=resource.RUSAGE_SELF):
    r = resource.getrusage(who)
    return r.ru_utime + r.ru_stime


def cli_run(binary, case, out, estimator, imu):
    """`graftnav navigate` as a child: its CPU (user + system) and wall time."""
    before = cpu_s(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    subprocess.run([binary, "navigate", case, "--out", out, "--estimator", estimator, "--imu", imu,
                    "--no-plots"], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return cpu_s(resource.RUSAGE_CHILDREN) - before, time.monotonic() - t0


def py_run(case, estimator, imu):
    before, t0 = cpu_s(), time.monotonic()
    r = graftnav.navigate(case, estimator, imu=imu, output_rate_hz=1.0)
    return cpu_s() - before, time.monotonic() - t0, r


def two_threads(case, estimator, imu):
    walls = [0.0, 0.0]

    def work(k):
        t0 = time.monotonic()
        graftnav.navigate(case, estimator, imu=imu, output_rate_hz=1.0)
        walls[k] = time.monotonic() - t0

    cpu0, t0 = cpu_s(), time.monotonic()
    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return cpu_s() - cpu0, time.monotonic() - t0


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("case")
    p.add_argument("out")
    p.add_argument("--estimator", default="ekf")
    p.add_argument("--imu", default="tested")
    p.add_argument("--binary", default=os.path.join(os.path.dirname(__file__), "..", "..",
                                                    "build", "graftnav"))
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    cli_cpu, cli_wall = cli_run(a.binary, a.case, os.path.join(a.out, "cli"), a.estimator, a.imu)
    t0 = time.monotonic()
    case = graftnav.load_case(a.case)
    case.imu(a.imu)  # loading excluded from the navigate timings
    load_wall = time.monotonic() - t0
    py_cpu, py_wall, r = py_run(case, a.estimator, a.imu)
    pair_cpu, pair_wall = two_threads(case, a.estimator, a.imu)
    n = len(case.imu(a.imu))
    print(f"case {a.case}: {n} IMU samples, estimator {a.estimator}, IMU {a.imu}; "
          f"load_case + imu: {load_wall:.1f} s wall")
    print("| run | CPU (s) | wall (s) | ratio |")
    print("|---|---|---|---|")
    print(f"| `graftnav navigate` (reads the case, writes its files) | {cli_cpu:.1f} | {cli_wall:.1f} | 1 |")
    print(f"| `graftnav.navigate` (case loaded before, no files) | {py_cpu:.1f} | {py_wall:.1f} | "
          f"CPU {py_cpu / cli_cpu:.2f} of the command's |")
    # CPU / wall above 1: both threads ran C++ at once (the GIL released).
    print(f"| two `graftnav.navigate` on two threads | {pair_cpu:.1f} | {pair_wall:.1f} | "
          f"wall {pair_wall / py_wall:.2f} of one call; CPU/wall {pair_cpu / pair_wall:.2f} |")
    print(f"load average during the run: {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"statistics equal the command's errors.json: overall horizontal RMS "
          f"{r.statistics['overall']['horizontal_rms_m']:.4f} m")


if __name__ == "__main__":
    main()
