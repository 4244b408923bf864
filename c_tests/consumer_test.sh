#!/usr/bin/env bash
# Installs dcol into a temporary prefix, then builds and runs separate consumer projects against
# it: find_package(dcol) with dcol::dcol (shared) and dcol::dcol_static, and pkg-config.
#
# Usage: consumer_test.sh BUILD_DIR CONSUMER_SOURCE_DIR WORK_DIR VERSION CMAKE C_COMPILER
set -euo pipefail
build=$1
src=$2
work=$3
version=$4
cmake=$5
cc=$6

rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix

echo "== cmake --install into $prefix"
"$cmake" --install "$build" --prefix "$prefix" >"$work/install.log"
libdir=$(dirname "$(find "$prefix" -name dcol.pc)")/..
libdir=$(cd "$libdir" && pwd)

for f in "$prefix/include/dcol.h" "$prefix/include/dcol.hpp" "$libdir/libdcol.so.$version" \
  "$libdir/libdcol.a" "$libdir/cmake/dcol/dcolConfig.cmake" \
  "$libdir/cmake/dcol/dcolConfigVersion.cmake" "$libdir/pkgconfig/dcol.pc"; do
  [[ -f "$f" ]] || { echo "FAILED: not installed: $f"; exit 1; }
done
for link in libdcol.so libdcol.so.0; do
  [[ -L "$libdir/$link" ]] || { echo "FAILED: $libdir/$link is not a symlink"; exit 1; }
done
[[ "$(readlink -f "$libdir/libdcol.so")" == "$(readlink -f "$libdir/libdcol.so.$version")" ]] ||
  { echo "FAILED: libdcol.so does not resolve to libdcol.so.$version"; exit 1; }

for mode in shared static; do
  echo "== find_package(dcol), $mode"
  static=OFF
  [[ $mode == static ]] && static=ON
  "$cmake" -S "$src" -B "$work/consumer-$mode" -DCMAKE_PREFIX_PATH="$prefix" \
    -DDCOL_CONSUMER_STATIC=$static -DCMAKE_BUILD_TYPE=Release >"$work/consumer-$mode.log"
  "$cmake" --build "$work/consumer-$mode" >>"$work/consumer-$mode.log" ||
    { cat "$work/consumer-$mode.log"; exit 1; }
  for exe in consumer consumer_cpp; do
    "$work/consumer-$mode/$exe"
    # ldd's output is captured before it is searched: under pipefail, `ldd | grep -q` fails
    # whenever grep exits at the first match while ldd is still writing (SIGPIPE), which made
    # this check flaky on CI although the library resolved correctly.
    deps=$(ldd "$work/consumer-$mode/$exe") || { echo "FAILED: ldd $exe"; exit 1; }
    if [[ $mode == shared ]]; then
      grep -qF "libdcol.so.0 => $libdir/libdcol.so.0 " <<<"$deps" ||
        { echo "FAILED: $exe does not load the installed libdcol.so.0"; echo "$deps"; exit 1; }
    elif grep -q libdcol <<<"$deps"; then
      echo "FAILED: the static $exe depends on a shared libdcol"
      exit 1
    fi
  done
done

echo "== pkg-config"
export PKG_CONFIG_PATH=$libdir/pkgconfig
got=$(pkg-config --modversion dcol)
[[ "$got" == "$version" ]] || { echo "FAILED: pkg-config reports $got, expected $version"; exit 1; }
# shellcheck disable=SC2046  # word splitting of the flags is intended
"$cc" -std=c99 -Wall -Wextra -Werror -pedantic "$src/main.c" -o "$work/pkgconfig-shared" \
  $(pkg-config --cflags --libs dcol) -lm
LD_LIBRARY_PATH=$libdir "$work/pkgconfig-shared"
# Static: the archive itself, plus what pkg-config --static adds for it.
# shellcheck disable=SC2046
"$cc" -std=c99 -Wall -Wextra -Werror -pedantic "$src/main.c" -o "$work/pkgconfig-static" \
  $(pkg-config --cflags dcol) "$libdir/libdcol.a" \
  $(pkg-config --static --libs-only-l dcol | sed 's/-ldcol//') -lm
"$work/pkgconfig-static"

echo "consumers: shared, static and pkg-config builds all ran"
