//! The bench's marker functions in the step-bench ELF: a minimal reader of an ELF32 symbol
//! table (no dependency on an ELF crate).

use std::path::Path;

use anyhow::{anyhow, ensure, Context, Result};

/// Symbol of the function that opens a measured region.
pub const BEGIN_SYMBOL: &str = "step_bench_begin";
/// Symbol of the function that closes a measured region.
pub const END_SYMBOL: &str = "step_bench_end";

/// The marker functions' addresses (Thumb bit cleared).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Markers {
    /// Entry of [`BEGIN_SYMBOL`].
    pub begin: u64,
    /// Entry of [`END_SYMBOL`].
    pub end: u64,
}

fn u16_at(b: &[u8], o: usize) -> Result<u16> {
    Ok(u16::from_le_bytes(
        b.get(o..o + 2)
            .ok_or_else(|| anyhow!("ELF truncated"))?
            .try_into()?,
    ))
}

fn u32_at(b: &[u8], o: usize) -> Result<u32> {
    Ok(u32::from_le_bytes(
        b.get(o..o + 4)
            .ok_or_else(|| anyhow!("ELF truncated"))?
            .try_into()?,
    ))
}

/// The function symbols of a little-endian ELF32 file (`.symtab`): `(name, address)` with the
/// Thumb bit cleared. Errors: not an ELF32 little-endian file, or no symbol table.
pub fn elf32_functions(elf: &[u8]) -> Result<Vec<(String, u64)>> {
    ensure!(
        elf.len() > 52 && &elf[..4] == b"\x7fELF" && elf[4] == 1 && elf[5] == 1,
        "not a little-endian ELF32 file"
    );
    let shoff = u32_at(elf, 0x20)? as usize;
    let shentsize = u16_at(elf, 0x2e)? as usize;
    let shnum = u16_at(elf, 0x30)? as usize;
    let section = |i: usize| -> Result<(u32, usize, usize, u32, usize)> {
        let o = shoff + i * shentsize;
        Ok((
            u32_at(elf, o + 4)?,           // sh_type
            u32_at(elf, o + 16)? as usize, // sh_offset
            u32_at(elf, o + 20)? as usize, // sh_size
            u32_at(elf, o + 24)?,          // sh_link
            u32_at(elf, o + 36)? as usize, // sh_entsize
        ))
    };
    let mut out = Vec::new();
    for i in 0..shnum {
        let (kind, off, size, link, entsize) = section(i)?;
        if kind != 2 {
            continue; // SHT_SYMTAB only
        }
        let (_, str_off, str_size, _, _) = section(link as usize)?;
        let strtab = elf
            .get(str_off..str_off + str_size)
            .ok_or_else(|| anyhow!("ELF string table truncated"))?;
        let entsize = if entsize == 0 { 16 } else { entsize };
        for s in (off..off + size).step_by(entsize) {
            let name_off = u32_at(elf, s)? as usize;
            let value = u32_at(elf, s + 4)?;
            let info = *elf.get(s + 12).ok_or_else(|| anyhow!("ELF truncated"))?;
            if info & 0xf != 2 {
                continue; // STT_FUNC only
            }
            let end = strtab[name_off..]
                .iter()
                .position(|&c| c == 0)
                .map_or(strtab.len(), |p| name_off + p);
            let name = String::from_utf8_lossy(&strtab[name_off..end]).into_owned();
            out.push((name, u64::from(value & !1)));
        }
    }
    ensure!(
        !out.is_empty(),
        "the ELF has no function symbols (stripped?)"
    );
    Ok(out)
}

/// The addresses of the bench's marker functions in `elf`.
pub fn markers(elf: &Path) -> Result<Markers> {
    let bytes = std::fs::read(elf).with_context(|| format!("reading {}", elf.display()))?;
    let functions = elf32_functions(&bytes)?;
    // mps2-an386 runs code from SSRAM1 at 0; an entry in the STM32's flash (0x0800_0000)
    // means the ELF was linked with the wrong memory map and would lock up at reset.
    let entry = u32_at(&bytes, 0x18)?;
    ensure!(
        entry < 0x0040_0000,
        "{}: entry point {entry:#010x} is outside mps2-an386's code memory (0..4 MiB): \
         linked with another board's memory.x?",
        elf.display()
    );
    let find = |name: &str| {
        functions
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, a)| *a)
            .ok_or_else(|| anyhow!("{} has no symbol {name}", elf.display()))
    };
    Ok(Markers {
        begin: find(BEGIN_SYMBOL)?,
        end: find(END_SYMBOL)?,
    })
}
