#!/usr/bin/env bash
# Regenerates the bundled samples data/sample_tactical and data/sample_mems with `graftnav
# simulate` (configs/sim/sample_*.yaml, fixed seed: the output is reproducible). The two cases
# share one simulated field test (same seed, track piece, reference IMU and GNSS): the MEMS case's
# field/ref_imu.txt, gnss.pos and truth.nav are stored once, as symbolic links to the tactical
# case's files, after checking that they are byte-identical.
# Usage: scripts/dev/make_sample.sh [path/to/graftnav]   (default ./build/graftnav)
# Needs the real track ../shared/data/tracks/wuhan_57min_rtk.pos (see configs/sim/sample_*.yaml).
set -euo pipefail
cd "$(dirname "$0")/../.."
BIN=${1:-./build/graftnav}

rm -rf data/sample_tactical data/sample_mems
"$BIN" simulate --sim-config configs/sim/sample_tactical.yaml --out data/sample_tactical
"$BIN" simulate --sim-config configs/sim/sample_mems.yaml --out data/sample_mems
for f in field/ref_imu.txt field/gnss.pos field/truth.nav; do
  if ! cmp -s "data/sample_tactical/$f" "data/sample_mems/$f"; then
    echo "make_sample: $f differs between the two cases; configs out of step" >&2
    exit 1
  fi
  ln -sf "../../sample_tactical/$f" "data/sample_mems/$f"
done
du -sh data/sample_tactical data/sample_mems
du -shL data/sample_mems
