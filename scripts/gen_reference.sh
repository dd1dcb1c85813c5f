#!/usr/bin/env bash
# Regenerates the three reference pages of the book from the code:
#   docs/src/reference/scenes.md  `decohesion reference scenes` (physics/src/scene/keys.rs, the law families)
#   docs/src/reference/cli.md     `decohesion reference cli`    (the clap definition in src/main.rs)
#   docs/src/reference/python.md  scripts/python_reference.py   (python/decohesion/_native.pyi, __init__.py)
# tests/reference.rs and `python3 scripts/python_reference.py --check` fail when a committed page
# differs from what this writes.
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/decohesion-target}"
out=docs/src/reference
cargo build --release --quiet --bin decohesion
"$CARGO_TARGET_DIR/release/decohesion" reference scenes --out "$out/scenes.md"
"$CARGO_TARGET_DIR/release/decohesion" reference cli --out "$out/cli.md"
python3 scripts/python_reference.py --out "$out/python.md"
echo "wrote $out/scenes.md, $out/cli.md, $out/python.md"
