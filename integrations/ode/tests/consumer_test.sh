#!/usr/bin/env bash
# The ode component from an installed dcol: installs the build into a temporary prefix, builds
# examples/ode (a plain ODE program calling dcol_ode::use_dcol(), find_package(dcol REQUIRED
# COMPONENTS ode)) against it and runs it; then checks that asking for a component this
# installation lacks stops the configuration with a message naming it.
#
# Usage: consumer_test.sh BUILD_DIR EXAMPLE_SOURCE_DIR WORK_DIR CMAKE
set -euo pipefail
build=$1
src=$2
work=$3
cmake=$4

rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix
"$cmake" --install "$build" --prefix "$prefix" >"$work/install.log"
for f in include/dcol_ode.hpp; do
  [[ -f "$prefix/$f" ]] || { echo "FAILED: not installed: $f"; exit 1; }
done
lib=$(find "$prefix" -name libdcol_ode.a)
[[ -n "$lib" ]] || { echo "FAILED: libdcol_ode.a not installed"; exit 1; }
[[ -f "$(dirname "$lib")/cmake/dcol/dcol-ode.cmake" ]] ||
  { echo "FAILED: dcol-ode.cmake not installed"; exit 1; }

echo "== examples/ode against the installed package (find_package(dcol REQUIRED COMPONENTS ode))"
"$cmake" -S "$src" -B "$work/example" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
  >"$work/example.log" 2>&1 || { cat "$work/example.log"; exit 1; }
"$cmake" --build "$work/example" >>"$work/example.log" 2>&1 || { cat "$work/example.log"; exit 1; }
"$work/example/ode_example"
deps=$(ldd "$work/example/ode_example") || { echo "FAILED: ldd ode_example"; exit 1; }
grep -qF "libdcol.so.0 => $(dirname "$lib")/libdcol.so.0 " <<<"$deps" ||
  { echo "FAILED: ode_example does not load the installed libdcol.so.0"; echo "$deps"; exit 1; }

echo "== a component the installation lacks fails at configure time"
mkdir -p "$work/missing"
cat >"$work/missing/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.16)
project(missing_component LANGUAGES CXX)
find_package(dcol REQUIRED COMPONENTS ode no_such_engine)
CMAKE
if "$cmake" -S "$work/missing" -B "$work/missing/build" -DCMAKE_PREFIX_PATH="$prefix" \
  >"$work/missing.log" 2>&1; then
  echo "FAILED: find_package(dcol REQUIRED COMPONENTS no_such_engine) configured"
  exit 1
fi
# CMake wraps the message: join the lines before searching it.
tr -s ' \n' ' ' <"$work/missing.log" | grep -q 'dcol has no component "no_such_engine"' ||
  { echo "FAILED: the message does not name the missing component"; cat "$work/missing.log"; exit 1; }
echo "the missing component stops the configuration: ok"
echo "ode consumer: ok"
