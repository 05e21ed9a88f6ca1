#!/usr/bin/env bash
# The main job, from nothing: set up this machine, build the firmware images and the host
# tools, start the rover twin (the real master and nine slave images in the emulator, on one
# I2C bus, with the rover's physics around them, behind a pseudo-terminal), and drive it with
# `hostctl run examples/demo.rover`: calibrate, reset the exceptions, drive forward at 1000,
# turn 40, lift a leg, stop, while a live view shows required against actual speeds and
# positions. Every number on screen is read back from the emulated boards over the serial
# line. Then it stops the twin and prints the twin's own speed report.
# Arguments go to the twin, e.g. `scripts/demo.sh --threads 1` (see `twin --help`).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

scripts/setup.sh
echo "demo: building the firmware images (scripts/firmware.sh)"
if ! scripts/firmware.sh >"$work/firmware.log" 2>&1; then
  cat "$work/firmware.log" >&2
  exit 1
fi
echo "demo: building twin and hostctl"
cargo build --release -q -p twin -p hostctl
bin=${CARGO_TARGET_DIR:-$root/target}/release

port=$work/port
"$bin/twin" --link "$port" --stats 5 "$@" >"$work/pty" 2>"$work/twin.log" &
twin=$!
stop_twin() {
  kill "$twin" 2>/dev/null || true
  wait "$twin" 2>/dev/null || true
}
trap 'stop_twin; rm -rf "$work"' EXIT
# Ready once it has made the link and printed the pty's path; a twin that dies on the way
# is reported at once, not after the wait.
for _ in $(seq 200); do
  [ -e "$port" ] && [ -s "$work/pty" ] && break
  kill -0 "$twin" 2>/dev/null || break
  sleep 0.1
done
if [ ! -e "$port" ] || [ ! -s "$work/pty" ]; then
  echo "demo: the twin did not start:" >&2
  cat "$work/twin.log" >&2
  exit 1
fi
echo "demo: the twin serves $(head -n1 "$work/pty") (link $port)"
echo

# One connection for the whole drive: opening the port resets the master, as on the Uno.
"$bin/hostctl" --port "$port" run examples/demo.rover

echo
stop_twin
echo "demo: the twin's own report (emulated time against wall-clock time):"
# Its report lines read "twin: E s emulated in W s, …"; none is no failure of the demo.
grep 'emulated in' "$work/twin.log" | tail -n 2 | sed 's/^/  /' || true
