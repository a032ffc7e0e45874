//! Emulated boards: start an image in its emulator (QEMU, or rp2040js for the RP2040) with its
//! UART on a loopback TCP port (the emulator the server, the host the client), talk frames, and
//! always stop the emulator (on drop, error or timeout).
//!
//! Both run in real time: QEMU (no `-icount`) drives SysTick from the host clock; rp2040js
//! counts cycles at 125 MHz and the harness moves its clock on with the host's while the core
//! sleeps (xtask/rp2040js_harness.mjs).

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::Path;
use std::process::{Child, Command, ExitStatus};
use std::time::{Duration, Instant};

use twocars::protocol::message::Counters;
use twocars_sim::link::{self, Reply, ReplyDecoder};

use crate::harness::firmware::{defmt_log, qemu, rp2040js};
use crate::image::{Image, Machine};

fn free_port() -> Result<u16, String> {
    let listener = TcpListener::bind("127.0.0.1:0").map_err(|e| format!("no free port: {e}"))?;
    listener
        .local_addr()
        .map(|a| a.port())
        .map_err(|e| e.to_string())
}

/// An emulator running an image, its UART a TCP server on 127.0.0.1:`port` that holds the
/// guest until one client connects; killed on drop.
pub struct Launched {
    emulator: Child,
    /// The thread printing the image's defmt log, which ends with the emulator's stdout.
    decoder: Option<std::thread::JoinHandle<()>>,
    /// The UART's port.
    pub port: u16,
}

impl Drop for Launched {
    fn drop(&mut self) {
        let _ = self.emulator.kill();
        let _ = self.emulator.wait();
        // The emulator's end closes its stdout, which ends the decoder's thread.
        if let Some(d) = self.decoder.take() {
            let _ = d.join();
        }
    }
}

/// Starts `board`'s emulator with its image `elf`; logs decoded to stdout when `show_logs` and
/// the image logs with defmt (the mps2-an386 COBS image).
pub fn launch(elf: &Path, board: Image, show_logs: bool) -> Result<Launched, String> {
    let machine = board
        .machine()
        .ok_or_else(|| format!("{}: no emulator models this board", board.name()))?;
    let port = free_port()?;
    let mut command: Command = match machine {
        Machine::Qemu(options) => qemu::command(options, elf, port)?,
        Machine::Rp2040js => rp2040js::command(elf, port)?,
    };
    let mut emulator = command
        .spawn()
        .map_err(|e| format!("{}: {e}", machine.name()))?;
    let logs = show_logs && board.logs_with_defmt();
    let decoder = match (logs, emulator.stdout.take()) {
        (true, Some(out)) => defmt_log::spawn(elf, out)
            .map_err(|e| eprintln!("xtask: the image's log is not decoded: {e}"))
            .ok(),
        _ => None,
    };
    Ok(Launched {
        emulator,
        decoder,
        port,
    })
}

/// An emulator running the firmware, connected to its UART over TCP.
pub struct Emulator {
    launched: Launched,
    stream: TcpStream,
    replies: ReplyDecoder,
    pending: std::collections::VecDeque<Reply>,
    /// Whether the image exits after a Shutdown ([`Image::exits_on_shutdown`]).
    exits_on_shutdown: bool,
    /// The counters the readiness probe found, where the image was probed.
    before_session: Option<Counters>,
    /// Bytes sent to the firmware.
    pub bytes_sent: usize,
    /// Frames received from the firmware.
    pub frames_received: usize,
}

impl Emulator {
    /// Starts `board`'s emulator with its image `elf` ([`launch`]) and connects to its UART.
    pub fn start(elf: &Path, board: Image, show_logs: bool) -> Result<Emulator, String> {
        let launched = launch(elf, board, show_logs)?;
        let port = launched.port;
        let stream = connect(port, "the emulator")?;
        stream
            .set_read_timeout(Some(Duration::from_secs(10)))
            .map_err(|e| e.to_string())?;
        stream.set_nodelay(true).map_err(|e| e.to_string())?;
        let mut emulator = Emulator {
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
            emulator.wait_ready()?;
        }
        Ok(emulator)
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

    /// The counters the readiness probe read (before its own reply was counted), where the
    /// image was probed.
    pub fn before_session(&self) -> Option<Counters> {
        self.before_session
    }

    /// Messages accepted and inputs refused before the session: the readiness probes (the one
    /// answered counts as accepted after its reply; a cut one is refused). Zero where the image
    /// was not probed.
    pub fn counted_before(&self) -> (u32, u32) {
        self.before_session
            .map_or((0, 0), |c| (c.accepted + 1, c.errors.iter().sum()))
    }

    /// Whether the image exits after a Shutdown; a flight image keeps serving, and the emulator
    /// is stopped instead.
    pub fn exits_on_shutdown(&self) -> bool {
        self.exits_on_shutdown
    }

    /// Waits (10 s at most) for the emulator to exit after Shutdown; returns its exit status.
    pub fn wait_exit(mut self) -> Result<ExitStatus, String> {
        let deadline = Instant::now() + Duration::from_secs(10);
        let launched = &mut self.launched;
        loop {
            if let Some(status) = launched.emulator.try_wait().map_err(|e| e.to_string())? {
                if let Some(d) = launched.decoder.take() {
                    let _ = d.join();
                }
                return Ok(status);
            }
            if Instant::now() > deadline {
                return Err("the emulator did not exit after Shutdown".to_string());
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

/// Connects to `what` listening on 127.0.0.1:`port`, trying every 50 ms for 20 s (a server
/// just started is not listening at once).
pub fn connect(port: u16, what: &str) -> Result<TcpStream, String> {
    let deadline = Instant::now() + Duration::from_secs(20);
    loop {
        match TcpStream::connect(("127.0.0.1", port)) {
            Ok(s) => return Ok(s),
            Err(e) if Instant::now() > deadline => {
                return Err(format!("could not connect to {what} on port {port}: {e}"));
            }
            Err(_) => std::thread::sleep(Duration::from_millis(50)),
        }
    }
}

impl Machine {
    /// The emulator's name and model, as reports print it.
    pub fn name(self) -> String {
        match self {
            Machine::Qemu(options) => match options {
                [_, machine, ..] => format!("QEMU {machine}"),
                _ => "QEMU".to_string(),
            },
            Machine::Rp2040js => format!("rp2040js {}", rp2040js::VERSION),
        }
    }
}
