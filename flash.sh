#!/usr/bin/env bash
# Builds a Blodwen board's firmware and uploads it with avrdude: the master through the
# Uno's USB bootloader, a slave through an ICSP programmer, with its I2C address N written
# to EEPROM byte 0. With --dry-run the same avrdude command runs against programmer-sim,
# an emulated programmer on a pseudo-terminal, and the images it captured are kept.
set -euo pipefail
root=$(cd "$(dirname "$0")" && pwd)
cd "$root"

usage() {
  cat <<'EOF'
Usage: ./flash.sh [--dry-run] [--force] [--port P] [--programmer PROG] [--baud B] ROLE [N]

Builds the firmware for ROLE and uploads it with avrdude.

Roles:
  master          the Arduino Uno master board (no N): avrdude -c arduino -b 115200 -D,
                  through the Uno's USB bootloader
  slave-drive N   a drive/steer slave, controller N in 1, 2, 4, 5, 7, 8
  slave-lift N    a lift/lift slave, controller N in 3, 6, 9
Slaves are written through an ICSP programmer (avrdude -c stk500v1 -b 19200 by default,
i.e. an Uno running ArduinoISP); N goes to EEPROM byte 0 as the board's I2C address.

Options:
  --dry-run         run the same avrdude command against programmer-sim, an emulated
                    programmer on a pseudo-terminal, instead of a board; the captured
                    images land in target/flash-dry-run/ROLE[-N]/{flash,eeprom}.bin
  --force           accept a controller number that does not match the role
                    (N must still be 1..9)
  --port P          serial port (default /dev/ttyACM0; for USB programmers use "usb")
  --programmer PROG avrdude programmer id for slaves (default $PROGRAMMER, else stk500v1);
                    e.g. avrisp (same as stk500v1), usbasp (--port usb), usbtiny, avrispmkII
  --baud B          serial speed (default 115200 for master, 19200 for slaves)
  -h, --help        show this help

Exit status: 0 uploaded (or dry run captured and verified), 1 build or upload failed,
2 bad arguments or refused role/controller.
Needs avrdude and avr-objcopy: run scripts/setup.sh if they are missing.
EOF
}

die() { # usage or validation error: say how to fix it
  echo "flash.sh: $*" >&2
  echo "Run './flash.sh --help' for usage." >&2
  exit 2
}
fail() {
  echo "flash.sh: $*" >&2
  exit 1
}

dry_run=0
force=0
port=/dev/ttyACM0
programmer=
baud=
args=()
while [ $# -gt 0 ]; do
  case $1 in
    -h | --help) usage; exit 0 ;;
    --dry-run) dry_run=1 ;;
    --force) force=1 ;;
    --port | --programmer | --baud)
      if [ $# -lt 2 ] || [ -z "$2" ]; then die "$1 needs a value"; fi
      case $1 in
        --port) port=$2 ;;
        --programmer) programmer=$2 ;;
        --baud) baud=$2 ;;
      esac
      shift
      ;;
    --port=* | --programmer=* | --baud=*)
      value=${1#*=}
      [ -n "$value" ] || die "${1%%=*} needs a value"
      case $1 in
        --port=*) port=$value ;;
        --programmer=*) programmer=$value ;;
        --baud=*) baud=$value ;;
      esac
      ;;
    --) shift; args+=("$@"); break ;;
    -*) die "unknown option '$1'" ;;
    *) args+=("$1") ;;
  esac
  shift
done

# ---- validate everything before building anything ----
[ ${#args[@]} -ge 1 ] || die "missing ROLE (master, slave-drive N or slave-lift N)"
role=${args[0]}
addr=${args[1]:-}
[ ${#args[@]} -le 2 ] || die "too many arguments: ${args[*]}"
if [ -n "$baud" ] && ! [[ $baud =~ ^[1-9][0-9]*$ ]]; then
  die "--baud '$baud' is not a number (e.g. --baud 19200)"
fi

case $role in
  master)
    [ -z "$addr" ] || die "the master has no I2C address: drop '$addr' (run './flash.sh master')"
    [ -z "$programmer" ] || [ "$programmer" = arduino ] ||
      die "the master is written through its USB bootloader (-c arduino); --programmer applies to slaves only"
    programmer=arduino
    baud=${baud:-115200}
    ;;
  slave-drive | slave-lift)
    [ -n "$addr" ] || die "$role needs its controller number N, e.g. './flash.sh $role $([ "$role" = slave-lift ] && echo 3 || echo 1)'"
    [[ $addr =~ ^[0-9]+$ ]] || die "controller number '$addr' is not a number: use 1..9"
    # Strip leading zeros so "03" is 3; anything longer than one digit is then >= 10.
    addr=${addr#"${addr%%[!0]*}"}
    addr=${addr:-0}
    if [ ${#addr} -gt 1 ] || [ "$addr" -lt 1 ]; then
      die "controller number $addr is out of range: the master talks to controllers 1..9 (drive/steer 1, 2, 4, 5, 7, 8; lift 3, 6, 9)"
    fi
    case $addr in
      3 | 6 | 9) wanted=slave-lift ;;
      *) wanted=slave-drive ;;
    esac
    if [ "$role" != "$wanted" ]; then
      if [ $force -eq 1 ]; then
        echo "flash.sh: warning: controller $addr is a $wanted board; writing $role anyway (--force)" >&2
      else
        die "controller $addr is a $wanted board (lift boards are 3, 6, 9; drive/steer boards 1, 2, 4, 5, 7, 8): run './flash.sh $wanted $addr', or add --force to write $role to it anyway"
      fi
    fi
    programmer=${programmer:-${PROGRAMMER:-stk500v1}}
    baud=${baud:-19200}
    ;;
  *) die "unknown role '$role': use master, slave-drive N or slave-lift N" ;;
esac

if [ $dry_run -eq 1 ]; then
  case $programmer in
    arduino | stk500v1 | avrisp) ;;
    *) die "--dry-run emulates STK500 v1 programmers only (arduino, stk500v1, avrisp), not '$programmer'" ;;
  esac
fi

for tool in avrdude avr-objcopy; do
  command -v "$tool" >/dev/null || fail "$tool not found: run scripts/setup.sh to install the AVR tools"
done

# A real upload needs the board now: check the port before the build, so a missing board
# costs no build and leaves the last outputs in place. (avrdude's usb and net: ports are
# not device files; it checks those itself.)
if [ $dry_run -eq 0 ] && [[ $port == /* ]]; then
  [ -e "$port" ] || die "no serial port $port: plug the board in, or pass --port PATH (ls /dev/ttyACM* /dev/ttyUSB*)"
  [ -r "$port" ] && [ -w "$port" ] ||
    die "cannot open $port for reading and writing: add yourself to its group (ls -l $port; often dialout) or run as root"
fi

# ---- build and convert ----
name=$role${addr:+-$addr}
if [ $dry_run -eq 1 ]; then dir=target/flash-dry-run/$name; else dir=target/flash/$name; fi
mkdir -p "$dir"
rm -f "$dir"/{image.elf,flash.hex,eeprom.hex,eeprom-byte.bin,flash.bin,eeprom.bin,log.json,sim.out,sim.err}

echo "flash.sh: building firmware (scripts/firmware.sh)" >&2
scripts/firmware.sh >/dev/null || fail "firmware build failed (see the cargo errors above)"
elf=${BLODWEN_FIRMWARE_DIR:-target/firmware}/$role.elf
[ -f "$elf" ] || fail "$elf was not produced by scripts/firmware.sh"
# Work from a private copy so a parallel build cannot change the image under us.
cp "$elf" "$dir/image.elf"
avr-objcopy -O ihex -j .text -j .data "$dir/image.elf" "$dir/flash.hex"

if [ "$role" != master ]; then
  printf '%b' "\\0$(printf '%03o' "$addr")" >"$dir/eeprom-byte.bin"
  avr-objcopy -I binary -O ihex "$dir/eeprom-byte.bin" "$dir/eeprom.hex"
fi

# The avrdude command for a port; the dry run differs from the real upload only in -P.
make_cmd() {
  cmd=(avrdude -p m328p -c "$programmer" -P "$1" -b "$baud")
  if [ "$role" = master ]; then
    # The bootloader cannot erase the chip; pages are rewritten in place.
    cmd+=(-D -U "flash:w:$dir/flash.hex:i")
  else
    cmd+=(-U "flash:w:$dir/flash.hex:i" -U "eeprom:w:$dir/eeprom.hex:i")
  fi
}
make_cmd "$port"

if [ $dry_run -eq 0 ]; then
  echo "flash.sh: running: ${cmd[*]}" >&2
  "${cmd[@]}" || fail "avrdude failed: check the cable, --port ($port) and --programmer ($programmer)"
  echo "flash.sh: $name written" >&2
  exit 0
fi

# ---- dry run: the same command against the emulated programmer ----
echo "flash.sh: building programmer-sim" >&2
cargo build -q -p programmer-sim || fail "programmer-sim build failed"
sim=${CARGO_TARGET_DIR:-$root/target}/debug/programmer-sim
if [ "$programmer" = arduino ]; then mode=bootloader; else mode=isp; fi

"$sim" --out "$dir" --mode "$mode" --idle-timeout 60 >"$dir/sim.out" 2>"$dir/sim.err" &
sim_pid=$!
stop_sim() { kill -TERM "$sim_pid" 2>/dev/null || true; }
trap stop_sim EXIT

pty=
for _ in $(seq 100); do
  pty=$(head -n 1 "$dir/sim.out" 2>/dev/null || true)
  [ -n "$pty" ] && break
  kill -0 "$sim_pid" 2>/dev/null || fail "programmer-sim exited early: $(cat "$dir/sim.err")"
  sleep 0.05
done
[ -n "$pty" ] || fail "programmer-sim printed no pseudo-terminal path within 5 s"

echo "flash.sh: on a board this runs: ${cmd[*]}" >&2
make_cmd "$pty"
echo "flash.sh: dry run, running:     ${cmd[*]}" >&2
echo "flash.sh: (avrdude's TIOCMGET warnings are expected: a pseudo-terminal has no DTR/RTS lines)" >&2
status=0
"${cmd[@]}" || status=$?

# avrdude has closed the port, so the simulator saves its images and exits by itself.
for _ in $(seq 100); do
  kill -0 "$sim_pid" 2>/dev/null || break
  sleep 0.05
done
stop_sim
sim_status=0
wait "$sim_pid" || sim_status=$?
trap - EXIT
cat "$dir/sim.err" >&2

[ $status -eq 0 ] || fail "avrdude failed against programmer-sim (exit $status); the simulator's log is $dir/log.json"
[ $sim_status -eq 0 ] || fail "programmer-sim failed (exit $sim_status)"
if ! [ -f "$dir/flash.bin" ] || ! [ -f "$dir/eeprom.bin" ]; then
  fail "programmer-sim saved no images in $dir"
fi
echo "flash.sh: dry run of $name passed: avrdude wrote and verified; captured images:"
echo "  $dir/flash.bin   (32 KB flash, unwritten bytes 0xff)"
echo "  $dir/eeprom.bin  (1 KB EEPROM$([ "$role" = master ] && echo ", untouched" || echo ", byte 0 = $addr"))"
echo "  $dir/log.json    (every command the programmer received)"
