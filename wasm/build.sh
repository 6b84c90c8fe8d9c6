#!/usr/bin/env bash
# Builds the npm package of laminar-wasm into OUT (default target/npm):
# the plain and the +simd128 builds, each through `wasm-bindgen --target web`,
# beside the loader (npm/index.js) that picks one by feature detection.
# Needs the wasm32-unknown-unknown target and the `wasm-bindgen` command of
# the version pinned in wasm/Cargo.toml (`.ci/run` installs it).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$root/target/npm}"
pinned="$(sed -n 's/^wasm-bindgen = "=\(.*\)"/\1/p' "$root/wasm/Cargo.toml")"
have="$(wasm-bindgen --version | awk '{print $2}')"
if [ "$have" != "$pinned" ]; then
  echo "wasm-bindgen $have found, $pinned needed: cargo install --locked wasm-bindgen-cli --version $pinned" >&2
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
for build in plain simd; do
  flags=""
  [ "$build" = simd ] && flags="-C target-feature=+simd128"
  CARGO_TARGET_DIR="$root/target/wasm-$build" RUSTFLAGS="$flags" \
    cargo build --quiet --manifest-path "$root/Cargo.toml" -p laminar-wasm \
    --profile wasm-release --target wasm32-unknown-unknown
  wasm-bindgen --target web --out-dir "$out/$build" \
    "$root/target/wasm-$build/wasm32-unknown-unknown/wasm-release/laminar_wasm.wasm"
done
cp "$root/wasm/npm/package.json" "$root/wasm/npm/index.js" "$root/wasm/npm/index.d.ts" \
  "$root/wasm/npm/README.md" "$out/"
