#!/usr/bin/env bash
# Install and package checks, run by CTest (tests/CMakeLists.txt):
#   check_install.sh consumer BUILD_DIR SOURCE_DIR WORK_DIR
#     `cmake --install` into WORK_DIR/prefix, then examples/consumer configured with
#     find_package(graftnav) against that prefix, built and run; the installed `graftnav navigate`
#     with plots must write its PNGs.
#   check_install.sh deb BUILD_DIR SOURCE_DIR WORK_DIR
#     `cpack -G DEB`, its file list (dpkg-deb -c) must hold the command, the libraries, the
#     headers, the plot scripts and the CMake package, and it must depend on or recommend
#     python3-matplotlib; the packaged `graftnav --version` must run and name a commit, and the
#     packaged `graftnav navigate` with plots must write its PNGs.
set -euo pipefail
mode=$1 build=$2 src=$3 work=$4
rm -rf "$work" && mkdir -p "$work"
cmake --build "$build" --target graftnav > "$work/build.log"

# navigate_with_plots BIN: the bundled tactical sample navigated by BIN with plots, from a folder
# outside the source and build trees and without GRAFTNAV_SCRIPTS_DIR, so the plot scripts must
# come from where BIN is installed. Fails unless every error plot is written and nothing warns.
navigate_with_plots() {
  local bin=$1 out="$work/navigate"
  (cd "$work" && env -u GRAFTNAV_SCRIPTS_DIR "$bin" navigate "$src/data/sample_tactical" \
      --out "$out" --estimator ekf > "$work/navigate.log" 2>&1) ||
    { cat "$work/navigate.log" >&2; exit 1; }
  if grep -q "warning: plot\|warning: python3" "$work/navigate.log"; then
    cat "$work/navigate.log" >&2; exit 1
  fi
  for png in errors_position.png errors_velocity.png errors_attitude.png; do
    [ -s "$out/$png" ] || { echo "$bin navigate wrote no $png" >&2; cat "$work/navigate.log" >&2; exit 1; }
  done
  echo "installed navigate wrote $(ls "$out"/*.png | wc -l) plots in $out"
}

case "$mode" in
  consumer)
    cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
    cmake -S "$src/examples/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_BUILD_TYPE=Release > "$work/consumer_configure.log"
    cmake --build "$work/consumer" > "$work/consumer_build.log"
    "$work/consumer/graftnav_consumer"
    "$work/prefix/bin/graftnav" --version
    [ -f "$work/prefix/share/graftnav/scripts/plot_errors.py" ] ||
      { echo "plot scripts not installed under share/graftnav/scripts" >&2; exit 1; }
    navigate_with_plots "$work/prefix/bin/graftnav"
    ;;
  deb)
    (cd "$build" && cpack -G DEB -B "$work/package" > "$work/cpack.log")
    deb=$(ls "$work"/package/graftnav_*.deb)
    dpkg-deb -c "$deb" > "$work/contents.txt"
    for f in ./usr/bin/graftnav ./usr/lib/libgraftnav_nav.a ./usr/lib/libgraftnav_filters.a \
             ./usr/lib/libgraftnav_graph.a ./usr/include/graftnav/nav/rotation.h \
             ./usr/include/graftnav/io/peer_import.h ./usr/lib/cmake/graftnav/graftnavConfig.cmake \
             ./usr/lib/cmake/graftnav/graftnavTargets.cmake ./usr/share/doc/graftnav/cli.md \
             ./usr/share/graftnav/scripts/plot_errors.py ./usr/share/graftnav/scripts/plot_sg.py; do
      grep -q " $f\$" "$work/contents.txt" || { echo "missing from $deb: $f" >&2; exit 1; }
    done
    dpkg-deb -f "$deb" Depends | grep -q libyaml-cpp || { echo "Depends lacks libyaml-cpp" >&2; exit 1; }
    dpkg-deb -f "$deb" Depends Recommends | grep -q python3-matplotlib ||
      { echo "the package neither depends on nor recommends python3-matplotlib" >&2; exit 1; }
    dpkg-deb -x "$deb" "$work/root"
    "$work/root/usr/bin/graftnav" --version | grep -Eq '^graftnav [0-9.]+ \(commit [0-9a-f]{12}'
    "$work/root/usr/bin/graftnav" --version
    navigate_with_plots "$work/root/usr/bin/graftnav"
    if [ -f "$build/python/graftnav/__init__.py" ]; then  # built with the Python module
      site=$(grep -o ' \./usr/lib/python3/dist-packages/graftnav/_graftnav[^ ]*\.so$' "$work/contents.txt" || true)
      [ -n "$site" ] || { echo "the Python module is missing from $deb" >&2; exit 1; }
      PYTHONPATH="$work/root/usr/lib/python3/dist-packages" /usr/bin/python3 -c \
        "import graftnav; c = graftnav.load_case('$src/data/sample_mems'); print(c, len(c.imu()))"
    fi
    ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
