#!/usr/bin/env bash
# Rebuild crslab serve's vendored browser code from npm (development time only; the built files are
# committed, so the page works offline and nothing here runs at install or run time).
#
#   bash tools/serve_vendor/build.sh
#
# Installs the exact versions of package-lock.json into a temporary folder, bundles entry.js with
# esbuild into crslab/serve/static/vendor/crslab-vendor.js (one IIFE, minified), copies xterm's
# stylesheet, and each bundled package's licence into crslab/serve/static/vendor/licenses/.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="$here/../../crslab/serve/static/vendor"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp "$here/package.json" "$here/package-lock.json" "$here/entry.js" "$work/"
cd "$work"
npm ci --no-audit --no-fund
npx esbuild entry.js --bundle --minify --format=iife --target=es2020 --legal-comments=none \
  --outfile="$out/crslab-vendor.js"
cp node_modules/@xterm/xterm/css/xterm.css "$out/xterm.css"
rm -rf "$out/licenses" && mkdir -p "$out/licenses"
for dir in $(find node_modules -name package.json -path '*node_modules/*/package.json' -not -path '*/node_modules/*/node_modules/*' | xargs -n1 dirname | sort); do
  name="${dir#node_modules/}"
  case "$name" in esbuild|@esbuild/*) continue ;; esac   # the bundler itself is not shipped
  lic="$(ls "$dir" | grep -iE '^(licen[cs]e|copying)' | head -n1 || true)"
  [ -n "$lic" ] || continue
  version="$(node -p "require('./$dir/package.json').version")"
  cp "$dir/$lic" "$out/licenses/$(echo "$name" | tr '/' '_')-$version.txt"
done
ls -l "$out" "$out/licenses"
