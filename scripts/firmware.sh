#!/usr/bin/env bash
# Builds every AVR image (nightly, avr-none, atmega328p, -Zbuild-std=core) and copies
# the ELF files to target/firmware/, the fixed paths that tests, the twin and flash.sh use
# (or to $BLODWEN_FIRMWARE_DIR, which the harness reads too).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
tdir=${CARGO_TARGET_DIR:-$root/target}
out=${BLODWEN_FIRMWARE_DIR:-$root/target/firmware}
mkdir -p "$out"
cargo +nightly build --target avr-none -Zbuild-std=core --profile avr \
  -p master -p slave -p firmware-examples -p drivers "$@"
for elf in "$tdir"/avr-none/avr/*.elf; do
  cp "$elf" "$out/"
done
ls "$out"
