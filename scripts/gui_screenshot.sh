#!/usr/bin/env bash
# Refreshes screenshots/gui.png: opens the explorer under Xvfb (Mesa llvmpipe through glow),
# runs the pull-off scene and grabs the window once the run is in the history. Needs, on Debian: apt-get install -y xvfb libgl1-mesa-dri libxkbcommon-x11-0 imagemagick
# Usage: scripts/gui_screenshot.sh [OUT.png [GUI ARGS...]]
#   default: runs the pull-off once (--run-on-start);
#   screenshots/gui_compare.png: scripts/gui_screenshot.sh screenshots/gui_compare.png --compare u_r=0.003,0.004,0.006
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-screenshots/gui.png}"
shift || true
args=("$@")
[ ${#args[@]} -eq 0 ] && args=(--run-on-start)
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/decohesion-target}"
# DECOHESION_BIN: an explorer already built; else build one and copy it at once (a target
# directory shared with other checkouts may get their binary under the same name).
bin="${DECOHESION_BIN:-}"
if [ -z "$bin" ]; then
  cargo build --release --quiet
  bin="$(mktemp -d)/decohesion"
  cp "$CARGO_TARGET_DIR/release/decohesion" "$bin"
fi

display=":${DECOHESION_XVFB_DISPLAY:-98}"
Xvfb "$display" -screen 0 1600x1000x24 >/dev/null 2>&1 &
xvfb=$!
# A fresh storage folder: the picture must not depend on what an earlier session saved.
state="$(mktemp -d)"
cleanup() { kill "${app:-}" 2>/dev/null || true; kill $xvfb 2>/dev/null || true; rm -rf "$state"; }
trap cleanup EXIT
sleep 1
XDG_DATA_HOME="$state" XDG_CONFIG_HOME="$state" DISPLAY="$display" \
  "$bin" gui scenes/pull_off.toml "${args[@]}" --record off >/dev/null 2>&1 &
app=$!
# The pull-off takes well under a second; the window needs a few to come up under llvmpipe.
sleep 12
mkdir -p "$(dirname "$out")"
DISPLAY="$display" import -window root -crop 1500x950+0+0 +repage "$out"
echo "wrote $out ($(stat -c %s "$out") bytes)"
