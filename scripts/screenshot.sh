#!/usr/bin/env bash
# Refreshes screenshots/viewer_pull_off.png: records the pull-off scene and has the Rerun viewer
# (same version as the SDK, from a virtual environment) render it under Xvfb with Mesa's
# software Vulkan (lavapipe). Needs, on Debian:
#   apt-get install -y xvfb mesa-vulkan-drivers libgl1-mesa-dri libxkbcommon-x11-0 xdotool
# Usage: scripts/screenshot.sh [SCENE] [OUT.png]
set -euo pipefail
cd "$(dirname "$0")/.."
scene="${1:-scenes/pull_off.toml}"
out="${2:-screenshots/viewer_pull_off.png}"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$HOME/.cache/decohesion-target}"
venv="${DECOHESION_VENV:-$HOME/.cache/decohesion-venv}"
if ! "$venv/bin/rerun" --version 2>/dev/null | grep -q "0.36.3"; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet "rerun-sdk==0.36.3"
  "$venv/bin/rerun" analytics disable >/dev/null 2>&1 || true
fi
mkdir -p out/captures "$(dirname "$out")"
rrd="out/captures/$(basename "$scene" .toml)_screenshot.rrd"
cargo run --release --quiet -- run "$scene" --quiet --save "$rrd"

display=":${DECOHESION_XVFB_DISPLAY:-97}"
Xvfb "$display" -screen 0 3400x2100x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill $xvfb 2>/dev/null || true' EXIT
sleep 1
# Park the pointer outside the window (the viewer draws at 2x): over the 3-D view it opens a
# hover tooltip.
DISPLAY="$display" xdotool mousemove 3399 2099 2>/dev/null || true
runtime="$(mktemp -d)"
# The viewer renders with wgpu on Vulkan (lavapipe); --screenshot-to saves the first settled
# frame and exits (code 102 on this version, sometimes after a panic message on shutdown).
set +e
XDG_RUNTIME_DIR="$runtime" DISPLAY="$display" WGPU_BACKEND=vulkan \
  timeout 180 "$venv/bin/rerun" --window-size 1560x960 --screenshot-to "$out" "$rrd" \
  >/dev/null 2>&1
set -e
if [ ! -s "$out" ]; then
  echo "screenshot failed: $out was not written" >&2
  exit 1
fi
# The viewer draws at 2x; half size keeps the repository light and the text readable.
if command -v convert >/dev/null; then
  convert "$out" -resize 50% "$out"
fi
echo "wrote $out ($(stat -c %s "$out") bytes)"
