#!/usr/bin/env bash
# Builds dcol with the top-level CMake (Release), installs it into build/bench-prefix, builds
# bench_bullet against the installed dcol::bullet and runs it: the table of whole-step and
# narrow-phase times, native against dcol, on the pile and the pyramid (bench_bullet.cpp).
#
#   benches/engines/bullet/run.sh [bench_bullet options]   # default: 3 runs of 5 s each, ~2 minutes
#   benches/engines/bullet/run.sh --smoke                  # one short run (the test suite's)
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
cd "$root"
jobs="${DCOL_BENCH_JOBS:-2}"
prefix="$root/build/bench-prefix"
cmake -S . -B build/bench-dcol -DCMAKE_BUILD_TYPE=Release -DDCOL_CARGO_TARGET_DIR="$root/build/cargo-target" >/dev/null
cmake --build build/bench-dcol -j"$jobs" >/dev/null
cmake --install build/bench-dcol --prefix "$prefix" >/dev/null
cmake -S benches/engines/bullet -B build/bench-bullet -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build build/bench-bullet -j"$jobs" >/dev/null
build/bench-bullet/bench_bullet "$@"
