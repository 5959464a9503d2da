#!/usr/bin/env bash
# Install and package checks, run by CTest (tests/CMakeLists.txt):
#   check_install.sh consumer BUILD_DIR SOURCE_DIR WORK_DIR
#     `cmake --install` into WORK_DIR/prefix, then examples/consumer configured with
#     find_package(graftnav) against that prefix, built and run.
#   check_install.sh deb BUILD_DIR SOURCE_DIR WORK_DIR
#     `cpack -G DEB`, its file list (dpkg-deb -c) must hold the command, the libraries, the
#     headers and the CMake package; the packaged `graftnav --version` must run and name a commit.
set -euo pipefail
mode=$1 build=$2 src=$3 work=$4
rm -rf "$work" && mkdir -p "$work"
cmake --build "$build" --target graftnav > "$work/build.log"

case "$mode" in
  consumer)
    cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
    cmake -S "$src/examples/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_BUILD_TYPE=Release > "$work/consumer_configure.log"
    cmake --build "$work/consumer" > "$work/consumer_build.log"
    "$work/consumer/graftnav_consumer"
    "$work/prefix/bin/graftnav" --version
    ;;
  deb)
    (cd "$build" && cpack -G DEB -B "$work/package" > "$work/cpack.log")
    deb=$(ls "$work"/package/graftnav_*.deb)
    dpkg-deb -c "$deb" > "$work/contents.txt"
    for f in ./usr/bin/graftnav ./usr/lib/libgraftnav_nav.a ./usr/lib/libgraftnav_filters.a \
             ./usr/lib/libgraftnav_graph.a ./usr/include/graftnav/nav/rotation.h \
             ./usr/include/graftnav/io/peer_import.h ./usr/lib/cmake/graftnav/graftnavConfig.cmake \
             ./usr/lib/cmake/graftnav/graftnavTargets.cmake ./usr/share/doc/graftnav/cli.md; do
      grep -q " $f\$" "$work/contents.txt" || { echo "missing from $deb: $f" >&2; exit 1; }
    done
    dpkg-deb -f "$deb" Depends | grep -q libyaml-cpp || { echo "Depends lacks libyaml-cpp" >&2; exit 1; }
    dpkg-deb -x "$deb" "$work/root"
    "$work/root/usr/bin/graftnav" --version | grep -Eq '^graftnav [0-9.]+ \(commit [0-9a-f]{12}'
    "$work/root/usr/bin/graftnav" --version
    ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
