#!/usr/bin/env python3
"""Compare the JSON results of two runs of graftnav, number by number.

Usage: scripts/dev/compare_outputs.py DIR_A DIR_B [--rtol 1e-12]

Every *.json under DIR_A is matched by relative path under DIR_B. Numbers agree when
|a - b| <= rtol * max(|a|, |b|) (or both are NaN/absent alike); strings, booleans and keys must
match exactly, except the keys that name where a run happened (paths, timestamps, the command
line, the version), which are ignored. Prints one line per difference and exits 1 if any.
"""
import argparse, json, math, os, sys

IGNORED_KEYS = {"out_dir", "case_dir", "command_line", "git_commit", "version", "started_utc",
                "finished_utc", "wall_s", "run_time_s", "imu_file", "path", "run_info"}


def walk(a, b, where, rtol, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k in IGNORED_KEYS:
                continue
            if k not in a or k not in b:
                out.append(f"{where}.{k}: only in {'A' if k in a else 'B'}")
                continue
            walk(a[k], b[k], f"{where}.{k}", rtol, out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{where}: length {len(a)} vs {len(b)}")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{where}[{i}]", rtol, out)
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        fa, fb = float(a), float(b)
        if math.isnan(fa) and math.isnan(fb):
            return
        if abs(fa - fb) > rtol * max(abs(fa), abs(fb)):
            out.append(f"{where}: {a!r} vs {b!r}")
    elif a != b:
        out.append(f"{where}: {a!r} vs {b!r}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir_a")
    ap.add_argument("dir_b")
    ap.add_argument("--rtol", type=float, default=1e-12)
    args = ap.parse_args()
    diffs, n = [], 0
    for root, _, files in os.walk(args.dir_a):
        for f in sorted(files):
            if not f.endswith(".json"):
                continue
            rel = os.path.relpath(os.path.join(root, f), args.dir_a)
            pb = os.path.join(args.dir_b, rel)
            if not os.path.exists(pb):
                diffs.append(f"{rel}: missing in B")
                continue
            n += 1
            with open(os.path.join(args.dir_a, rel)) as fa, open(pb) as fb:
                out = []
                walk(json.load(fa), json.load(fb), rel, args.rtol, out)
                diffs.extend(out)
    for d in diffs:
        print(d)
    print(f"compared {n} JSON files: {len(diffs)} difference(s) beyond rtol {args.rtol:g}")
    return 1 if diffs or n == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
