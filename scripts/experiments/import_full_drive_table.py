#!/usr/bin/env python3
"""OUT/table.md of import_full_drive.sh: the hand-made EKF set-up against the imported KF-GINS
set-up (errors.json and run_info.json of both navigate runs).

Usage: import_full_drive_table.py OUT
"""
import json, sys
out = sys.argv[1]
rows = []
for name in ("hand", "imported"):
    j = json.load(open(f"{out}/{name}/errors.json"))
    info = json.load(open(f"{out}/{name}/run_info.json"))
    rows.append((name, j["outages"]["count"], j["outage"]["horizontal_m"], j["outage_max"]["horizontal_m"],
                 j["outage"]["heading_deg"], info["gnss"]["used"]))
h = rows[0][2]
lines = ["| set-up | outages | outage RMS horizontal (m) | RMS of per-outage max horizontal (m) | outage RMS heading (deg) | GNSS used | vs hand |",
         "|---|---|---|---|---|---|---|"]
for r in rows:
    lines.append(f"| {r[0]} | {r[1]} | {r[2]:.3f} | {r[3]:.3f} | {r[4]:.4f} | {r[5]} | {100 * (r[2] / h - 1):+.2f} % |")
open(f"{out}/table.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
