#!/usr/bin/env bash
# Reports flash and static RAM of each firmware image against the limits in memory.x and
# fails if one does not fit. (The link step enforces the same limits; this makes them visible.)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
limit() { awk -v r="$1" '$1 == r { for (i = 1; i <= NF; i++) if ($i == "LENGTH") { v = $(i + 2); gsub(",", "", v); print v } }' "$root/memory.x"; }
flash_max=$(limit FLASH); ram_max=$(limit RAM); eeprom_max=$(limit EEPROM)
pct() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", 100 * a / b }'; }
status=0
printf '%-22s %8s %7s %8s %7s %7s\n' image flash "%" ram "%" eeprom
dir=${BLODWEN_FIRMWARE_DIR:-$root/target/firmware}
shopt -s nullglob
elves=("$dir"/*.elf)
if [ ${#elves[@]} -eq 0 ]; then
  echo "size-report: no firmware images in $dir; build them first: scripts/firmware.sh" >&2
  exit 1
fi
for elf in "${elves[@]}"; do
  # Captured first, so that a failing avr-size stops the script instead of reading as 0 B.
  sections=$(avr-size -A "$elf")
  read -r text data bss eep < <(printf '%s\n' "$sections" | awk '
    $1 == ".text" { t = $2 } $1 == ".data" { d = $2 } $1 == ".bss" { b = $2 } $1 == ".noinit" { b += $2 }
    $1 == ".eeprom" { e = $2 } END { print t + 0, d + 0, b + 0, e + 0 }')
  flash=$((text + data)); ram=$((data + bss))
  printf '%-22s %8d %6.1f%% %8d %6.1f%% %7d\n' "$(basename "$elf")" "$flash" \
    "$(pct "$flash" "$flash_max")" "$ram" "$(pct "$ram" "$ram_max")" "$eep"
  if [ "$flash" -gt "$flash_max" ] || [ "$ram" -gt "$ram_max" ] || [ "$eep" -gt "$eeprom_max" ]; then
    echo "  ^ does not fit memory.x (flash $flash_max, RAM $ram_max, EEPROM $eeprom_max)" >&2; status=1
  fi
done
echo "limits (memory.x): flash $flash_max B (32 KB less the 512 B bootloader), RAM $ram_max B, EEPROM $eeprom_max B"
exit $status
