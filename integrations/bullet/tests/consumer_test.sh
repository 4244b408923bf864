#!/usr/bin/env bash
# Installs dcol (this build tree) into a temporary prefix, then, as a user would: builds and runs
# examples/bullet (a Bullet program with find_package(dcol REQUIRED COMPONENTS bullet), linking
# dcol::bullet, calling use_dcol) against it; and checks that asking for a component that does not
# exist fails at configure time with a clear message (and only warns as an optional component).
#
# Usage: consumer_test.sh BUILD_DIR EXAMPLE_DIR WORK_DIR CMAKE
set -euo pipefail
build=$1
example=$2
work=$3
cmake=$4

rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix
"$cmake" --install "$build" --prefix "$prefix" >"$work/install.log"
cfgdir=$(dirname "$(find "$prefix" -name dcolConfig.cmake)")
for f in "$prefix/include/dcol_bullet.hpp" "$cfgdir/dcol-bullet.cmake" "$cfgdir/../../libdcol_bullet.a"; do
  [[ -f "$f" ]] || { echo "FAILED: not installed: $f"; exit 1; }
done

echo "== examples/bullet against the installed dcol::bullet"
"$cmake" -S "$example" -B "$work/example" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  >"$work/example.log" 2>&1 || { cat "$work/example.log"; exit 1; }
"$cmake" --build "$work/example" >>"$work/example.log" 2>&1 || { cat "$work/example.log"; exit 1; }
"$work/example/bullet_example"

echo "== a component that does not exist"
mkdir -p "$work/missing"
cat >"$work/missing/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(missing_component LANGUAGES CXX)
if(OPTIONAL)
  find_package(dcol 0.1 REQUIRED COMPONENTS bullet OPTIONAL_COMPONENTS nosuch)
  if(NOT TARGET dcol::bullet OR dcol_nosuch_FOUND)
    message(FATAL_ERROR "optional component: expected dcol::bullet and dcol_nosuch_FOUND false")
  endif()
else()
  find_package(dcol 0.1 REQUIRED COMPONENTS bullet nosuch)
endif()
CMAKE
if "$cmake" -S "$work/missing" -B "$work/missing/build" -DCMAKE_PREFIX_PATH="$prefix" >"$work/missing.log" 2>&1; then
  echo "FAILED: find_package(dcol REQUIRED COMPONENTS nosuch) succeeded"
  exit 1
fi
grep -q 'dcol has no component "nosuch"' "$work/missing.log" ||
  { echo "FAILED: no clear message for a missing component:"; cat "$work/missing.log"; exit 1; }
grep -A3 'dcol has no component' "$work/missing.log"
rm -rf "$work/missing/build"
"$cmake" -S "$work/missing" -B "$work/missing/build" -DCMAKE_PREFIX_PATH="$prefix" -DOPTIONAL=ON \
  >"$work/optional.log" 2>&1 || { echo "FAILED: an optional missing component failed:"; cat "$work/optional.log"; exit 1; }
echo "consumer: examples/bullet ran against the installed component; a missing component fails clearly"
