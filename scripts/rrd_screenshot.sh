#!/usr/bin/env bash
# A screenshot of a recording as the Rerun viewer (same version as the SDK) opens it: the viewer
# runs headless (`rerun --headless`, an offscreen egui_kittest harness on Mesa's software Vulkan,
# lavapipe; no X server, no start-up notices over the views), its gRPC port bound to 127.0.0.1,
# and the SDK's ViewerClient asks it for the picture once the recording has loaded.
# Needs, on Debian: apt-get install -y mesa-vulkan-drivers imagemagick
# Usage: scripts/rrd_screenshot.sh RECORDING.rrd OUT.png [WIDTHxHEIGHT] [SETTLE_SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
rrd="$1"
out="$2"
size="${3:-1560x960}"
settle="${4:-12}"
venv="${DECOHESION_VENV:-$HOME/.cache/decohesion-venv}"
if ! "$venv/bin/rerun" --version 2>/dev/null | grep -q "0.36.3"; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet "rerun-sdk==0.36.3"
  "$venv/bin/rerun" analytics disable >/dev/null 2>&1 || true
fi
# A free loopback port: a viewer already listening on the port would be sent the recording
# instead, and this script would photograph the wrong window.
port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
runtime="$(mktemp -d)"
log="$(mktemp)"
mkdir -p "$(dirname "$out")"
XDG_RUNTIME_DIR="$runtime" WGPU_BACKEND=vulkan timeout 300 "$venv/bin/rerun" --headless \
  --bind 127.0.0.1 --port "$port" --window-size "$size" "$rrd" >"$log" 2>&1 &
viewer=$!
trap 'kill $viewer 2>/dev/null || true' EXIT
# Loaded and laid out: the views are drawn from the next frames on.
for _ in $(seq 60); do
  grep -q "Headless viewer running" "$log" && break
  if ! kill -0 $viewer 2>/dev/null; then
    echo "the viewer exited before loading $rrd:" >&2
    tail -5 "$log" >&2
    exit 1
  fi
  sleep 1
done
sleep "$settle"
rm -f "$out"
"$venv/bin/python" - "$port" "$(realpath -m "$out")" <<'PY'
import sys
from rerun.experimental import ViewerClient
ViewerClient.connect(f"rerun+http://127.0.0.1:{sys.argv[1]}/proxy").save_screenshot(sys.argv[2])
PY
for _ in $(seq 30); do
  [ -s "$out" ] && break
  sleep 1
done
if [ ! -s "$out" ]; then
  echo "screenshot failed: $out was not written; the viewer said:" >&2
  tail -5 "$log" >&2
  exit 1
fi
echo "wrote $out ($(stat -c %s "$out") bytes)"
