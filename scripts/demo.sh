#!/usr/bin/env bash
# Builds dcol, installs it into build/install, and runs the C quickstart (examples/quickstart.c)
# built against the installed library with pkg-config.
#
#   ./scripts/demo.sh
set -euo pipefail
cd "$(dirname "$0")/.."

prefix=$PWD/build/install
cmake -S . -B build/cmake-demo -DCMAKE_BUILD_TYPE=Release -DDCOL_BUILD_TESTS=OFF \
  -DDCOL_BUILD_EXAMPLES=OFF -DDCOL_CARGO_TARGET_DIR="$PWD/build/cargo-target"
cmake --build build/cmake-demo -j "${JOBS:-2}"
cmake --install build/cmake-demo --prefix "$prefix"

export PKG_CONFIG_PATH=$prefix/lib/pkgconfig${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}
# shellcheck disable=SC2046  # word splitting of the flags is intended
cc -std=c99 -Wall -Wextra -pedantic examples/quickstart.c -o build/quickstart \
  $(pkg-config --cflags --libs dcol) -Wl,-rpath,"$prefix/lib"
echo "== build/quickstart (against $prefix)"
./build/quickstart
