#!/usr/bin/env bash
# Builds the viewer's web page into DIR (default target/web): index.html, eapbd.js (the
# JavaScript glue) and eapbd_bg.wasm (the viewer, with the solvers and WGSL kernels).
#
# Usage: web/build.sh [--out DIR]
#
# Serve DIR on localhost (WebGPU needs a secure context, which localhost is) and open it:
#   python3 -m http.server 8000 --bind 127.0.0.1 --directory target/web
#   then http://localhost:8000/ (URL parameters: see src/viewer/web.rs, e.g. ?scene=bunny)
# Installs what it lacks: Rust's wasm32-unknown-unknown target (rustup) and wasm-bindgen-cli at
# the version of the wasm-bindgen crate in Cargo.lock (cargo install, from crates.io).
set -euo pipefail
cd "$(dirname "$0")/.."
out=target/web
while [ $# -gt 0 ]; do
    case "$1" in
        --out) out=${2:?--out needs a directory}; shift 2 ;;
        -h | --help) sed -n '2,11p' "$0"; exit 0 ;;
        *) echo "web/build.sh: unknown argument $1 (usage: web/build.sh [--out DIR])" >&2; exit 2 ;;
    esac
done

version=$(awk '$0 == "name = \"wasm-bindgen\"" { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)
if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
    rustup target add wasm32-unknown-unknown
fi
if [ "$(wasm-bindgen --version 2>/dev/null | awk '{ print $2 }')" != "$version" ]; then
    cargo install wasm-bindgen-cli --version "$version"
fi
cargo rustc --release --lib --target wasm32-unknown-unknown --no-default-features --features viewer \
    --crate-type cdylib
mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out" --out-name eapbd \
    target/wasm32-unknown-unknown/release/eapbd.wasm
cp web/index.html "$out/"
echo "web/build.sh: the page is in $out ($(du -k "$out/eapbd_bg.wasm" | cut -f1) KiB of wasm)"
