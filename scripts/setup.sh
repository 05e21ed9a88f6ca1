#!/usr/bin/env bash
# Installs everything the project needs beyond stable Rust, gcc and Python, idempotently:
# Debian packages for the AVR toolchain and the emulator bindings, and the nightly's rust-src.
# Run as root (or with sudo available). Safe to run again: it installs only what is missing.
set -euo pipefail

packages=(
  gcc-avr binutils-avr avr-libc # firmware linker and libc for the ATmega328P
  avrdude                       # flash.sh
  libelf-dev libzstd-dev libclang-dev pkg-config make # simavr-ffi builds simavr from source
  libudev-dev                   # serialport (hostctl)
)

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"
  elif command -v sudo >/dev/null; then sudo "$@"
  else echo "setup: need root to run: $*" >&2; exit 1
  fi
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
else
  echo "setup: Debian packages present"
fi

if ! rustup toolchain list | grep -q '^nightly'; then
  echo "setup: the 'nightly' toolchain is missing; it is part of the machine image and cannot be fetched here" >&2
  exit 1
fi
for c in rust-src clippy rustfmt; do
  rustup component list --toolchain nightly --installed 2>/dev/null | grep -q "^$c" \
    || rustup component add "$c" --toolchain nightly
done
for c in clippy rustfmt; do
  rustup component list --installed 2>/dev/null | grep -q "^$c" || rustup component add "$c"
done
# A full build and test run writes about 4 GB into target/; a linker that runs out of disk
# dies with an obscure "Bus error", so say it plainly first.
need_mb=4500
target_parent=${CARGO_TARGET_DIR:-$(cd "$(dirname "$0")/.." && pwd)/target}
probe=$target_parent
while [ ! -d "$probe" ]; do probe=$(dirname "$probe"); done
free_mb=$(df -Pm "$probe" | awk 'NR==2 {print $4}')
if [ "${free_mb:-0}" -lt "$need_mb" ]; then
  echo "setup: only ${free_mb} MB free under $probe; a full build needs about ${need_mb} MB." >&2
  echo "setup: free some space (an old target/ directory: cargo clean) and run again." >&2
  exit 1
fi
echo "setup: done (${free_mb} MB free for target/)"
