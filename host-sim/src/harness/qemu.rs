//! The one QEMU process runner of the harnesses: `qemu-system-arm -machine mps2-an386` (a
//! Cortex-M4 with FPU) running a firmware ELF. [`Qemu`] spawns it with its standard streams
//! wired for the caller ([`Io`]), kills and reaps it on a timeout or when dropped (also on
//! error paths), reports its exit status, and turns its semihosting log file into text for a
//! post-mortem.
//!
//! Two command lines, both written here: [`serial_link_args`] (processor in the loop, the
//! firmware's serial port 0 on QEMU's stdin/stdout and its defmt log in a file) and
//! [`semihosting_args`] (the instruction-count bench, semihosting output on stdout).

use std::ffi::OsString;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStderr, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};

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

/// QEMU's instruction counting for the processor in the loop: the virtual clock advances
/// 2³ = 8 ns per instruction while the core runs (125 million instructions per second, near
/// what a 168 MHz Cortex-M4F executes at 1 to 1.5 cycles per instruction), and at host speed
/// while it sleeps (`sleep=on`; with QEMU 7.2 it never does: the executor idles on `wfe`, which
/// QEMU runs as a yield, so the idle loop's instructions advance the clock instead). So the firmware's embassy-time clock
/// (SysTick on the virtual clock) times each control step by its instruction count, not by how
/// fast the host emulates it, and the step overruns it counts
/// ([`crate::harness::pil::defmt_log::overruns`]) are deterministic: a step overruns when it
/// runs more than one law period's worth of instructions (125 000 at 1 kHz).
pub const ICOUNT: &str = "shift=3,align=off,sleep=on";

/// The QEMU command line for `elf` as a serial link, the defmt log going to `defmt_path`.
/// `-serial stdio`: UART 0 on stdin/stdout; `-semihosting-config … chardev=defmt`:
/// semihosting output (defmt frames and the exit call) to a file chardev.
pub fn serial_link_args(elf: &Path, defmt_path: &Path) -> Vec<OsString> {
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
        "-icount",
        ICOUNT,
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

/// The QEMU command line for `elf` printing over semihosting on stdout (`-nographic`), for
/// the instruction-count bench; the caller appends the plugin or trace options.
pub fn semihosting_args(elf: &Path) -> Vec<OsString> {
    [
        "-M",
        "mps2-an386",
        "-nographic",
        "-monitor",
        "none",
        "-semihosting-config",
        "enable=on,target=native",
        "-kernel",
    ]
    .into_iter()
    .map(OsString::from)
    .chain([elf.as_os_str().to_owned()])
    .collect()
}

/// How QEMU's standard streams are wired.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Io {
    /// A byte link: stdin piped ([`Qemu::send`]), stdout read by a thread into a channel
    /// ([`Qemu::receive`], so waiting has a timeout), stderr inherited.
    SerialLink,
    /// Run to the end: stdin closed, stdout and stderr each read whole by a thread
    /// ([`Qemu::finish`]).
    Capture,
    /// Stream the log: stdin closed, stdout discarded, stderr piped for the caller to read
    /// ([`Qemu::take_stderr`]).
    StreamStderr,
}

/// Turns the log file at a path into text lines.
type LogDecoder = Box<dyn Fn(&Path) -> Vec<String>>;

/// How a QEMU run that went to its end finished ([`Qemu::finish`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Finished {
    /// Exit code (`None`: ended by a signal).
    pub code: Option<i32>,
    /// Everything QEMU wrote on stdout (lossy UTF-8).
    pub stdout: String,
    /// Everything QEMU wrote on stderr (lossy UTF-8).
    pub stderr: String,
}

/// A running QEMU. Dropping it kills and reaps the process (also on error paths).
pub struct Qemu {
    child: Child,
    stdin: Option<ChildStdin>,
    output: Option<Receiver<Vec<u8>>>,
    reader: Option<JoinHandle<()>>,
    /// The readers of stdout and stderr in [`Io::Capture`].
    captured: Option<(JoinHandle<String>, JoinHandle<String>)>,
    /// Exit status once known.
    status: Option<ExitStatus>,
    /// The QEMU binary, for messages.
    binary: PathBuf,
    /// The log file (semihosting output) read by a post-mortem, if any.
    log_path: Option<PathBuf>,
    /// Turns the log file into text lines for a post-mortem (set by the caller).
    decode_tail: Option<LogDecoder>,
}

/// Reads a stream to its end on a thread (lossy UTF-8).
fn read_whole(mut stream: impl Read + Send + 'static) -> JoinHandle<String> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        let _ = stream.read_to_end(&mut bytes);
        String::from_utf8_lossy(&bytes).into_owned()
    })
}

impl Qemu {
    /// Starts `binary` (e.g. `qemu-system-arm`) with `args`, its streams wired as `io`.
    /// Errors: the binary cannot be started (not installed?).
    pub fn spawn(binary: &Path, args: Vec<OsString>, io: Io) -> Result<Self> {
        let mut command = Command::new(binary);
        command.args(args);
        match io {
            Io::SerialLink => command
                .stdin(Stdio::piped())
                .stdout(Stdio::piped())
                .stderr(Stdio::inherit()),
            Io::Capture => command
                .stdin(Stdio::null())
                .stdout(Stdio::piped())
                .stderr(Stdio::piped()),
            Io::StreamStderr => command
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(Stdio::piped()),
        };
        let mut child = command.spawn().with_context(|| {
            format!(
                "cannot start {} (install it, e.g. `apt install qemu-system-arm`, or pass \
                 --qemu)",
                binary.display()
            )
        })?;
        let mut q = Self {
            stdin: child.stdin.take(),
            child,
            output: None,
            reader: None,
            captured: None,
            status: None,
            binary: binary.to_owned(),
            log_path: None,
            decode_tail: None,
        };
        match io {
            Io::SerialLink => {
                let mut stdout = q.child.stdout.take().context("QEMU stdout not piped")?;
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
                q.output = Some(rx);
                q.reader = Some(reader);
            }
            Io::Capture => {
                let stdout = q.child.stdout.take().context("QEMU stdout not piped")?;
                let stderr = q.child.stderr.take().context("QEMU stderr not piped")?;
                q.captured = Some((read_whole(stdout), read_whole(stderr)));
            }
            Io::StreamStderr => {}
        }
        Ok(q)
    }

    /// Starts `binary` on `elf` as a serial link ([`serial_link_args`], [`Io::SerialLink`]),
    /// the defmt log going to `defmt_path` (read by [`Qemu::post_mortem`]). Errors: the binary
    /// cannot be started (not installed?).
    pub fn spawn_serial_link(binary: &Path, elf: &Path, defmt_path: &Path) -> Result<Self> {
        let mut q = Self::spawn(binary, serial_link_args(elf, defmt_path), Io::SerialLink)?;
        q.log_path = Some(defmt_path.to_owned());
        Ok(q)
    }

    /// The process id.
    pub fn id(&self) -> u32 {
        self.child.id()
    }

    /// Sets how a post-mortem turns the log file into text lines.
    pub fn set_log_decoder(&mut self, decode: impl Fn(&Path) -> Vec<String> + 'static) {
        self.decode_tail = Some(Box::new(decode));
    }

    /// QEMU's stderr, to stream it ([`Io::StreamStderr`]; `None` otherwise or once taken).
    pub fn take_stderr(&mut self) -> Option<ChildStderr> {
        self.child.stderr.take()
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

    /// Waits for QEMU to exit by itself ([`Io::Capture`]) and returns what it wrote.
    /// Errors: it did not exit within `timeout` (it is killed and reaped), or its status could
    /// not be read.
    pub fn finish(mut self, timeout: Duration) -> Result<Finished> {
        let start = Instant::now();
        let status = loop {
            if let Some(s) = self.child.try_wait()? {
                break s;
            }
            if start.elapsed() > timeout {
                self.stop();
                bail!("QEMU did not finish within {} s", timeout.as_secs());
            }
            std::thread::sleep(Duration::from_millis(20));
        };
        self.status = Some(status);
        let (stdout, stderr) = match self.captured.take() {
            Some((out, err)) => (
                out.join().unwrap_or_default(),
                err.join().unwrap_or_default(),
            ),
            None => (String::new(), String::new()),
        };
        Ok(Finished {
            code: status.code(),
            stdout,
            stderr,
        })
    }

    /// Stops QEMU (kill, then reap) unless it already exited; its exit status. Idempotent.
    /// The log file is complete afterwards.
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
        if let Some((out, err)) = self.captured.take() {
            let _ = (out.join(), err.join());
        }
        self.status
    }

    /// Sends bytes to the firmware's serial port ([`Io::SerialLink`]). Blocking is
    /// backpressure. Errors: the link is gone (QEMU exited).
    pub fn send(&mut self, bytes: &[u8]) -> Result<()> {
        let stdin = self.stdin.as_mut().context("QEMU stdin closed")?;
        stdin
            .write_all(bytes)
            .and_then(|()| stdin.flush())
            .context("writing to QEMU's serial port (stdin) failed: QEMU exited?")
    }

    /// Waits at most `timeout` for bytes from the firmware's serial port ([`Io::SerialLink`];
    /// otherwise [`Received::Closed`]).
    pub fn receive(&mut self, timeout: Duration) -> Received {
        let Some(output) = &self.output else {
            return Received::Closed;
        };
        match output.recv_timeout(timeout) {
            Ok(b) => Received::Bytes(b),
            Err(RecvTimeoutError::Timeout) => Received::Timeout,
            Err(RecvTimeoutError::Disconnected) => Received::Closed,
        }
    }

    /// Why QEMU is gone, for an error message: its exit status (waiting up to 2 s for it, then
    /// killing it) and the last 20 lines of its log.
    pub fn post_mortem(&mut self) -> String {
        let status = self.wait_exit(Duration::from_secs(2));
        let status = status.map_or_else(
            || "still running (killed)".to_string(),
            |s| format!("exited with {s}"),
        );
        self.stop();
        let log_path = self.log_path.clone().unwrap_or_default();
        let tail = match &self.decode_tail {
            Some(decode) => {
                let lines = decode(&log_path);
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
            log_path.display()
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
        let args = serial_link_args(Path::new("/x/fw.elf"), Path::new("/o/defmt.bin"));
        let s: Vec<_> = args
            .iter()
            .map(|a| a.to_string_lossy().into_owned())
            .collect();
        let joined = s.join(" ");
        assert!(joined.starts_with("-machine mps2-an386 -cpu cortex-m4 -display none"));
        assert!(joined.contains("-serial stdio"));
        assert!(joined.contains("-icount shift=3,align=off,sleep=on"));
        assert!(joined.contains(
            "-semihosting-config enable=on,target=native,chardev=defmt \
             -chardev file,id=defmt,path=/o/defmt.bin"
        ));
        assert!(joined.ends_with("-kernel /x/fw.elf"));
    }

    #[test]
    fn a_hung_emulator_is_killed_and_reaped_on_drop() {
        let bin = script("hang.sh", "exec sleep 60");
        let mut q =
            Qemu::spawn_serial_link(&bin, Path::new("fw.elf"), Path::new("defmt.bin")).unwrap();
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
        let mut q =
            Qemu::spawn_serial_link(&bin, Path::new("fw.elf"), Path::new("defmt.bin")).unwrap();
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
    fn a_run_to_the_end_is_captured_and_a_hung_one_times_out() {
        let bin = script("capture.sh", "printf out; printf err >&2; exit 4");
        let f = Qemu::spawn(&bin, Vec::new(), Io::Capture)
            .unwrap()
            .finish(Duration::from_secs(10))
            .unwrap();
        assert_eq!(
            (f.code, f.stdout.as_str(), f.stderr.as_str()),
            (Some(4), "out", "err")
        );
        let bin = script("hang-capture.sh", "exec sleep 60");
        let e = Qemu::spawn(&bin, Vec::new(), Io::Capture)
            .unwrap()
            .finish(Duration::from_millis(100))
            .unwrap_err();
        assert!(format!("{e:#}").contains("did not finish"), "{e:#}");
    }

    #[test]
    fn a_missing_binary_is_a_clear_error() {
        let e = Qemu::spawn_serial_link(
            Path::new("/nonexistent/qemu-system-arm"),
            Path::new("fw.elf"),
            Path::new("defmt.bin"),
        )
        .err()
        .unwrap();
        assert!(format!("{e:#}").contains("cannot start"), "{e:#}");
    }
}
