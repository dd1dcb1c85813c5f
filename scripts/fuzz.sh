#!/usr/bin/env bash
# Coverage-guided fuzzing of the scene, Gmsh and STL parsers (fuzz/, cargo-fuzz on nightly):
# each target runs SECONDS (default 60) from the bad-input corpus's files as seeds; a crash is
# written to fuzz/artifacts/TARGET/ and fails the script. Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
if ! rustup toolchain list | grep -q '^nightly'; then
  echo "scripts/fuzz.sh needs the nightly toolchain: rustup toolchain install nightly" >&2
  exit 2
fi
command -v cargo-fuzz >/dev/null || cargo install --locked cargo-fuzz
data=tests/data/bad_input
for target in scene msh stl; do
  seeds="fuzz/corpus/$target"
  mkdir -p "$seeds"
  case $target in
    scene) cp "$data"/valid/*.toml "$data"/scene/*.toml scenes/*.toml "$seeds"/ ;;
    msh) cp "$data"/valid/*.msh "$data"/msh/* "$seeds"/ 2>/dev/null || true ;;
    stl) cp "$data"/valid/*.stl "$data"/stl/* "$seeds"/ 2>/dev/null || true ;;
  esac
  echo "== fuzz $target for $seconds s"
  cargo +nightly fuzz run --fuzz-dir fuzz "$target" "$seeds" -- -max_total_time="$seconds" -max_len=65536
done
