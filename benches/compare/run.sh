#!/usr/bin/env bash
# Reproduces results/benchmark.md, results/time_vs_error.csv and results/time_vs_error.png:
# builds dcol with the top-level CMake and installs it into build/bench-prefix, fetches Coal 3
# (the libcoal wheel from PyPI and the cmeel wheels it links: boost, octomap, qhull, assimp;
# unpacked into build/coal, once), builds this benchmark against them (FCL 0.7 and libccd 2.1
# from the system: libfcl-dev libccd-dev; Eigen from the system: libeigen3-dev), runs it and
# makes the plot (matplotlib). When Coal cannot be fetched or found, the benchmark is built and
# run without it and says so ("Coal: not available (reason)").
#
#   benches/compare/run.sh            # full run (DCOL_BENCH_CASES=1500 per pair type), a few minutes
#   benches/compare/run.sh --smoke    # 6 cases per pair type, results to build/bench-smoke/, no plot
#                                     # unless matplotlib is importable; < 60 s after the build
#   benches/compare/run.sh --trajectory   # only bench_trajectory (warm against cold, dcol against
#                                     # Coal): results/trajectory.md and results/trajectory.csv
# Environment: DCOL_BENCH_CASES, DCOL_BENCH_REPEAT, DCOL_BENCH_SEED (see bench_compare.cpp),
# DCOL_BENCH_CPU=n (bench_trajectory pins itself to core n),
# DCOL_BENCH_RAW=file (every sample's time as CSV, for what-if questions about the medians),
# DCOL_BENCH_COAL=0 (leave Coal out), DCOL_BENCH_COAL_PREFIX (use a Coal install prefix instead of
# the wheels), and
# DCOL_TARGET_CPU (e.g. x86-64-v3: dcol compiled for that CPU level, see the README; FCL and
# libccd stay the system's builds).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$root"
smoke=0
trajectory=0
[[ "${1:-}" == "--smoke" ]] && smoke=1
[[ "${1:-}" == "--trajectory" ]] && trajectory=1
jobs="${DCOL_BENCH_JOBS:-2}"
prefix="$root/build/bench-prefix"

cpu="${DCOL_TARGET_CPU:-}"
# A CPU level has its own cargo target directory (other flags: a full rebuild each time it flips).
cmake -S . -B build/bench-dcol -DCMAKE_BUILD_TYPE=Release -DDCOL_TARGET_CPU="$cpu" \
  -DDCOL_CARGO_TARGET_DIR="$root/build/cargo-target${cpu:+-$cpu}" >/dev/null
cmake --build build/bench-dcol -j"$jobs" >/dev/null
cmake --install build/bench-dcol --prefix "$prefix" >/dev/null

# Coal 3: the C++ library is the libcoal wheel (the `coal` wheel only adds the Python bindings);
# its CMake config needs Boost (serialization, filesystem), octomap and Eigen3, and libcoal.so
# links boost 1.90, octomap, qhull and assimp: all from their cmeel wheels, unpacked (only
# cmeel.prefix/, no Python modules) into one prefix. Pinned to what libcoal 3.0.3 requires.
coal_wheels=(libcoal==3.0.3 "cmeel-boost~=1.90.0" "cmeel-octomap>=1.9.8.2,<2"
             "cmeel-qhull>=8.0.2.1,<8.0.3" "cmeel-assimp>=6.0.2,<7")
coal_dir="$root/build/coal"
coal_prefix=""
coal_reason=""
if [[ "${DCOL_BENCH_COAL:-1}" == 0 ]]; then
  coal_reason="disabled (DCOL_BENCH_COAL=0)"
elif [[ -n "${DCOL_BENCH_COAL_PREFIX:-}" ]]; then
  coal_prefix="$DCOL_BENCH_COAL_PREFIX"
elif [[ -f "$coal_dir/unpacked" ]]; then
  coal_prefix="$coal_dir/cmeel.prefix"
elif ! python3 -m pip --version >/dev/null 2>&1; then
  coal_reason="python3 -m pip not available to download the libcoal wheel"
else
  mkdir -p "$coal_dir/wheels"
  if timeout 600 python3 -m pip download --quiet --no-deps --only-binary=:all: \
       -d "$coal_dir/wheels" "${coal_wheels[@]}" >"$coal_dir/pip.log" 2>&1 &&
     python3 - "$coal_dir" >>"$coal_dir/pip.log" 2>&1 <<'PY'
import glob, os, sys, zipfile
out = sys.argv[1]
for whl in sorted(glob.glob(os.path.join(out, "wheels", "*.whl"))):
    with zipfile.ZipFile(whl) as z:
        for info in z.infolist():
            n = info.filename
            if n.startswith("cmeel.prefix/") and "/python3" not in n and "/site-packages/" not in n:
                z.extract(info, out)
                mode = (info.external_attr >> 16) & 0o777
                if mode:
                    os.chmod(os.path.join(out, n), mode)
# the wheels store the .so symlinks as copies: nothing to fix up
PY
  then
    touch "$coal_dir/unpacked"
    rm -rf "$coal_dir/wheels"   # (unpacked: never read again)
    coal_prefix="$coal_dir/cmeel.prefix"
  else
    coal_reason="downloading or unpacking the libcoal wheel failed, see build/coal/pip.log"
  fi
fi
if [[ -n "$coal_reason" ]]; then
  echo "Coal: not available ($coal_reason); benchmarking without it"
fi
cmake -S benches/compare -B build/bench-compare -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DDCOL_BENCH_COAL_PREFIX="$coal_prefix" \
  -DDCOL_BENCH_COAL_REASON="$coal_reason" >/dev/null
cmake --build build/bench-compare -j"$jobs" >/dev/null

if [[ $smoke == 1 ]]; then
  out="$root/build/bench-smoke"
  mkdir -p "$out"
  DCOL_BENCH_CASES="${DCOL_BENCH_CASES:-6}" DCOL_BENCH_OUT="$out" build/bench-compare/bench_compare 2>/dev/null
  test -s "$out/benchmark.md" && test -s "$out/time_vs_error.csv"
  DCOL_BENCH_SMOKE=1 build/bench-compare/bench_hulls > "$out/hulls.md"
  grep -q "^| 2000 |" "$out/hulls.md"
  if [[ -x build/bench-compare/bench_posesets ]]; then
    DCOL_BENCH_SMOKE=1 build/bench-compare/bench_posesets > "$out/posesets.md"
    grep -q "^| separated |" "$out/posesets.md"
  fi
  if [[ -x build/bench-compare/bench_trajectory ]]; then
    DCOL_BENCH_SMOKE=1 DCOL_BENCH_CSV="$out/trajectory.csv" build/bench-compare/bench_trajectory > "$out/trajectory.md"
    grep -q "^| proximity cached / cold (separated) |" "$out/trajectory.md"
    grep -q ",all-pairs,,gradient cached / cold (all steps),ratio," "$out/trajectory.csv"
  fi
  if python3 -c "import matplotlib" 2>/dev/null; then python3 benches/compare/plot.py "$out"; fi
  echo "smoke OK"
elif [[ $trajectory == 1 ]]; then
  if [[ ! -x build/bench-compare/bench_trajectory ]]; then
    echo "bench_trajectory needs Coal (${coal_reason:-find_package(coal 3) failed})" >&2
    exit 1
  fi
  mkdir -p results
  DCOL_BENCH_CSV="$root/results/trajectory.csv" build/bench-compare/bench_trajectory | tee results/trajectory.md
else
  mkdir -p results
  DCOL_BENCH_OUT="$root/results" build/bench-compare/bench_compare
  build/bench-compare/bench_hulls | tee results/hulls.md
  if [[ -x build/bench-compare/bench_posesets ]]; then
    build/bench-compare/bench_posesets | tee results/posesets.md
  fi
  if [[ -x build/bench-compare/bench_trajectory ]]; then
    DCOL_BENCH_CSV="$root/results/trajectory.csv" build/bench-compare/bench_trajectory | tee results/trajectory.md
  fi
  python3 benches/compare/plot.py results
fi
