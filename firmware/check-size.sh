#!/usr/bin/env bash
# Size budget of the release firmware: flash (vector table + text + rodata + the load image of
# .data) <= 384 KiB, static RAM (.data + .bss + .uninit, stack excluded) <= 64 KiB. Our budget,
# not the chip's: the STM32F405RG has 1 MiB of flash and 128 KiB of SRAM (boards/stm32f405/
# memory.x); half the RAM is left to the stack. Per-package opt-levels: the workspace Cargo.toml.
#
#   bash firmware/check-size.sh            # builds the release ELF (cargo fw-build), then checks it
#   bash firmware/check-size.sh PATH/ELF   # checks an ELF that is already built
#
# Reads the section table with binutils' `size -A` (installed with gcc); exits 1 over budget.
set -euo pipefail

# 384 KiB since the on-board certificate grew to re-check airmode's shadow fits, the envelope
# design's local regime and the vertical channel (docs/firmware-board.md#size-budget).
FLASH_BUDGET=$((384 * 1024))
RAM_BUDGET=$((64 * 1024))
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

if [ $# -ge 1 ]; then
  elf="$1"
else
  (cd "$root" && cargo fw-build)
  target_dir="${CARGO_TARGET_DIR:-$root/target}"
  case "$target_dir" in /*) ;; *) target_dir="$root/$target_dir" ;; esac
  elf="$target_dir/thumbv7em-none-eabihf/release/firmware"
fi

size -A "$elf" | awk -v flash_budget="$FLASH_BUDGET" -v ram_budget="$RAM_BUDGET" '
  $1 == ".vector_table" || $1 == ".text" || $1 == ".rodata" { flash += $2 }
  $1 == ".data" { flash += $2; ram += $2 }
  $1 == ".bss" || $1 == ".uninit" { ram += $2 }
  END {
    printf "firmware flash: %d B (%.1f KiB) of %.0f KiB\n", flash, flash / 1024, flash_budget / 1024
    printf "firmware static RAM: %d B (%.1f KiB) of %.0f KiB\n", ram, ram / 1024, ram_budget / 1024
    if (flash == 0) { print "check-size: no .text section found"; exit 1 }
    if (flash > flash_budget || ram > ram_budget) { print "check-size: OVER BUDGET"; exit 1 }
  }'
