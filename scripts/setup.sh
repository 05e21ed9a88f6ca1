#!/usr/bin/env bash
# Installs everything the project needs beyond stable Rust, gcc and Python, idempotently:
# Debian packages for the AVR toolchain and the emulator bindings, and the nightly's rust-src.
# Run as root (or with sudo available). Safe to run again: it installs only what is missing.
set -euo pipefail

packages=(
  gcc-avr binutils-avr avr-libc # firmware linker and libc for the ATmega328P
  avrdude                       # flash.sh
  libelf-dev libzstd-dev zlib1g-dev libclang-dev pkg-config make # simavr-ffi builds simavr from source
)

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"
  elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then sudo "$@"
  else
    echo "setup: installing Debian packages needs root, and sudo is not available without a password here." >&2
    echo "setup: run 'sudo scripts/setup.sh' (or as root), or install them yourself:" >&2
    echo "setup:   apt-get install ${missing[*]}" >&2
    exit 1
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

# The firmware builds with `cargo +nightly`: a toolchain named exactly `nightly` (a dated
# nightly-YYYY-MM-DD alone does not answer to that name).
if ! rustup run nightly rustc -V >/dev/null 2>&1; then
  echo "setup: no toolchain named 'nightly'; it is part of the machine image and cannot be fetched here" >&2
  echo "setup: (rustup toolchain list shows what is installed)" >&2
  exit 1
fi
# add_component TOOLCHAIN COMPONENT: installs it unless present, saying plainly what failed.
add_component() {
  rustup component list --toolchain "$1" --installed 2>/dev/null | grep -q "^$2" && return 0
  echo "setup: adding $2 to the $1 toolchain"
  if ! rustup component add "$2" --toolchain "$1"; then
    echo "setup: could not add $2 to $1 (rustup could not download it?);" >&2
    echo "setup: run 'rustup component add $2 --toolchain $1' where it can, then run this again" >&2
    exit 1
  fi
}
# Nightly: rust-src for -Zbuild-std=core, clippy for the firmware lints. Stable: the host
# build's formatting and lints.
add_component nightly rust-src
add_component nightly clippy
stable=$(rustup show active-toolchain | cut -d' ' -f1)
add_component "$stable" clippy
add_component "$stable" rustfmt
# A full build and test run writes about 4 GB into target/; a linker that runs out of disk
# dies with an obscure "Bus error", so say it plainly first.
# What target/ holds already counts towards it: a built tree needs little more.
need_mb=4500
target_parent=${CARGO_TARGET_DIR:-$(cd "$(dirname "$0")/.." && pwd)/target}
if [ -d "$target_parent" ]; then
  have_mb=$(du -sm "$target_parent" 2>/dev/null | cut -f1)
  need_mb=$(( need_mb > ${have_mb:-0} + 500 ? need_mb - ${have_mb:-0} : 500 ))
fi
probe=$target_parent
while [ ! -d "$probe" ]; do probe=$(dirname "$probe"); done
free_mb=$(df -Pm "$probe" | awk 'NR==2 {print $4}')
if [ "${free_mb:-0}" -lt "$need_mb" ]; then
  echo "setup: only ${free_mb} MB free under $probe; a full build needs about ${need_mb} MB more." >&2
  echo "setup: free some space (an old target/ directory: cargo clean) and run again." >&2
  exit 1
fi
echo "setup: done (${free_mb} MB free for target/)"
