#!/usr/bin/env bash
# Builds dcol (Release) with the top-level CMake, installs it into build/bench-prefix, builds the
# ODE benchmark against the installed package and runs it: whole-step time and narrow-phase time
# per dCollide call, ODE's own colliders against dcol's, on the pyramid and the pile, in one run.
#
#   benches/engines/ode/run.sh            # full run (3 rounds), about two minutes
#   benches/engines/ode/run.sh --smoke    # a few steps, to check that it builds and runs
# Environment: DCOL_BENCH_ROUNDS (default 3), DCOL_BENCH_JOBS (default 2).
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
cd "$root"
jobs="${DCOL_BENCH_JOBS:-2}"
prefix="$root/build/bench-prefix"
cmake -S . -B build/bench-dcol -DCMAKE_BUILD_TYPE=Release -DDCOL_CARGO_TARGET_DIR="$root/build/cargo-target" >/dev/null
cmake --build build/bench-dcol -j"$jobs" >/dev/null
cmake --install build/bench-dcol --prefix "$prefix" >/dev/null
cmake -S benches/engines/ode -B build/bench-ode -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build build/bench-ode -j"$jobs" >/dev/null
build/bench-ode/bench_ode "$@"
