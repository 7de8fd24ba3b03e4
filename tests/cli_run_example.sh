#!/usr/bin/env bash
# Runs an example through the command line and checks what it must write.
set -eu
exe="$1"; file="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$exe" check "$file" | grep -q "check: OK"
"$exe" "$file" --output "$tmp/out" --quiet
for f in result.h5 result.xdmf summary.json; do test -s "$tmp/out/$f" || { echo "missing $f"; exit 1; }; done
grep -q '"converged": true' "$tmp/out/summary.json"
ls "$tmp/out" | grep -q '\.part$' && { echo "temporary file left behind"; exit 1; }
"$exe" --version | grep -q igacontact
"$exe" --help | grep -q "usage"
echo "example OK"
