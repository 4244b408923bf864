#!/usr/bin/env bash
# Fuzz smoke run: a short run of both fuzz targets (`shapes`: the shape constructors,
# hulls included, Rust and C; `queries`: every query of the Rust API and of the C ABI, the
# batch and a scene included, with arbitrary shapes, poses and options, every number written on
# DCOL_OK checked finite), starting from the checked-in seeds in fuzz/seeds/. Exits non-zero if
# any input crashes (panics, violates an invariant of fuzz/src/lib.rs) or if the build fails.
#
#   ./scripts/fuzz_smoke.sh                  # 20 s per target after the build
#   FUZZ_SECONDS=60 ./scripts/fuzz_smoke.sh  # longer
#   FUZZ_ENGINE=random ./scripts/fuzz_smoke.sh
#
# Engines (FUZZ_ENGINE=auto picks the first that is available):
#   libfuzzer  coverage-guided libFuzzer through cargo-fuzz (`cargo install cargo-fuzz`). With a
#              nightly toolchain: `cargo +nightly fuzz run` (AddressSanitizer on, which also
#              checks the C ABI's unsafe code); without one: the stable toolchain with
#              RUSTC_BOOTSTRAP=1 and `--sanitizer none` (same coverage guidance, no ASan).
#              A crashing input is saved under fuzz/artifacts/<target>/.
#   random     stable Rust only, nothing to install: fuzz/examples/random_driver.rs feeds the
#              same targets with pseudo-random and mutated-seed inputs (no coverage feedback);
#              a crashing input is saved under fuzz/artifacts/random_driver/.
# The fuzz builds use their own target directory (fuzz/target), not the main one.
set -euo pipefail
cd "$(dirname "$0")/.."

secs=${FUZZ_SECONDS:-20}
engine=${FUZZ_ENGINE:-auto}
targets=(shapes queries)

if [[ $engine == auto ]]; then
  if cargo fuzz --version >/dev/null 2>&1; then
    engine=libfuzzer
  else
    engine=random
  fi
fi
fuzz=(cargo fuzz)
sanitizer=()
if [[ $engine == libfuzzer ]]; then
  if cargo +nightly --version >/dev/null 2>&1; then
    fuzz=(cargo +nightly fuzz)
  else
    # cargo-fuzz passes unstable flags; the stable compiler accepts them with RUSTC_BOOTSTRAP.
    export RUSTC_BOOTSTRAP=1
    sanitizer=(--sanitizer none)
  fi
fi
if [[ $engine == libfuzzer ]]; then
  echo "== fuzz smoke: libFuzzer via '${fuzz[*]} ${sanitizer[*]}', ${secs} s per target"
else
  echo "== fuzz smoke: stable random driver, ${secs} s per target"
fi

case $engine in
  libfuzzer)
    "${fuzz[@]}" build -O "${sanitizer[@]}"
    status=0
    for t in "${targets[@]}"; do
      # A scratch corpus seeded from the checked-in seeds, so the repository is not modified.
      corpus=$(mktemp -d)
      log=$(mktemp)
      cp fuzz/seeds/"$t"/* "$corpus"/ 2>/dev/null || true
      echo "== cargo fuzz run $t (${secs} s)"
      if "${fuzz[@]}" run -O "${sanitizer[@]}" "$t" "$corpus" -- \
          -max_total_time="$secs" -timeout=10 -rss_limit_mb=4096 -print_final_stats=1 \
          >"$log" 2>&1; then
        grep -E "^(Done|stat::number_of_executed_units)" "$log" || tail -n 5 "$log"
      else
        tail -n 60 "$log"
        echo "FUZZ FAILURE in $t: the input is in fuzz/artifacts/$t/" \
          "(replay: ${fuzz[*]} run ${sanitizer[*]} $t <file>)"
        status=1
      fi
      rm -rf "$corpus" "$log"
    done
    exit $status
    ;;
  random)
    (cd fuzz && cargo run --release --no-default-features --example random_driver -- \
        --seconds "$((secs * ${#targets[@]}))")
    ;;
  *)
    echo "unknown FUZZ_ENGINE=$engine (libfuzzer|random|auto)" >&2
    exit 2
    ;;
esac
