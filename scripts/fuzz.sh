#!/usr/bin/env bash
# Coverage-guided fuzzing of the scene, Gmsh and STL parsers (fuzz/): libFuzzer through
# libfuzzer-sys on the stable toolchain, instrumented with the coverage flags cargo-fuzz passes
# (no nightly, no cargo-fuzz). Each target runs SECONDS (default 60) from the bad-input corpus's
# files and the shipped scenes as seeds; a crash is written to fuzz/artifacts/TARGET/ and fails the
# script. `.ci/run` calls it with a short time. Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
export CARGO_TARGET_DIR="${DECOHESION_FUZZ_TARGET:-$HOME/.cache/decohesion-fuzz-target}"
# The host triple given explicitly, so that RUSTFLAGS reach the fuzzed crates and not the build
# scripts and procedural macros (which run on the host and must not be instrumented).
host="$(rustc -vV | sed -n 's/^host: //p')"
export RUSTFLAGS="--cfg fuzzing -Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares"
# The workspace's clippy wrapper (set by .ci/run) is not for this build.
unset RUSTC_WORKSPACE_WRAPPER CLIPPY_ARGS
echo "== building the fuzz targets (fuzz/, release profile of fuzz/Cargo.toml, $host)"
cargo build --manifest-path fuzz/Cargo.toml --release --target "$host" --bins --locked
bin="$CARGO_TARGET_DIR/$host/release"
data=tests/data/bad_input
for target in scene msh stl; do
  seeds="fuzz/corpus/$target"
  mkdir -p "$seeds" "fuzz/artifacts/$target"
  case $target in
    scene) cp "$data"/valid/*.toml "$data"/scene/*.toml scenes/*.toml "$seeds"/ ;;
    msh) cp "$data"/valid/*.msh "$data"/msh/* "$seeds"/ 2>/dev/null || true ;;
    stl) cp "$data"/valid/*.stl "$data"/stl/* "$seeds"/ 2>/dev/null || true ;;
  esac
  echo "== fuzz $target for $seconds s ($(ls "$seeds" | wc -l) seeds)"
  log="$(mktemp)"
  status=0
  # -close_fd_mask=3: the targets' own output (none expected) stays out of the log.
  "$bin/$target" "$seeds" -max_total_time="$seconds" -max_len=65536 -close_fd_mask=3 \
    -artifact_prefix="fuzz/artifacts/$target/" -print_final_stats=1 > "$log" 2>&1 || status=$?
  grep -E '^(Done|stat::number_of_executed_units|stat::new_units_added|stat::peak_rss_mb)' "$log" || true
  if [ "$status" -ne 0 ]; then
    tail -n 60 "$log" >&2
    echo "fuzz target $target failed (exit $status); the input is in fuzz/artifacts/$target/" >&2
    exit 1
  fi
  rm -f "$log"
done
