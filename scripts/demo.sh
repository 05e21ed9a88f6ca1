#!/usr/bin/env bash
# The main job: set up, build the firmware images and the host tools, start the rover
# twin (the real master image in the emulator, behind a pseudo-terminal), and drive it
# with hostctl exactly as a real rover on /dev/ttyACM0 would be driven.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

scripts/setup.sh
scripts/firmware.sh >/dev/null
cargo build --release -q -p twin -p hostctl
bin=$root/target/release

port=$root/target/rover.pty
"$bin/twin" --link "$port" --stats 5 &
twin=$!
trap 'kill $twin 2>/dev/null; wait $twin 2>/dev/null || true' EXIT
for _ in $(seq 50); do [ -e "$port" ] && break; sleep 0.1; done

run() {
  printf '\n$ hostctl %s\n' "$*"
  "$bin/hostctl" --port "$port" --settle-ms 0 "$@"
}

# Opening the port resets the master, as on the Uno: each hostctl call sees a fresh
# banner and a master in its boot exception (EXCEPTIONDATA 2) until it is reset.
run write 0 REGMASTER_RESET 1
run readset --device 0 5 TEMPAMBIENT EXCEPTIONDATA LASTERROR ERRORCOUNT
run watch --readset 2 --device 0 --count 3
# Bad input is refused before anything is sent:
run write 0 TEMP1 20 || true
run write 1 DRIVE_REQSPEED 5000 || true
run read 0 NOSUCHREG || true
