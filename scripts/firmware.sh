#!/usr/bin/env bash
# Builds every AVR image (nightly, avr-none, atmega328p, -Zbuild-std=core) and copies
# the ELF files to target/firmware/, the fixed paths that tests, the twin and flash.sh use
# (or to $BLODWEN_FIRMWARE_DIR, which the harness reads too). Only the images this build
# names are copied, and images of binaries since renamed or removed are deleted there, so
# no test or size report sees a stale one.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
out=${BLODWEN_FIRMWARE_DIR:-$root/target/firmware}
mkdir -p "$out"
messages=$(mktemp)
trap 'rm -f "$messages"' EXIT
cargo +nightly build --target avr-none -Zbuild-std=core --profile avr \
  -p master -p slave -p firmware-examples -p drivers --message-format=json-render-diagnostics \
  "$@" >"$messages"
# Each binary's "executable" (its .elf) from cargo's build messages.
mapfile -t images < <(python3 -c '
import json, sys
for line in open(sys.argv[1]):
    if line.startswith("{"):
        exe = json.loads(line).get("executable")
        if exe:
            print(exe)
' "$messages")
if [ ${#images[@]} -eq 0 ]; then
  echo "firmware: the build named no images" >&2
  exit 1
fi
keep=()
for elf in "${images[@]}"; do
  cp "$elf" "$out/"
  keep+=("$(basename "$elf")")
done
shopt -s nullglob
for old in "$out"/*.elf; do
  name=$(basename "$old")
  [[ " ${keep[*]} " == *" $name "* ]] || rm -f "$old"
done
ls "$out"
