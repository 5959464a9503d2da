# Sourced by the real-data experiment scripts: sets ROOT, CASE (from REAL_CASE_NAME), OUT (from
# the first argument or DEFAULT_OUT), GN (the graftnav to run; built when missing) and PY.
# Environment: GRAFTNAV (path to graftnav), GRAFTNAV_REAL_DATA (folder of the real cases).
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
DATA="${GRAFTNAV_REAL_DATA:-$ROOT/../shared/data/real}"
CASE="$DATA/$REAL_CASE_NAME"
OUT="${1:-$DEFAULT_OUT}"
GN="${GRAFTNAV:-$ROOT/build/graftnav}"
PY=/usr/bin/python3; [ -x "$PY" ] || PY=python3
if [ ! -d "$CASE" ]; then echo "$(basename "$0"): $CASE not found (set GRAFTNAV_REAL_DATA)" >&2; exit 2; fi
if [ ! -x "$GN" ]; then
  cmake -S "$ROOT" -B "$ROOT/build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$ROOT/build" -j2 --target graftnav
  GN="$ROOT/build/graftnav"
fi
mkdir -p "$OUT"
