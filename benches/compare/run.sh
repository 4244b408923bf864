#!/usr/bin/env bash
# Reproduces results/benchmark.md, results/time_vs_error.csv and results/time_vs_error.png:
# builds dcol with the top-level CMake and installs it into build/bench-prefix, builds this
# benchmark against it (FCL 0.7 and libccd 2.1 from the system: libfcl-dev libccd-dev), runs it
# and makes the plot (matplotlib).
#
#   benches/compare/run.sh            # full run (DCOL_BENCH_CASES=1500 per pair type), a few minutes
#   benches/compare/run.sh --smoke    # 6 cases per pair type, results to build/bench-smoke/, no plot
#                                     # unless matplotlib is importable; < 60 s after the build
# Environment: DCOL_BENCH_CASES, DCOL_BENCH_REPEAT, DCOL_BENCH_SEED (see bench_compare.cpp), and
# DCOL_TARGET_CPU (e.g. x86-64-v3: dcol compiled for that CPU level, see the README; FCL and
# libccd stay the system's builds).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
smoke=0
[[ "${1:-}" == "--smoke" ]] && smoke=1
jobs="${DCOL_BENCH_JOBS:-2}"
prefix="$root/build/bench-prefix"

cpu="${DCOL_TARGET_CPU:-}"
# A CPU level has its own cargo target directory (other flags: a full rebuild each time it flips).
cmake -S . -B build/bench-dcol -DCMAKE_BUILD_TYPE=Release -DDCOL_TARGET_CPU="$cpu" \
  -DDCOL_CARGO_TARGET_DIR="$root/build/cargo-target${cpu:+-$cpu}" >/dev/null
cmake --build build/bench-dcol -j"$jobs" >/dev/null
cmake --install build/bench-dcol --prefix "$prefix" >/dev/null
cmake -S benches/compare -B build/bench-compare -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build build/bench-compare -j"$jobs" >/dev/null

if [[ $smoke == 1 ]]; then
  out="$root/build/bench-smoke"
  mkdir -p "$out"
  DCOL_BENCH_CASES="${DCOL_BENCH_CASES:-6}" DCOL_BENCH_OUT="$out" build/bench-compare/bench_compare 2>/dev/null
  test -s "$out/benchmark.md" && test -s "$out/time_vs_error.csv"
  if python3 -c "import matplotlib" 2>/dev/null; then python3 benches/compare/plot.py "$out"; fi
  echo "smoke OK"
else
  mkdir -p results
  DCOL_BENCH_OUT="$root/results" build/bench-compare/bench_compare
  python3 benches/compare/plot.py results
fi
