//! The MAVLink router between the autopilot's SITL (ArduPilot over TCP, PX4 over UDP), the
//! unit's UART (the emulator's TCP port, or the companion's) and the host (the ground station
//! and the target): whole frames only, so that a frame the host injects never lands inside one
//! of the autopilot's.
//!
//! Frames are split by their headers' lengths (TCP and localhost UDP carry no noise), which
//! needs no message's CRC_EXTRA: each autopilot's own dialect passes through untouched. The messages the harness reads
//! are decoded with the `mavlink` crate's common dialect.

use std::io::{self, ErrorKind, Read, Write};
use std::net::{TcpStream, UdpSocket};
use std::time::{Duration, Instant};

use mavlink::dialects::common::MavMessage;
use mavlink::{MavlinkVersion, Message, MessageData};
use twocars::mavlink::signing::Signer;
use twocars::mavlink::Outbox;

use super::backlog::UnitEnd;

/// MAVLink 1 and 2 start bytes.
const STX_V1: u8 = 0xFE;
const STX_V2: u8 = 0xFD;
/// MAVLink 2's incompatibility flag for a signed frame (13 more bytes).
const SIGNED: u8 = 0x01;

/// One whole frame and what its header says.
#[derive(Clone, Debug)]
pub struct RawFrame {
    /// The frame's bytes, start byte to checksum (and signature).
    pub bytes: Vec<u8>,
    /// Sender's system and component ids.
    pub system: u8,
    pub component: u8,
    /// The message id.
    pub message_id: u32,
}

impl RawFrame {
    /// The message, where the common dialect knows it.
    pub fn message(&self) -> Option<MavMessage> {
        let (version, start) = if self.bytes.first() == Some(&STX_V2) {
            (MavlinkVersion::V2, 10)
        } else {
            (MavlinkVersion::V1, 6)
        };
        let length = usize::from(*self.bytes.get(1)?);
        let payload = self.bytes.get(start..start + length)?;
        MavMessage::parse(version, self.message_id, payload).ok()
    }
}

/// Splits a byte stream into whole frames by their headers' lengths.
#[derive(Default)]
pub struct Splitter {
    buffer: Vec<u8>,
}

impl Splitter {
    /// Appends received bytes.
    pub fn push(&mut self, bytes: &[u8]) {
        self.buffer.extend_from_slice(bytes);
    }

    /// The next whole frame, if one has arrived (bytes before a start byte are dropped).
    pub fn next_frame(&mut self) -> Option<RawFrame> {
        let start = self
            .buffer
            .iter()
            .position(|&b| b == STX_V1 || b == STX_V2)
            .unwrap_or(self.buffer.len());
        self.buffer.drain(..start);
        let b = &self.buffer;
        let (stx, length) = (*b.first()?, usize::from(*b.get(1)?));
        let total = if stx == STX_V2 {
            10 + length + 2 + if b.get(2)? & SIGNED != 0 { 13 } else { 0 }
        } else {
            6 + length + 2
        };
        if b.len() < total {
            return None;
        }
        let (system, component, message_id) = if stx == STX_V2 {
            (b[5], b[6], u32::from_le_bytes([b[7], b[8], b[9], 0]))
        } else {
            (b[3], b[4], u32::from(b[5]))
        };
        let bytes = self.buffer.drain(..total).collect();
        Some(RawFrame {
            bytes,
            system,
            component,
            message_id,
        })
    }
}

/// Where a frame came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    Autopilot,
    Unit,
}

/// A link to the autopilot: a TCP stream, or a UDP socket connected to the autopilot's port
/// (each datagram whole frames).
pub enum Link {
    Tcp(TcpStream),
    Udp(UdpSocket),
}

impl From<TcpStream> for Link {
    fn from(stream: TcpStream) -> Link {
        Link::Tcp(stream)
    }
}

impl From<UdpSocket> for Link {
    fn from(socket: UdpSocket) -> Link {
        Link::Udp(socket)
    }
}

impl Link {
    fn set_nonblocking(&self) -> io::Result<()> {
        match self {
            Link::Tcp(s) => s.set_nonblocking(true).and_then(|()| s.set_nodelay(true)),
            Link::Udp(s) => s.set_nonblocking(true),
        }
    }
}

impl Read for Link {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match self {
            Link::Tcp(s) => s.read(buf),
            // An empty datagram is nothing, not a closed link; a refused send (no one on the
            // port yet) reads as nothing too.
            Link::Udp(s) => match s.recv(buf) {
                Ok(0) => Err(ErrorKind::WouldBlock.into()),
                Err(e) if e.kind() == ErrorKind::ConnectionRefused => {
                    Err(ErrorKind::WouldBlock.into())
                }
                other => other,
            },
        }
    }
}

impl Write for Link {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self {
            Link::Tcp(s) => s.write(buf),
            Link::Udp(s) => match s.send(buf) {
                Err(e) if e.kind() == ErrorKind::ConnectionRefused => Ok(buf.len()),
                other => other,
            },
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// The two links, their splitters, and the host's own sender (system 255, component 190, as a
/// ground station; or another system id for the target).
pub struct Router {
    autopilot: Link,
    /// The unit's UART; `None` on a link to an autopilot alone (the evader's rover).
    unit: Option<TcpStream>,
    from_autopilot: Splitter,
    from_unit: Splitter,
    outbox: Outbox,
    /// Where signing is on: the autopilot's SERIAL0, read and dropped (it must stay
    /// connected; the chase runs on SERIAL1, where ArduPilot checks signatures).
    serial0: Option<TcpStream>,
    /// Every byte written to the unit's UART, with our clock (ms since the router started) at
    /// each write: the stream the unit parsed, for replays.
    pub to_unit_log: Vec<(u32, Vec<u8>)>,
    started: Instant,
    /// The autopilot's messages the unit is sent (all where `None`), as a companion port's
    /// stream rates would be set.
    unit_messages: Option<&'static [u32]>,
    /// The unit's end of its link, the most it has held unread since [`Router::take_unread`]
    /// (bytes), and when it was last looked at.
    unit_end: Option<UnitEnd>,
    unread_peak: Option<u64>,
    unread_sampled: Instant,
}

/// How often the router looks at what the unit holds unread (wall clock).
pub const UNREAD_EVERY: Duration = Duration::from_millis(50);

/// The host's ground-station identity.
pub const GCS: (u8, u8) = (255, 190);
/// The router's link id where it signs.
pub const LINK_ID: u8 = 2;
/// How far the router's signing clock runs ahead of the wall clock, 10 us: two minutes.
/// ArduPilot starts its own a minute past the key's timestamp, and a receiver takes a new
/// stream only within a minute of the newest it has seen.
pub const CLOCK_LEAD: u64 = 12_000_000;

impl Router {
    /// Joins the autopilot's link and the unit's TCP link.
    pub fn new(autopilot: impl Into<Link>, unit: TcpStream) -> Result<Router, String> {
        let mut router = Router::alone(autopilot)?;
        unit.set_nonblocking(true).map_err(|e| e.to_string())?;
        unit.set_nodelay(true).map_err(|e| e.to_string())?;
        router.unit_end = UnitEnd::of(&unit);
        router.unit = Some(unit);
        Ok(router)
    }

    /// A link to the autopilot alone: the ground station's, with no unit behind it.
    pub fn alone(autopilot: impl Into<Link>) -> Result<Router, String> {
        let autopilot = autopilot.into();
        autopilot.set_nonblocking().map_err(|e| e.to_string())?;
        Ok(Router {
            autopilot,
            unit: None,
            from_autopilot: Splitter::default(),
            from_unit: Splitter::default(),
            outbox: Outbox::default(),
            serial0: None,
            to_unit_log: Vec::new(),
            started: Instant::now(),
            unit_messages: None,
            unit_end: None,
            unread_peak: None,
            unread_sampled: Instant::now(),
        })
    }

    /// The same router signing what it sends (the ground station's frames and the target's)
    /// under `key` with link id [`LINK_ID`], its clock ahead of the wall clock by
    /// [`CLOCK_LEAD`]; `serial0` is drained.
    pub fn with_signing(mut self, key: [u8; 32], serial0: TcpStream) -> Result<Router, String> {
        serial0.set_nonblocking(true).map_err(|e| e.to_string())?;
        self.outbox.signer = Some(Signer::new(key, LINK_ID));
        self.serial0 = Some(serial0);
        Ok(self)
    }

    /// Whether the router signs.
    pub fn signing(&self) -> bool {
        self.outbox.signer.is_some()
    }

    /// Sends `message` from the ground station to the autopilot without a signature.
    pub fn send_unsigned_to_autopilot<M: MessageData>(
        &mut self,
        message: &M,
    ) -> Result<(), String> {
        let signer = self.outbox.signer.take();
        let bytes = self.encode(GCS, message);
        self.outbox.signer = signer;
        write_all(&mut self.autopilot, &bytes, "autopilot")
    }

    /// The next whole frame from either link, waiting up to `timeout`; not forwarded (the
    /// caller forwards with [`Router::forward`], after what it injects before it).
    pub fn next(&mut self, timeout: Duration) -> Result<Option<(Source, RawFrame)>, String> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(f) = self.from_autopilot.next_frame() {
                return Ok(Some((Source::Autopilot, f)));
            }
            if let Some(f) = self.from_unit.next_frame() {
                return Ok(Some((Source::Unit, f)));
            }
            if let Some(serial0) = self.serial0.as_mut() {
                let mut drained = Splitter::default();
                read_into(serial0, &mut drained, "autopilot's SERIAL0")?;
            }
            let mut got = read_into(&mut self.autopilot, &mut self.from_autopilot, "autopilot")?;
            if let Some(unit) = self.unit.as_mut() {
                got |= read_into(unit, &mut self.from_unit, "unit")?;
            }
            if !got {
                if Instant::now() >= deadline {
                    return Ok(None);
                }
                std::thread::sleep(Duration::from_micros(500));
            }
        }
    }

    /// Sends the unit only these of the autopilot's messages (by id) from here on; all of
    /// them with `None`.
    pub fn pass_to_unit(&mut self, messages: Option<&'static [u32]>) {
        self.unit_messages = messages;
    }

    /// The most bytes the unit held unread on its link since the last call (sampled every
    /// [`UNREAD_EVERY`] as the router writes to it); `None` where unmeasured.
    pub fn take_unread(&mut self) -> Option<u64> {
        self.unread_peak.take()
    }

    /// Passes a frame on to the other side.
    pub fn forward(&mut self, source: Source, frame: &RawFrame) -> Result<(), String> {
        match source {
            Source::Autopilot
                if self
                    .unit_messages
                    .is_some_and(|m| !m.contains(&frame.message_id)) =>
            {
                Ok(())
            }
            Source::Autopilot => self.send_to_unit(&frame.bytes),
            Source::Unit => write_all(&mut self.autopilot, &frame.bytes, "autopilot"),
        }
    }

    /// Writes bytes to the unit's UART (logged).
    pub fn send_to_unit(&mut self, bytes: &[u8]) -> Result<(), String> {
        let now = self.started.elapsed().as_millis() as u32;
        let Some(unit) = self.unit.as_mut() else {
            return Ok(());
        };
        self.to_unit_log.push((now, bytes.to_vec()));
        write_all(unit, bytes, "unit")?;
        if self.unread_sampled.elapsed() >= UNREAD_EVERY {
            self.unread_sampled = Instant::now();
            if let Some(queued) = self.unit_end.as_ref().and_then(UnitEnd::queued) {
                self.unread_peak = Some(self.unread_peak.unwrap_or(0).max(queued));
            }
        }
        Ok(())
    }

    /// Encodes `message` from `sender` (MAVLink 2; signed where signing is on).
    pub fn encode<M: MessageData>(&mut self, sender: (u8, u8), message: &M) -> Vec<u8> {
        self.outbox.timestamp = crate::image::signing::clock_now() + CLOCK_LEAD;
        let mut out = Vec::new();
        self.outbox
            .send_as(sender, message, &mut |f| out.extend_from_slice(f));
        out
    }

    /// Sends `message` from the ground station to the autopilot.
    pub fn send_to_autopilot<M: MessageData>(&mut self, message: &M) -> Result<(), String> {
        let bytes = self.encode(GCS, message);
        write_all(&mut self.autopilot, &bytes, "autopilot")
    }

    /// Sends `message` from `sender` to the unit.
    pub fn send_to_unit_as<M: MessageData>(
        &mut self,
        sender: (u8, u8),
        message: &M,
    ) -> Result<(), String> {
        let bytes = self.encode(sender, message);
        self.send_to_unit(&bytes)
    }
}

/// Reads what `stream` has into `splitter`; whether anything came.
fn read_into(stream: &mut impl Read, splitter: &mut Splitter, name: &str) -> Result<bool, String> {
    let mut buf = [0u8; 4096];
    match stream.read(&mut buf) {
        Ok(0) => Err(format!("the {name} closed its link")),
        Ok(n) => {
            splitter.push(buf.get(..n).unwrap_or(&[]));
            Ok(true)
        }
        Err(e) if e.kind() == ErrorKind::WouldBlock => Ok(false),
        Err(e) if e.kind() == ErrorKind::Interrupted => Ok(false),
        Err(e) => Err(format!("{name}: {e}")),
    }
}

/// Writes all of `bytes` to a non-blocking stream.
fn write_all(stream: &mut impl Write, mut bytes: &[u8], name: &str) -> Result<(), String> {
    let deadline = Instant::now() + Duration::from_secs(5);
    while !bytes.is_empty() {
        match stream.write(bytes) {
            Ok(n) => bytes = bytes.get(n..).unwrap_or(&[]),
            Err(e) if e.kind() == ErrorKind::WouldBlock && Instant::now() < deadline => {
                std::thread::sleep(Duration::from_micros(200));
            }
            Err(e) => return Err(format!("to the {name}: {e}")),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::common::HEARTBEAT_DATA;

    #[test]
    fn frames_split_whole_after_noise_and_in_pieces() {
        let mut outbox = Outbox::default();
        let mut stream = vec![1, 2, 3];
        for _ in 0..3 {
            outbox.send_as((1, 1), &HEARTBEAT_DATA::default(), &mut |f| {
                stream.extend_from_slice(f)
            });
        }
        let mut splitter = Splitter::default();
        let mut frames = Vec::new();
        for chunk in stream.chunks(5) {
            splitter.push(chunk);
            while let Some(f) = splitter.next_frame() {
                frames.push(f);
            }
        }
        assert_eq!(frames.len(), 3);
        assert!(frames.iter().all(|f| f.message_id == 0 && f.system == 1));
        assert!(matches!(
            frames[0].message(),
            Some(MavMessage::HEARTBEAT(_))
        ));
    }
}
