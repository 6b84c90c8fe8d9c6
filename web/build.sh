#!/usr/bin/env bash
# Builds the web page into OUT (default target/web): plain files that work
# offline from any static server (`python3 -m http.server -d target/web`).
# The npm package is built first (wasm/build.sh) unless NPM_PACKAGE names a
# built one.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="${1:-$root/target/web}"
package="${NPM_PACKAGE:-}"
if [ -z "$package" ]; then
  package="$root/target/npm"
  bash "$root/wasm/build.sh" "$package"
fi
rm -rf "$out"
mkdir -p "$out/laminar-brdf"
cp "$root"/web/src/* "$out/"
cp -r "$package"/index.js "$package"/loader.js "$package"/plain "$package"/simd "$package"/eval "$out/laminar-brdf/"
echo "$out"
