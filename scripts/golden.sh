#!/usr/bin/env bash
# Regenerates tests/golden/*.json from the code: every scene of scenes/ and scenes/extreme/ run to
# its end, its summary physics (timings removed) and a hash of its final state. Run it only for a
# change of physics, and say why in the same commit; tests/golden.rs compares against these files.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/decohesion-target}"
UPDATE_GOLDEN=1 cargo test --release --test integration golden:: -- --nocapture
git status --short tests/golden
