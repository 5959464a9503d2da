#!/usr/bin/env python3
"""The bundled-samples table of docs/results/mismatch_concealed.md: what `graftnav diagnose` claims
on data/sample_mems and data/sample_tactical (nothing should be claimed).

Usage: mismatch_samples_table.py WORK   (reads WORK/sample_<grade>_diag/diagnosis.json)
"""
import json, math, os, sys
work = sys.argv[1]
print("| sample | claimed | ambiguous | unexplained spans | gyro residual RMS before -> after (deg/s) | accel residual RMS before -> after (m/s^2) |")
print("|---|---|---|---|---|---|")
for grade in ("mems", "tactical"):
    j = json.load(open(os.path.join(work, f"sample_{grade}_diag", "diagnosis.json")))
    fit = j["fit"]
    rb, ra = fit["signal_rms_before"], fit["signal_rms_after"]
    deg = lambda v: "/".join(f"{x * 180 / math.pi:.4g}" for x in v)
    si = lambda v: "/".join(f"{x:.4g}" for x in v)
    claimed = ", ".join(f"{e['name']}({e['sensor']})" for e in j["effects"]) or "none"
    ambiguous = ", ".join(f"{e['name']}({e['sensor']})" for e in j.get("ambiguous", [])) or "none"
    print(f"| sample_{grade} | {claimed} | {ambiguous} | {len(j.get('unexplained', []))} | "
          f"{deg(rb['gyro'])} -> {deg(ra['gyro'])} | {si(rb['accel'])} -> {si(ra['accel'])} |")
