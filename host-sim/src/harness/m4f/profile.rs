//! Instructions per function over the measured regions, from the plugin's block profile.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use anyhow::Result;

use super::elf::elf32_functions;

/// A per-function profile of the measured regions from the plugin's block profile
/// (`tb <addr> <insns> <execs>` lines): instructions per function (the innermost symbol
/// covering each block; inlined code counts for its caller), most first. Function names are
/// demangled with `nm -C` when binutils is installed.
pub fn profile(elf: &Path, profile: &str, top: usize) -> Result<String> {
    let mut functions: Vec<(u64, String)> = match Command::new("nm").arg("-nC").arg(elf).output() {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout)
            .lines()
            .filter_map(|l| {
                let mut p = l.splitn(3, ' ');
                let a = u64::from_str_radix(p.next()?, 16).ok()?;
                let t = p.next()?;
                let name = p.next()?;
                (matches!(t, "t" | "T" | "w" | "W") && !name.starts_with('$'))
                    .then(|| (a & !1, name.to_string()))
            })
            .collect(),
        _ => {
            let bytes = std::fs::read(elf)?;
            elf32_functions(&bytes)?
                .into_iter()
                .map(|(n, a)| (a, n))
                .collect()
        }
    };
    functions.sort();
    let mut per: BTreeMap<String, u64> = BTreeMap::new();
    let mut total = 0u64;
    for line in profile.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        if f.len() != 4 || f[0] != "tb" {
            continue;
        }
        let pc = u64::from_str_radix(f[1].trim_start_matches("0x"), 16)?;
        let n: u64 = f[2].parse::<u64>()? * f[3].parse::<u64>()?;
        total += n;
        let i = functions.partition_point(|(a, _)| *a <= pc);
        let name = if i == 0 {
            "?".to_string()
        } else {
            functions[i - 1].1.clone()
        };
        *per.entry(name).or_default() += n;
    }
    let mut v: Vec<(String, u64)> = per.into_iter().collect();
    v.sort_by_key(|e| std::cmp::Reverse(e.1));
    let mut s = format!("profile of all measured regions: {total} instructions\n");
    for (name, n) in v.into_iter().take(top) {
        let _ = writeln!(
            s,
            "{n:>10} {:>5.1} %  {}",
            100.0 * n as f64 / total.max(1) as f64,
            name.chars().take(140).collect::<String>()
        );
    }
    Ok(s)
}
