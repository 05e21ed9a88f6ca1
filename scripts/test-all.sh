#!/usr/bin/env bash
# Sets up the machine and runs every check: formatting, clippy (host and firmware), the
# firmware builds, host unit/property tests, emulator tests of the real images, the main
# job (scripts/demo.sh), and the size report against memory.x. `.ci/run` calls exactly
# this.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
step() { printf '\n==> %s\n' "$*"; }
start=$(date +%s)

step "set-up"
scripts/setup.sh

host_pkgs=(--workspace --exclude master --exclude slave --exclude firmware-examples --exclude drivers)
avr=(--target avr-none -Zbuild-std=core --profile avr)

step "format"
cargo fmt --all --check

step "clippy (host)"
cargo clippy "${host_pkgs[@]}" --all-targets -- -D warnings

step "firmware images"
scripts/firmware.sh

step "clippy (firmware, nightly)"
cargo +nightly clippy "${avr[@]}" -p master -p slave -p firmware-examples -p drivers -p executor -p shared -- -D warnings

step "tests (host logic and emulator)"
cargo test "${host_pkgs[@]}"

step "the main job (scripts/demo.sh: the twin driven by hostctl), last lines"
# The README's first command, end to end, so it cannot break unseen.
scripts/demo.sh | tail -n 20

step "size report"
scripts/size-report.sh

echo "test-all: everything passed in $(( $(date +%s) - start )) s"
