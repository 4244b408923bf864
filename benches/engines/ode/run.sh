#!/usr/bin/env bash
# Builds dcol (Release) with the top-level CMake, installs it into build/bench-prefix, builds the
# ODE benchmark against the installed package and runs it: whole-step time and narrow-phase time
# per dCollide call, ODE's own colliders against dcol's, on the pyramid and the pile, in one run.
#
#   benches/engines/ode/run.sh            # full run (5 rounds), about three minutes
#   benches/engines/ode/run.sh --smoke    # a few steps, to check that it builds and runs
#   benches/engines/ode/run.sh --instructions   # instructions per step and per dCollide under
#                                         # callgrind (the same on a loaded machine), ~10 minutes
# Environment: DCOL_BENCH_ROUNDS (default 5), DCOL_BENCH_JOBS (default 2).
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
if [[ "${1:-}" != "--instructions" ]]; then
  build/bench-ode/bench_ode "$@"
  exit 0
fi
# Instructions (valgrind --tool=callgrind), which a loaded machine does not change: inside
# World::step (the whole step) and inside dCollide (the narrow phase), per step and per call.
echo "instructions per step and per dCollide call (callgrind; pyramid: the first ${DCOL_BENCH_PYRAMID_STEPS:-400} steps)"
echo
echo "| scene | narrow phase | per step | per dCollide call | calls per step |"
echo "|---|---|---|---|---|"
for scene in pyramid pile pile2; do
  steps=1000
  [[ $scene == pyramid ]] && steps=${DCOL_BENCH_PYRAMID_STEPS:-400}
  for mode in native dcol; do
    out=build/bench-ode/callgrind.$scene.$mode
    calls=$(valgrind --tool=callgrind --callgrind-out-file="$out" \
      --toggle-collect='ode_scenes::World::step()' build/bench-ode/bench_ode --only $scene $mode $steps 2>/dev/null |
      awk '{print $1}')
    step_ir=$(callgrind_annotate "$out" 2>/dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1}')
    valgrind --tool=callgrind --callgrind-out-file="$out.collide" \
      --toggle-collect='dCollide' build/bench-ode/bench_ode --only $scene $mode $steps >/dev/null 2>&1
    collide_ir=$(callgrind_annotate "$out.collide" 2>/dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1}')
    echo "| $scene | $mode | $((step_ir / steps)) | $((collide_ir / calls)) | $((calls / steps)) |"
  done
done

# One resting pair at a time: instructions per dCollide (callgrind, 1000 calls minus 0), aligned
# faces and tilted by 1e-6 rad.
ir() {
  valgrind --tool=callgrind --callgrind-out-file=/dev/null build/bench-ode/pair_instructions "$@" 2>&1 |
    awk '/Collected/ {print $4}'
}
echo
echo "instructions per dCollide of one resting pair (contacts), aligned and tilted by 1e-6 rad"
echo
echo "| pair | ODE | dcol | ODE, tilted | dcol, tilted |"
echo "|---|---|---|---|---|"
i=0
while read -r name; do
  row="| $name"
  for tilt in 0 1e-6; do
    for mode in native dcol; do
      n0=$(ir $i $mode 0 $tilt)
      n1=$(ir $i $mode 1000 $tilt)
      contacts=$(build/bench-ode/pair_instructions $i $mode 1 $tilt)
      row="$row | $(((n1 - n0) / 1000)) ($contacts)"
    done
  done
  echo "$row |"
  i=$((i + 1))
done < <(build/bench-ode/pair_instructions --list)
