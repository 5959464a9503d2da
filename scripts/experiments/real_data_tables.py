#!/usr/bin/env python3
"""Writes the result tables of docs/real-data.md from the current code: runs the graftnav binary
on the real recordings and copies the tables it writes (timing columns dropped, so a rerun of the
same code gives the same file) into

  docs/results/real_yandld.md    `graftnav real` (EKF, RTS, FGO; outage errors at the RTK check
                                 points, GNSS latency scan and correction) and `graftnav compare`
                                 on yandld_20220405_rtk;
  docs/results/real_wid_car.md   `graftnav real-sg` (RTS and EKF) on wid_car_trial07.

The mismatch finder's tables of the same recordings are scripts/experiments/real_diagnose_tables.py's.

Usage: scripts/experiments/real_data_tables.py [--data DIR] [--binary build/graftnav] [--out-dir DIR]
                                   [--work DIR]
  --data     the real-data folder (default: $GRAFTNAV_REAL_DATA or ../shared/data/real)
  --out-dir  where the Markdown files go (default docs/results)
  --work     where the runs write (default /tmp/graftnav_real_data)
Runtime: about 25 s of CPU (2.5 min wall on the shared 2-core machine at load ~13, 2026-11-26);
the batch factor graph on yandld is most of it.
"""
import argparse
import os
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DROP_COLUMNS = {"run (s)"}  # wall-clock timings differ from run to run


def drop_columns(markdown):
    """Removes the DROP_COLUMNS columns from every Markdown table in the text."""
    out, drop = [], []
    for line in markdown.splitlines():
        if not line.startswith("|"):
            drop = []
            out.append(line)
            continue
        cells = line.strip().strip("|").split("|")
        if not drop:
            drop = [i for i, c in enumerate(cells) if c.strip() in DROP_COLUMNS] or [-1]
        kept = [c for i, c in enumerate(cells) if i not in drop]
        out.append("|" + "|".join(kept) + "|")
    return "\n".join(out) + "\n"


def run(binary, args, log):
    """Runs graftnav with args (paths as given), its output into log; exits naming the log."""
    shown = "graftnav " + " ".join(args)
    with open(log, "w") as f:
        r = subprocess.run([binary] + args, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit(f"real_data_tables: `{shown}` failed (exit {r.returncode}); see {log}")
    return shown


def read(path):
    with open(path) as f:
        return f.read()


def git_commit():
    r = subprocess.run(["git", "-C", REPO, "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
    return r.stdout.strip() or "unknown"


def header(title, commit):
    return (f"# {title}\n\nWritten by `scripts/experiments/real_data_tables.py` from the code at commit {commit}; "
            "do not edit by hand (rerun the script). Commands are relative to the repository, the "
            "data folder written as `DATA`.\n\n")


def yandld(binary, data, work, commit):
    case = os.path.join(data, "yandld_20220405_rtk")
    common = ["--run-config", "configs/real/yandld.yaml", "--imu", "tested", "--profile",
              "configs/real/yandld_mems.yaml", "--estimator", "ekf,rts,fgo"]
    real_out = os.path.join(work, "yandld_real")
    cmp_out = os.path.join(work, "yandld_compare")
    real_cmd = run(binary, ["real", case, "--out", real_out] + common +
                   ["--latency-scan", "--latency-grid", "0,0.2,0.4,0.6", "--latency-types", "4,5",
                    "--no-plots"], os.path.join(work, "yandld_real.log"))
    cmp_cmd = run(binary, ["compare", case, "--out", cmp_out, "--lenient"] + common + ["--no-plots"],
                  os.path.join(work, "yandld_compare.log"))
    show = lambda c: c.replace(data, "DATA").replace(work, "OUT")
    md = header("Real data: yandld_20220405_rtk", commit)
    md += f"## Outage errors at the RTK check points, latency scan and correction\n\n`{show(real_cmd)}`\n\n"
    md += drop_columns(read(os.path.join(real_out, "summary.md"))) + "\n"
    compare = read(os.path.join(cmp_out, "compare.md"))
    compare = compare.split("\n", 1)[1] if compare.startswith("# ") else compare  # our own title
    md += f"## Errors against reference.nav (`graftnav compare`)\n\n`{show(cmp_cmd)}`\n\n"
    md += drop_columns(compare.replace("\n## ", "\n### "))
    return md


def wid_car(binary, data, work, commit):
    case = os.path.join(data, "wid_car_trial07")
    md = header("Real data: wid_car_trial07, real-data SG#1", commit)
    for est in ("rts", "ekf"):
        out = os.path.join(work, f"wid_sg_{est}")
        cmd = run(binary, ["real-sg", case, "--out", out, "--estimator", est, "--run-config",
                           "configs/real/wid_car.yaml", "--ref-profile", "configs/real/wid_mrup.yaml",
                           "--tested-profile", "configs/real/wid_dot.yaml", "--static-gyro-threshold",
                           "0.02", "--static-accel-threshold", "0.65", "--no-plots"],
                  os.path.join(work, f"wid_sg_{est}.log"))
        md += f"## {est.upper()}\n\n`{cmd.replace(data, 'DATA').replace(work, 'OUT')}`\n\n"
        tables = read(os.path.join(out, "tables.md"))
        tables = tables.split("\n", 1)[1] if tables.startswith("# ") else tables  # our own title
        md += drop_columns(tables.replace("\n## ", "\n### ")) + "\n"
    return md


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", default=os.environ.get("GRAFTNAV_REAL_DATA",
                                                     os.path.join(REPO, "..", "shared", "data", "real")))
    ap.add_argument("--binary", default=os.path.join(REPO, "build", "graftnav"))
    ap.add_argument("--out-dir", default=os.path.join(REPO, "docs", "results"))
    ap.add_argument("--work", default="/tmp/graftnav_real_data")
    a = ap.parse_args()
    data = os.path.realpath(a.data)
    if not os.path.isdir(data):
        sys.exit(f"real_data_tables: {data}: no real-data folder (set --data or GRAFTNAV_REAL_DATA)")
    os.makedirs(a.work, exist_ok=True)
    os.makedirs(a.out_dir, exist_ok=True)
    os.chdir(REPO)  # the run configs and profiles are named relative to the repository
    commit = git_commit()
    t0 = time.time()
    for name, fn in (("real_yandld.md", yandld), ("real_wid_car.md", wid_car)):
        text = fn(os.path.realpath(a.binary), data, os.path.realpath(a.work), commit)
        text = text.replace(data, "DATA")  # the outputs name the case folder
        with open(os.path.join(a.out_dir, name), "w") as f:
            f.write(text.rstrip("\n") + "\n")
        print(f"wrote {os.path.join(a.out_dir, name)}")
    print(f"real_data_tables: {time.time() - t0:.0f} s")


if __name__ == "__main__":
    main()
