//! The firmware's defmt log: the raw frames QEMU wrote to `defmt.bin` (semihosting), decoded
//! to text with the ELF's defmt table as `defmt-print -e <ELF> < defmt.bin` does, and the
//! firmware's 1 Hz counter lines read back from it.

use std::path::Path;

use anyhow::{anyhow, Context, Result};
use defmt_decoder::{DecodeError, Table};
use serde::Serialize;

/// A decoded defmt log.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DefmtLog {
    /// One line per log frame: `[timestamp ]LEVEL message` (no colours, no locations).
    pub lines: Vec<String>,
    /// Frames that did not decode (the rest of the stream is skipped when the encoding cannot
    /// resynchronise).
    pub malformed: usize,
    /// Bytes of raw log read.
    pub bytes: usize,
}

/// Decodes `raw` (defmt frames as the firmware's global logger wrote them) with the defmt
/// table of `elf` (the ELF file's bytes). Errors: the ELF has no `.defmt` section or a defmt
/// version the decoder does not support.
pub fn decode(elf: &[u8], raw: &[u8]) -> Result<DefmtLog> {
    let table = Table::parse(elf)
        .context("reading the ELF's defmt table")?
        .ok_or_else(|| anyhow!("the ELF has no .defmt section (not a defmt firmware?)"))?;
    let mut decoder = table.new_stream_decoder();
    decoder.received(raw);
    let mut log = DefmtLog {
        bytes: raw.len(),
        ..Default::default()
    };
    loop {
        match decoder.decode() {
            Ok(frame) => log.lines.push(frame.display(false).to_string()),
            Err(DecodeError::UnexpectedEof) => break,
            Err(DecodeError::Malformed) => {
                log.malformed += 1;
                if !table.encoding().can_recover() {
                    break;
                }
            }
        }
    }
    Ok(log)
}

/// [`decode`] of the files `elf` and `bin`. Errors: a file cannot be read, or as [`decode`].
pub fn decode_files(elf: &Path, bin: &Path) -> Result<DefmtLog> {
    let elf_bytes = std::fs::read(elf).with_context(|| format!("reading {}", elf.display()))?;
    let raw = std::fs::read(bin).with_context(|| format!("reading {}", bin.display()))?;
    decode(&elf_bytes, &raw)
}

/// The firmware's counters from its last 1 Hz `link:` and `pipeline:` log lines.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FirmwareCounters {
    /// MAVLink frames its decoder used (`HIL_SENSOR` included) / dropped / found malformed.
    pub link_frames: [u32; 3],
    /// Control ticks run.
    pub ticks: u32,
    /// Non-finite values counted.
    pub non_finite: u32,
    /// Commands and setpoints refused.
    pub refused: u32,
    /// Ticks in which the mixer gave something up.
    pub mixer_saturated: u32,
}

/// The number after `key ` in `line` (`"… frames ok 12 …"` with key `"ok"`).
fn number_after(line: &str, key: &str) -> Option<u32> {
    let pat = format!("{key} ");
    let at = line.find(&pat)? + pat.len();
    let digits: String = line[at..]
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

/// Reads the last `link: frames ok … dropped … malformed …` and `pipeline: ticks … non-finite
/// … refused … mixer-saturated …` lines (the firmware's 1 Hz counters); `None` unless both are
/// there.
pub fn counters(lines: &[String]) -> Option<FirmwareCounters> {
    let last = |prefix: &str| lines.iter().rev().find(|l| l.contains(prefix));
    let link = last("link: frames ok ")?;
    let pipe = last("pipeline: ticks ")?;
    Some(FirmwareCounters {
        link_frames: [
            number_after(link, "ok")?,
            number_after(link, "dropped")?,
            number_after(link, "malformed")?,
        ],
        ticks: number_after(pipe, "ticks")?,
        non_finite: number_after(pipe, "non-finite")?,
        refused: number_after(pipe, "refused")?,
        mixer_saturated: number_after(pipe, "mixer-saturated")?,
    })
}

/// The control task's overruns since boot, from the last 1 Hz `timing: … overruns N (total M)`
/// line (`M`); `None` if there is none. In the lockstep a step overruns when it takes longer
/// than one law period on the board's embassy-time clock (`firmware::timing::is_overrun` with
/// zero lateness): on QEMU that clock is the SysTick millisecond count on QEMU's virtual
/// clock, which [`crate::harness::qemu::ICOUNT`] ties to the instructions run (8 ns each), so
/// a step overruns when it runs more than a period's worth of instructions (125 000 at 1 kHz),
/// however fast the host emulates it. The count is up to 1 s old at the end of a run.
pub fn overruns(lines: &[String]) -> Option<u32> {
    let line = lines.iter().rev().find(|l| l.contains("timing: "))?;
    number_after(line, "(total")
}

/// The longest control step \[µs\] of the whole log, from the 1 Hz `timing: … longest step N us`
/// lines, on the same clock as [`overruns`] (on QEMU: instructions run × 8 ns); `None` if no
/// line has it. The last window, up to 1 s, is not in the log.
pub fn longest_step_us(lines: &[String]) -> Option<u32> {
    lines
        .iter()
        .filter(|l| l.contains("timing: "))
        .filter_map(|l| number_after(l, "longest step"))
        .max()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counters_from_the_last_lines() {
        let lines: Vec<String> = [
            "0.000 INFO link: frames ok 1 dropped 0 malformed 0, bytes discarded 0; telemetry dropped 0",
            "1.000 INFO pipeline: ticks 100 imu 1000 poses 98 non-finite 0 refused 0 mixer-saturated 0 events dropped 0",
            "2.000 INFO link: frames ok 2100 dropped 3 malformed 1, bytes discarded 9; telemetry dropped 0",
            "2.000 INFO pipeline: ticks 200 imu 2000 poses 196 non-finite 2 refused 1 mixer-saturated 5 events dropped 0",
        ]
        .map(String::from)
        .to_vec();
        assert_eq!(
            counters(&lines),
            Some(FirmwareCounters {
                link_frames: [2100, 3, 1],
                ticks: 200,
                non_finite: 2,
                refused: 1,
                mixer_saturated: 5,
            })
        );
        assert_eq!(counters(&lines[..1]), None);
    }

    #[test]
    fn overruns_from_the_last_timing_line() {
        let lines: Vec<String> = [
            "1.000 INFO timing: 1000 steps, mean 0 cyc (0 us), max 0 cyc (0 us), longest step 180 us, overruns 2 (total 2)",
            "1.000 INFO io: imu reads 0 errors 0",
            "2.000 INFO timing: 1000 steps, mean 0 cyc (0 us), max 0 cyc (0 us), longest step 95 us, overruns 1 (total 3)",
        ]
        .map(String::from)
        .to_vec();
        assert_eq!(overruns(&lines), Some(3));
        assert_eq!(overruns(&lines[..2]), Some(2));
        assert_eq!(overruns(&lines[1..2]), None);
        assert_eq!(longest_step_us(&lines), Some(180));
        assert_eq!(longest_step_us(&lines[1..]), Some(95));
        assert_eq!(longest_step_us(&lines[1..2]), None);
    }

    #[test]
    fn an_elf_without_defmt_is_refused() {
        assert!(decode(b"not an elf", &[]).is_err());
    }
}
