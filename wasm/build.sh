#!/usr/bin/env bash
# Builds the npm package of laminar-wasm into OUT (default target/npm): the
# whole package and the evaluation-only one (`laminar-brdf/eval`, OUT/eval),
# each in a plain and a +simd128 build through `wasm-bindgen --target web`,
# beside the loader (npm/loader.js) that picks one by feature detection.
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
mkdir -p "$out/eval"
# The whole package (feature `fit`, the default) into OUT/{plain,simd}, the
# evaluation-only one (no default features) into OUT/eval/{plain,simd}.
for package in full eval; do
  features=""
  dir="$out"
  profile=wasm-release
  if [ "$package" = eval ]; then
    features="--no-default-features"
    dir="$out/eval"
    profile=wasm-eval
  fi
  for build in plain simd; do
    flags=""
    [ "$build" = simd ] && flags="-C target-feature=+simd128"
    target="$root/target/wasm-$package-$build"
    CARGO_TARGET_DIR="$target" RUSTFLAGS="$flags" \
      cargo build --quiet --manifest-path "$root/Cargo.toml" -p laminar-wasm $features \
      --profile "$profile" --target wasm32-unknown-unknown
    wasm-bindgen --target web --out-dir "$dir/$build" \
      "$target/wasm32-unknown-unknown/$profile/laminar_wasm.wasm"
    # binaryen's wasm-opt -Oz pays on the evaluation-only package (42.6 →
    # 39.6 KiB gzip with opt-level z); on the whole one it saves 0.4%, so it
    # is not run there. Without wasm-opt the package is built as is (and
    # cli/tests/web.rs says its size test was skipped).
    if [ "$package" = eval ] && command -v wasm-opt > /dev/null; then
      simd_flag=""
      [ "$build" = simd ] && simd_flag="--enable-simd"
      wasm-opt -Oz --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext \
        --enable-mutable-globals --enable-reference-types --enable-multivalue $simd_flag \
        "$dir/$build/laminar_wasm_bg.wasm" -o "$dir/$build/laminar_wasm_bg.wasm"
    fi
  done
done
cp "$root/wasm/npm/package.json" "$root/wasm/npm/index.js" "$root/wasm/npm/node.js" "$root/wasm/npm/index.d.ts" \
  "$root/wasm/npm/fits.d.ts" \
  "$root/wasm/npm/loader.js" "$root/wasm/npm/README.md" "$root/LICENSE-MIT" "$root/LICENSE-APACHE" "$out/"
cp "$root/wasm/npm/eval/index.js" "$root/wasm/npm/eval/node.js" "$root/wasm/npm/eval/index.d.ts" "$out/eval/"
