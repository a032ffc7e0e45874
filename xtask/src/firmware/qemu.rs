//! QEMU sessions: start `qemu-system-arm` with UART0 on a loopback TCP port (QEMU the server,
//! we the client) and the defmt log stream decoded by `defmt-print`, talk frames, and always
//! stop QEMU (on drop, error or timeout).
//!
//! QEMU runs in real time (no `-icount`): the firmware's watchdog clock is SysTick, which QEMU
//! drives from the host clock.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use host_tests::link::{self, Reply, ReplyDecoder};
use twocars::protocol::message::Counters;

use crate::firmware::build::Board;

/// `program` on the PATH (or in ~/.cargo/bin).
pub fn on_path(program: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    let mut dirs: Vec<PathBuf> = std::env::split_paths(&path).collect();
    if let Some(home) = std::env::var_os("HOME") {
        dirs.push(PathBuf::from(home).join(".cargo/bin"));
    }
    dirs.into_iter()
        .map(|d| d.join(program))
        .find(|p| p.is_file())
}

/// `qemu-system-arm`, or a message saying how to install it.
pub fn qemu_binary() -> Result<PathBuf, String> {
    on_path("qemu-system-arm").ok_or_else(|| {
        "qemu-system-arm is not installed: run `sudo apt-get install qemu-system-arm` \
         (Debian/Ubuntu), or `bash .ci/run` which installs it"
            .to_string()
    })
}

/// `defmt-print`, installed with `cargo install` when missing; `None` if that fails (logs are
/// then not shown).
pub fn defmt_print() -> Option<PathBuf> {
    if let Some(p) = on_path("defmt-print") {
        return Some(p);
    }
    eprintln!("xtask: installing defmt-print (cargo install defmt-print --locked) to decode logs");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let ok = Command::new(cargo)
        .args(["install", "defmt-print", "--version", "1.2.0", "--locked"])
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        eprintln!("xtask: could not install defmt-print; firmware logs will not be decoded");
    }
    on_path("defmt-print")
}

fn free_port() -> Result<u16, String> {
    let listener = TcpListener::bind("127.0.0.1:0").map_err(|e| format!("no free port: {e}"))?;
    listener
        .local_addr()
        .map(|a| a.port())
        .map_err(|e| e.to_string())
}

/// QEMU running an image, its UART a TCP server on 127.0.0.1:`port` that holds the guest until
/// one client connects; killed on drop.
pub struct Launched {
    qemu: Child,
    decoder: Option<Child>,
    /// The UART's port.
    pub port: u16,
}

impl Drop for Launched {
    fn drop(&mut self) {
        let _ = self.qemu.kill();
        let _ = self.qemu.wait();
        if let Some(mut d) = self.decoder.take() {
            let _ = d.kill();
            let _ = d.wait();
        }
    }
}

/// Starts QEMU with `board`'s image `elf`; logs decoded to stderr when `show_logs` (the
/// mps2-an386 COBS image logs with defmt).
pub fn launch(elf: &Path, board: Board, show_logs: bool) -> Result<Launched, String> {
    let machine = board
        .machine()
        .ok_or_else(|| format!("{}: QEMU has no model of this board", board.name()))?;
    let port = free_port()?;
    let mut command = Command::new(qemu_binary()?);
    command
        .args(machine)
        .args(["-display", "none", "-monitor", "none"])
        .args(["-semihosting-config", "enable=on,target=native"])
        .arg("-serial")
        // nodelay: QEMU writes a reply byte by byte; with Nagle's algorithm against the
        // client's delayed ACK every round trip cost 44 ms (measured), with it about 2 ms.
        .arg(format!("tcp:127.0.0.1:{port},server=on,wait=on,nodelay=on"))
        .arg("-kernel")
        .arg(elf)
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .stdout(Stdio::piped());
    let mut qemu = command
        .spawn()
        .map_err(|e| format!("qemu-system-arm: {e}"))?;
    let decoder = match (show_logs, qemu.stdout.take(), defmt_print()) {
        (true, Some(out), Some(tool)) => Command::new(tool)
            .arg("-e")
            .arg(elf)
            .stdin(out)
            .stdout(Stdio::inherit())
            .spawn()
            .ok(),
        _ => None,
    };
    Ok(Launched {
        qemu,
        decoder,
        port,
    })
}

/// A running QEMU with the firmware, connected over TCP.
pub struct Qemu {
    launched: Launched,
    stream: TcpStream,
    replies: ReplyDecoder,
    pending: std::collections::VecDeque<Reply>,
    /// Whether the image exits after a Shutdown ([`Board::exits_on_shutdown`]).
    exits_on_shutdown: bool,
    /// The counters the readiness probe found, where the image was probed.
    before_session: Option<Counters>,
    /// Bytes sent to the firmware.
    pub bytes_sent: usize,
    /// Frames received from the firmware.
    pub frames_received: usize,
}

impl Qemu {
    /// Starts QEMU with `board`'s image `elf` ([`launch`]) and connects to its UART.
    pub fn start(elf: &Path, board: Board, show_logs: bool) -> Result<Qemu, String> {
        let launched = launch(elf, board, show_logs)?;
        let port = launched.port;
        let deadline = Instant::now() + Duration::from_secs(20);
        let stream = loop {
            match TcpStream::connect(("127.0.0.1", port)) {
                Ok(s) => break s,
                Err(e) if Instant::now() > deadline => {
                    return Err(format!("could not connect to QEMU on port {port}: {e}"));
                }
                Err(_) => std::thread::sleep(Duration::from_millis(50)),
            }
        };
        stream
            .set_read_timeout(Some(Duration::from_secs(10)))
            .map_err(|e| e.to_string())?;
        stream.set_nodelay(true).map_err(|e| e.to_string())?;
        let mut qemu = Qemu {
            launched,
            stream,
            replies: ReplyDecoder::default(),
            pending: Default::default(),
            exits_on_shutdown: board.exits_on_shutdown(),
            before_session: None,
            bytes_sent: 0,
            frames_received: 0,
        };
        if board.drops_bytes_at_start() {
            qemu.wait_ready()?;
        }
        Ok(qemu)
    }

    /// Asks for the counters every 100 ms until they come (10 s at most): the image answers
    /// once its UART is on, and bytes that came before were dropped (the STM32's USART drops
    /// what arrives while it is disabled, on the chip as in QEMU's model).
    fn wait_ready(&mut self) -> Result<(), String> {
        let deadline = Instant::now() + Duration::from_secs(10);
        let probe = Duration::from_millis(100);
        self.stream
            .set_read_timeout(Some(probe))
            .map_err(|e| e.to_string())?;
        let ready = loop {
            self.send(&link::read_counters(0))?;
            match self.reply() {
                Ok(Reply::Counters(_, counters)) => {
                    // The answers to earlier probes, if they come, are not the session's.
                    while self.reply().is_ok() {}
                    self.pending.clear();
                    self.before_session = Some(counters);
                    break Ok(());
                }
                // A probe cut by the UART's start: refused, and probed again.
                Ok(Reply::Error(..)) => {}
                Ok(other) => break Err(format!("expected Counters, got {other:?}")),
                Err(_) if Instant::now() < deadline => {}
                Err(e) => break Err(format!("the image never answered: {e}")),
            }
        };
        self.stream
            .set_read_timeout(Some(Duration::from_secs(10)))
            .map_err(|e| e.to_string())?;
        ready
    }

    /// Sends raw bytes.
    pub fn send(&mut self, bytes: &[u8]) -> Result<(), String> {
        self.stream
            .write_all(bytes)
            .map_err(|e| format!("send to firmware: {e}"))?;
        self.bytes_sent += bytes.len();
        Ok(())
    }

    /// Waits for the next reply (10 s at most).
    pub fn reply(&mut self) -> Result<Reply, String> {
        let mut buf = [0u8; 256];
        while self.pending.is_empty() {
            let n = self
                .stream
                .read(&mut buf)
                .map_err(|e| format!("no reply from firmware: {e}"))?;
            if n == 0 {
                return Err("firmware closed the link".to_string());
            }
            for r in self.replies.feed(buf.get(..n).unwrap_or(&[])) {
                let r = r.map_err(|e| format!("undecodable reply from firmware: {e:?}"))?;
                self.frames_received += 1;
                self.pending.push_back(r);
            }
        }
        self.pending
            .pop_front()
            .ok_or_else(|| "no reply".to_string())
    }

    /// Messages accepted and inputs refused before the session: the readiness probes (the one
    /// answered counts as accepted after its reply; a cut one is refused). Zero where the image
    /// was not probed.
    pub fn counted_before(&self) -> (u32, u32) {
        self.before_session
            .map_or((0, 0), |c| (c.accepted + 1, c.errors.iter().sum()))
    }

    /// Whether the image exits after a Shutdown; a flight image keeps serving, and QEMU is
    /// stopped instead.
    pub fn exits_on_shutdown(&self) -> bool {
        self.exits_on_shutdown
    }

    /// Waits (10 s at most) for QEMU to exit after Shutdown; returns its exit status.
    pub fn wait_exit(mut self) -> Result<ExitStatus, String> {
        let deadline = Instant::now() + Duration::from_secs(10);
        let launched = &mut self.launched;
        loop {
            if let Some(status) = launched.qemu.try_wait().map_err(|e| e.to_string())? {
                if let Some(mut d) = launched.decoder.take() {
                    let _ = d.wait();
                }
                return Ok(status);
            }
            if Instant::now() > deadline {
                return Err("QEMU did not exit after Shutdown".to_string());
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}
