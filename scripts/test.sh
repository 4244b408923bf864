#!/usr/bin/env bash
# Runs the whole test suite: the lints (rustfmt, clippy, rustdoc), the Rust tests, then the CMake
# build with its C tests (ctest), once normally and once with AddressSanitizer + UBSan, then the
# Python package (python/: built and installed into a venv under build/, tested with pytest).
#
#   ./scripts/test.sh
#
# Both CMake builds share one cargo target directory (build/cargo-target), so the Rust library
# is compiled for them once. Set JOBS to change the build parallelism (default 2).
#
# The CMake builds need Bullet, ODE and Ipopt (Debian: libbullet-dev libode-dev
# coinor-libipopt-dev, with pkg-config): they are configured with DCOL_REQUIRE_INTEGRATIONS=ON, so
# a missing one stops the run naming its package, unless DCOL_ALLOW_SKIP=1 asks for the reduced
# run (their bullet_*, ode_* and app_* tests left out), as it lets the Rust tests skip missing data.
set -euo pipefail
cd "$(dirname "$0")/.."

jobs=${JOBS:-2}
cargo_target=$PWD/build/cargo-target
require_integrations=ON
if [[ ${DCOL_ALLOW_SKIP:-0} == 1 ]]; then
  require_integrations=OFF
  echo "(DCOL_ALLOW_SKIP=1: a missing Bullet, ODE or Ipopt skips its tests instead of failing)"
fi

# Disk: a CI machine can have little of it (a run once stopped at "No space left on device").
# The tests need no debug info (Cargo.toml keeps it in release builds for profilers), so it is
# left out here unless CARGO_PROFILE_RELEASE_DEBUG / CARGO_PROFILE_BENCH_DEBUG say otherwise. With
# DCOL_TEST_FREE_DISK=1 (the default when CI is set) each build directory is removed once the
# steps that use it are done, and pip keeps no download cache.
export CARGO_PROFILE_RELEASE_DEBUG=${CARGO_PROFILE_RELEASE_DEBUG:-0}
export CARGO_PROFILE_BENCH_DEBUG=${CARGO_PROFILE_BENCH_DEBUG:-0}
free_disk=${DCOL_TEST_FREE_DISK:-}
if [[ -z $free_disk && -n ${CI:-} && ${CI:-} != false && ${CI:-} != 0 ]]; then free_disk=1; fi
if [[ $free_disk == 1 ]]; then export PIP_NO_CACHE_DIR=1; fi
done_with() {
  if [[ $free_disk == 1 ]]; then
    echo "(DCOL_TEST_FREE_DISK=1: removing $*)"
    rm -rf "$@"
  fi
}

echo "== lints: rustfmt, clippy and rustdoc, warnings as errors"
# rustfmt and clippy are rustup components a minimal toolchain may lack; rustdoc never is.
if cargo fmt --version >/dev/null 2>&1; then
  cargo fmt --check
else
  echo "(rustfmt is not installed: format check skipped)"
fi
if cargo clippy --version >/dev/null 2>&1; then
  cargo clippy --release --all-targets -- -D warnings
else
  echo "(clippy is not installed: lint skipped)"
fi
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps

echo "== cargo test --release"
cargo test --release

echo "== cargo test --release compiled for the x86-64-v3 CPU level (the DCOL_TARGET_CPU build),"
echo "   where this machine has that level"
# glibc's loader lists the levels the CPU supports; without that level the build cannot run here.
# (Read whole, not piped into `grep -q`: with pipefail, grep's early exit could fail the pipe.)
loader=/lib64/ld-linux-x86-64.so.2
levels=""
if [[ $(uname -m) == x86_64 && -x $loader ]]; then
  levels=$("$loader" --help 2>/dev/null || true)
fi
if [[ $levels == *"x86-64-v3 (supported"* ]]; then
  RUSTFLAGS="${RUSTFLAGS:-} -C target-cpu=x86-64-v3" cargo test --release --tests \
    --target-dir build/cargo-target-x86-64-v3
  done_with build/cargo-target-x86-64-v3
else
  echo "(this machine does not report x86-64-v3 support: skipped)"
fi

echo "== fuzz smoke (the deterministic, fixed-seed random driver: a test run must not go red on a"
echo "   coverage-guided fuzzer's fresh find; run ./scripts/fuzz_smoke.sh with libFuzzer for that)"
FUZZ_ENGINE=random ./scripts/fuzz_smoke.sh
done_with fuzz/target

echo "== benchmark smoke runs (a few poses each, so the benchmarks cannot rot)"
cargo bench --bench proximity -- --test
cargo bench --bench scene -- --test
# (Everything below builds the Rust library in build/cargo-target*.)
done_with target

for config in normal sanitize; do
  dir=build/cmake-$config
  sanitize=OFF
  [[ $config == sanitize ]] && sanitize=ON
  echo "== CMake ($config): configure, build, ctest"
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DDCOL_SANITIZE=$sanitize \
    -DDCOL_CARGO_TARGET_DIR="$cargo_target" -DDCOL_REQUIRE_INTEGRATIONS=$require_integrations
  cmake --build "$dir" -j "$jobs"
  (cd "$dir" && ctest --output-on-failure -j "$jobs")
  if [[ $config == sanitize ]]; then done_with "$dir"; fi
done

echo "== comparison suite against FCL 0.7 and libccd 2.1 (c_tests/compare), against installed dcol"
prefix=$PWD/build/compare-prefix
cmake --install build/cmake-normal --prefix "$prefix"
cmake -S c_tests/compare -B build/compare -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix"
cmake --build build/compare -j "$jobs"
(cd build/compare && ctest -V -j "$jobs")
done_with build/compare

echo "== time-vs-error benchmark against FCL and libccd: smoke run (benches/compare)"
./benches/compare/run.sh --smoke

if [[ -f build/cmake-normal/dcol-bullet.cmake ]]; then
  echo "== Bullet with dcol as its narrow phase: benchmark smoke run (benches/engines/bullet)"
  ./benches/engines/bullet/run.sh --smoke
fi
done_with build/bench-compare build/bench-dcol build/bench-prefix build/coal build/bench-smoke

echo "== Python package (python/): lints, pip install into a venv under build/ (with the jax"
echo "   extra), pytest (against tests/data and the C library built above), benchmark smoke run"
# Needs python3 (>= 3.9) with venv and pip, and PyPI (maturin, numpy, jax, pytest; coal and
# python-fcl for the benchmark). When those are missing the run fails, unless DCOL_ALLOW_SKIP=1
# (then the step is left out, saying so). Once they are there, every failure fails the run.
py_venv=$PWD/build/python-venv
py_target=$PWD/build/cargo-target-python
python_env() {
  # (Debian's python3 has the venv module but not ensurepip, which venv needs for pip.)
  if ! command -v python3 >/dev/null 2>&1 || ! python3 -c 'import ensurepip, venv' 2>/dev/null
  then
    echo "python3 with the venv and ensurepip modules is missing (Debian: apt-get install" \
      "python3-venv)"
    return 1
  fi
  [[ -x $py_venv/bin/pip ]] || python3 -m venv "$py_venv" || return 1
  # What the package and its tests need from PyPI (a network failure shows here).
  "$py_venv/bin/pip" install --quiet "maturin>=1.9,<2" numpy "jax>=0.4.34" pytest coal \
    python-fcl || return 1
}
if python_env; then
  # The crate is its own workspace: format and lint it there (pyo3's build script reads the
  # venv's interpreter).
  if cargo fmt --version >/dev/null 2>&1; then
    (cd python && cargo fmt --check)
  fi
  if cargo clippy --version >/dev/null 2>&1; then
    (cd python && PYO3_PYTHON=$py_venv/bin/python CARGO_TARGET_DIR=$py_target \
      cargo clippy --release -- -D warnings)
  fi
  # What the README says, `pip install ./python` (maturin builds it in an isolated environment).
  CARGO_TARGET_DIR=$py_target "$py_venv/bin/pip" install --quiet --force-reinstall --no-deps \
    ./python
  done_with "$py_target"
  # pytest from build/ (not python/, whose dcol/ folder is the uninstalled source), against the
  # C library the CMake build made; the JAX tests must run, not skip.
  py_lib=$PWD/build/cargo-target/release/libdcol.so
  [[ -f $py_lib ]] || { echo "$py_lib is missing (the CMake build above makes it)"; exit 1; }
  (cd build && DCOL_C_LIBRARY=$py_lib DCOL_REQUIRE_JAX=1 "$py_venv/bin/pytest" -q \
    -p no:cacheprovider ../python/tests)
  "$py_venv/bin/python" python/bench/bench.py --smoke
elif [[ ${DCOL_ALLOW_SKIP:-0} == 1 ]]; then
  echo "(not run, as DCOL_ALLOW_SKIP=1 allows: python3, its venv module, pip or PyPI is missing)"
else
  echo "python3, its venv module, pip or PyPI is missing (set DCOL_ALLOW_SKIP=1 to go on without"
  echo "the Python package's tests)"
  exit 1
fi
