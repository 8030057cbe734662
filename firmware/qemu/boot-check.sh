#!/usr/bin/env bash
# Boots the mps2-an386 firmware under QEMU with nothing on its serial port and checks that it
# is still running after a few seconds (a panic or a hard fault ends QEMU with status 1 through
# semihosting) and that it wrote its defmt boot log to the semihosting console.
#   bash firmware/qemu/boot-check.sh ELF
set -euo pipefail
elf="$1"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
status=0
timeout 5 qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -display none -monitor none \
  -serial null -semihosting-config enable=on,target=native,chardev=defmt \
  -chardev file,id=defmt,path="$log" -kernel "$elf" </dev/null || status=$?
if [ "$status" -ne 124 ]; then
  echo "boot-check: QEMU ended with status $status before the timeout (crash or exit)" >&2
  exit 1
fi
bytes=$(stat -c %s "$log")
if [ "$bytes" -lt 500 ]; then
  echo "boot-check: only $bytes bytes of defmt log (expected the boot banner)" >&2
  exit 1
fi
echo "boot-check: running after 5 s, $bytes bytes of defmt boot log"
