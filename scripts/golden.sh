#!/usr/bin/env bash
# Regenerates tests/golden/*.json from the code: every scene of scenes/ and scenes/extreme/ run to
# its end, its summary physics (timings removed) and a hash of its final state. Run it only for a
# change of physics, and say why in the same commit; tests/golden.rs compares against these files.
#
# Each new summary is compared with the committed one within physical tolerances (what
# `decohesion compare` does): a file whose bits changed but whose physics did not is rewritten; a
# file whose physics moved is not, and this fails listing what moved, unless the change is
# acknowledged: GOLDEN_PHYSICS_CHANGE="why the physics changed" scripts/golden.sh
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/decohesion-target}"
UPDATE_GOLDEN=1 GOLDEN_PHYSICS_CHANGE="${GOLDEN_PHYSICS_CHANGE:-}" cargo test --release --test integration golden:: -- --nocapture
git status --short tests/golden
