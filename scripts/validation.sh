#!/usr/bin/env bash
# The validation report in one command: runs both crates' integration test binaries with
# DECOHESION_VALIDATION_DIR=out/validation (cleared first), so that the tests that compare with
# an independent reference record what they compare (tests/common/validation.rs), then writes
# docs/src/validation.md and its plots (docs/src/validation/*.png) with
# scripts/validation_report.py. Exits non-zero if a test or a recorded case failed.
#
# The report's Python: $PYTHON if set, else python3; the plots need matplotlib there (without
# it the report has the tables only, and says so).
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/decohesion-target}"
out="$PWD/out/validation"
rm -rf "$out"
mkdir -p "$out"
# Absolute: each test binary runs in its own package's directory.
export DECOHESION_VALIDATION_DIR="$out"
status=0
cargo test --release -p decohesion-physics --test integration || status=$?
cargo test --release -p decohesion --test integration || status=$?
"${PYTHON:-python3}" scripts/validation_report.py --dir "$out" --strict || status=$?
exit "$status"
