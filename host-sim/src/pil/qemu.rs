//! The emulated flight controller: `qemu-system-arm -machine mps2-an386` running the firmware
//! ELF, its serial port 0 on QEMU's stdin/stdout (raw bytes), its defmt log (semihosting) in a
//! file. [`Qemu`] spawns it, writes stdin from the caller's thread, reads stdout on a thread
//! that feeds a channel (so waiting has a timeout), and kills and reaps QEMU when dropped.

use std::ffi::OsString;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};

/// What a wait on the serial output gave.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Received {
    /// Bytes from the firmware's serial port (any chunking).
    Bytes(Vec<u8>),
    /// Nothing within the timeout.
    Timeout,
    /// The output closed: the emulator (or the fake firmware) exited.
    Closed,
}

/// A byte link to the flight software under test: the emulator's serial port, or an
/// in-process fake in tests.
pub trait Transport {
    /// Sends bytes to the firmware's serial port. Blocking is backpressure. Errors: the link
    /// is gone (the emulator exited).
    fn send(&mut self, bytes: &[u8]) -> Result<()>;
    /// Waits at most `timeout` for bytes from the firmware.
    fn receive(&mut self, timeout: Duration) -> Received;
    /// Why the link closed, for an error message: exit status, log tail (empty if unknown).
    fn post_mortem(&mut self) -> String;
}

/// The QEMU command line for `elf` with the defmt log going to `defmt_path` (the one place
/// the arguments are written). `-serial stdio`: UART 0 on stdin/stdout;
/// `-semihosting-config … chardev=defmt`: semihosting output (defmt frames and the exit call)
/// to a file chardev.
pub fn qemu_args(elf: &Path, defmt_path: &Path) -> Vec<OsString> {
    let mut chardev = OsString::from("file,id=defmt,path=");
    chardev.push(defmt_path.as_os_str());
    [
        "-machine",
        "mps2-an386",
        "-cpu",
        "cortex-m4",
        "-display",
        "none",
        "-monitor",
        "none",
        "-serial",
        "stdio",
        "-semihosting-config",
        "enable=on,target=native,chardev=defmt",
        "-chardev",
    ]
    .into_iter()
    .map(OsString::from)
    .chain([
        chardev,
        OsString::from("-kernel"),
        elf.as_os_str().to_owned(),
    ])
    .collect()
}

/// Turns the defmt file at a path into text lines.
type LogDecoder = Box<dyn Fn(&Path) -> Vec<String>>;

/// A running QEMU. Dropping it kills and reaps the process (also on error paths).
pub struct Qemu {
    child: Child,
    stdin: Option<ChildStdin>,
    output: Receiver<Vec<u8>>,
    reader: Option<JoinHandle<()>>,
    /// Exit status once known.
    status: Option<ExitStatus>,
    /// The QEMU binary and the defmt file, for messages.
    binary: PathBuf,
    defmt_path: PathBuf,
    /// Turns the defmt file into text lines for a post-mortem (set by the caller).
    decode_tail: Option<LogDecoder>,
}

impl Qemu {
    /// Starts `binary` (e.g. `qemu-system-arm`) on `elf`, the defmt log going to
    /// `defmt_path`. Errors: the binary cannot be started (not installed?).
    pub fn spawn(binary: &Path, elf: &Path, defmt_path: &Path) -> Result<Self> {
        let mut child = Command::new(binary)
            .args(qemu_args(elf, defmt_path))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .with_context(|| {
                format!(
                    "cannot start {} (install it, e.g. `apt install qemu-system-arm`, or pass \
                     --qemu)",
                    binary.display()
                )
            })?;
        let stdin = child.stdin.take();
        let mut stdout = child.stdout.take().context("QEMU stdout not piped")?;
        let (tx, rx) = mpsc::channel();
        let reader = std::thread::Builder::new()
            .name("qemu-serial".into())
            .spawn(move || {
                let mut buf = vec![0u8; 8192];
                loop {
                    match stdout.read(&mut buf) {
                        Ok(0) | Err(_) => break,
                        Ok(n) => {
                            if tx.send(buf[..n].to_vec()).is_err() {
                                break;
                            }
                        }
                    }
                }
            })
            .context("cannot start the serial reader thread")?;
        Ok(Self {
            child,
            stdin,
            output: rx,
            reader: Some(reader),
            status: None,
            binary: binary.to_owned(),
            defmt_path: defmt_path.to_owned(),
            decode_tail: None,
        })
    }

    /// The process id.
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// Sets how a post-mortem turns the defmt file into text lines.
    pub fn set_log_decoder(&mut self, decode: impl Fn(&Path) -> Vec<String> + 'static) {
        self.decode_tail = Some(Box::new(decode));
    }

    /// Waits up to `timeout` for QEMU to exit by itself; its status if it did.
    pub fn wait_exit(&mut self, timeout: Duration) -> Option<ExitStatus> {
        let end = Instant::now() + timeout;
        while self.status.is_none() {
            match self.child.try_wait() {
                Ok(Some(s)) => self.status = Some(s),
                Ok(None) if Instant::now() < end => std::thread::sleep(Duration::from_millis(10)),
                _ => break,
            }
        }
        self.status
    }

    /// Stops QEMU (kill, then reap) unless it already exited; its exit status. Idempotent.
    /// The defmt file is complete afterwards.
    pub fn stop(&mut self) -> Option<ExitStatus> {
        self.stdin = None;
        if self.status.is_none() {
            if let Ok(Some(s)) = self.child.try_wait() {
                self.status = Some(s);
            } else {
                let _ = self.child.kill();
                self.status = self.child.wait().ok();
            }
        }
        if let Some(r) = self.reader.take() {
            let _ = r.join();
        }
        self.status
    }
}

impl Transport for Qemu {
    fn send(&mut self, bytes: &[u8]) -> Result<()> {
        let stdin = self.stdin.as_mut().context("QEMU stdin closed")?;
        stdin
            .write_all(bytes)
            .and_then(|()| stdin.flush())
            .context("writing to QEMU's serial port (stdin) failed: QEMU exited?")
    }

    fn receive(&mut self, timeout: Duration) -> Received {
        match self.output.recv_timeout(timeout) {
            Ok(b) => Received::Bytes(b),
            Err(RecvTimeoutError::Timeout) => Received::Timeout,
            Err(RecvTimeoutError::Disconnected) => Received::Closed,
        }
    }

    fn post_mortem(&mut self) -> String {
        let status = self.wait_exit(Duration::from_secs(2));
        let status = status.map_or_else(
            || "still running (killed)".to_string(),
            |s| format!("exited with {s}"),
        );
        self.stop();
        let tail = match &self.decode_tail {
            Some(decode) => {
                let lines = decode(&self.defmt_path);
                let from = lines.len().saturating_sub(20);
                if lines.is_empty() {
                    "  (empty)".to_string()
                } else {
                    lines[from..]
                        .iter()
                        .map(|l| format!("  {l}"))
                        .collect::<Vec<_>>()
                        .join("\n")
                }
            }
            None => "  (not decoded)".to_string(),
        };
        format!(
            "{} {status}; last lines of its defmt log ({}):\n{tail}",
            self.binary.display(),
            self.defmt_path.display()
        )
    }
}

impl Drop for Qemu {
    fn drop(&mut self) {
        self.stop();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stand-in for QEMU: a shell script that ignores QEMU's arguments.
    fn script(name: &str, body: &str) -> PathBuf {
        use std::os::unix::fs::PermissionsExt;
        let dir = std::env::temp_dir().join(format!("pil-qemu-unit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        path
    }

    #[test]
    fn arguments_route_the_serial_port_and_the_log() {
        let args = qemu_args(Path::new("/x/fw.elf"), Path::new("/o/defmt.bin"));
        let s: Vec<_> = args
            .iter()
            .map(|a| a.to_string_lossy().into_owned())
            .collect();
        let joined = s.join(" ");
        assert!(joined.starts_with("-machine mps2-an386 -cpu cortex-m4 -display none"));
        assert!(joined.contains("-serial stdio"));
        assert!(joined.contains(
            "-semihosting-config enable=on,target=native,chardev=defmt \
             -chardev file,id=defmt,path=/o/defmt.bin"
        ));
        assert!(joined.ends_with("-kernel /x/fw.elf"));
    }

    #[test]
    fn a_hung_emulator_is_killed_and_reaped_on_drop() {
        let bin = script("hang.sh", "exec sleep 60");
        let mut q = Qemu::spawn(&bin, Path::new("fw.elf"), Path::new("defmt.bin")).unwrap();
        let pid = q.id();
        assert_eq!(q.receive(Duration::from_millis(50)), Received::Timeout);
        q.send(b"bytes").unwrap();
        drop(q);
        // Reaped: no zombie left behind.
        assert!(!Path::new(&format!("/proc/{pid}")).exists());
    }

    #[test]
    fn an_exit_closes_the_output_and_reports_the_status() {
        let bin = script("exit.sh", "printf hello; exit 3");
        let mut q = Qemu::spawn(&bin, Path::new("fw.elf"), Path::new("defmt.bin")).unwrap();
        q.set_log_decoder(|_| vec!["last line".into()]);
        let mut got = Vec::new();
        loop {
            match q.receive(Duration::from_secs(10)) {
                Received::Bytes(b) => got.extend(b),
                Received::Closed => break,
                Received::Timeout => panic!("no EOF"),
            }
        }
        assert_eq!(got, b"hello");
        let m = q.post_mortem();
        assert!(
            m.contains("exit status: 3") && m.contains("last line"),
            "{m}"
        );
    }

    #[test]
    fn a_missing_binary_is_a_clear_error() {
        let e = Qemu::spawn(
            Path::new("/nonexistent/qemu-system-arm"),
            Path::new("fw.elf"),
            Path::new("defmt.bin"),
        )
        .err()
        .unwrap();
        assert!(format!("{e:#}").contains("cannot start"), "{e:#}");
    }
}
