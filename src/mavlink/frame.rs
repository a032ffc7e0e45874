//! MAVLink 1 and 2 frames found in a byte stream, one byte at a time (the UART interrupt's queue
//! drained by the loop).
//!
//! A frame starts at 0xFE (MAVLink 1) or 0xFD (MAVLink 2); its length byte gives where it ends;
//! its checksum (X.25 over the header and payload, then the message's CRC_EXTRA: the `mavlink`
//! crate's `calculate_crc`) is checked for the messages we decode. A frame that fails is dropped
//! and the search for a start byte resumes at the byte after its start, so a good frame that
//! began inside a corrupt one is still found. A frame of a message we do not decode cannot be
//! checked (its CRC_EXTRA is not known here). A MAVLink 2 one is skipped whole when a start
//! byte follows it, as the next frame of a clean stream does; otherwise, and for MAVLink 1 (no
//! flags byte to check), it is searched like a corrupt one, so that a start byte in line noise
//! that claims a long unknown frame rarely swallows the good frames behind it (noise passes the
//! flags check 2 times in 256, then needs a start byte where its claimed frame ends).
//! Searching through every unknown frame found phantom frames in the payloads of an
//! autopilot's telemetry (ArduPilot Rover: 2.6 a second, each holding up the frames behind it).
//! MAVLink 2 frames with an incompatibility flag other than "signed" are dropped, as
//! the protocol requires; a signed frame's signature is handed out with it, for
//! [`super::signing`] to check where signing is on.
//! Nothing here panics or allocates: every index is checked.

/// MAVLink 1 start byte.
pub const STX_V1: u8 = 0xFE;
/// MAVLink 2 start byte.
pub const STX_V2: u8 = 0xFD;
/// MAVLink 2's "signed" incompatibility flag: 13 signature bytes follow the checksum.
const IFLAG_SIGNED: u8 = 0x01;
/// The longest frame: a MAVLink 2 header (10), 255 payload bytes, the checksum (2) and a
/// signature (13).
pub const MAX_FRAME: usize = 280;

/// The protocol version of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Version {
    /// MAVLink 1 (0xFE).
    V1,
    /// MAVLink 2 (0xFD).
    V2,
}

/// A checked frame: its header and its payload (MAVLink 2 may have dropped trailing zero bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Frame<'a> {
    /// The protocol version.
    pub version: Version,
    /// The sender's sequence number.
    pub sequence: u8,
    /// The sender's system id.
    pub system: u8,
    /// The sender's component id.
    pub component: u8,
    /// The message id.
    pub message_id: u32,
    /// The payload bytes as sent.
    pub payload: &'a [u8],
    /// The frame from its start byte through its checksum: what a signature covers.
    pub signed: &'a [u8],
    /// The 13 signature bytes (link id, timestamp, signature) of a signed MAVLink 2 frame.
    pub signature: Option<&'a [u8]>,
}

/// What the reader has seen, since it started (wrapping counts).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameCounters {
    /// Frames checked and handed out.
    pub frames: u32,
    /// Frames whose checksum failed.
    pub bad_checksum: u32,
    /// MAVLink 2 frames with an incompatibility flag we do not support.
    pub bad_flags: u32,
    /// MAVLink 2 frames of messages we do not decode, skipped whole (a start byte followed
    /// them).
    pub unknown: u32,
    /// Bytes outside any frame (line noise, or the rest of a dropped frame).
    pub skipped_bytes: u32,
}

/// The frame search's state: the bytes since a start byte.
#[derive(Clone, Debug)]
pub struct FrameReader {
    /// The frame being read, and the byte after it (an unknown frame's confirmation).
    buffer: [u8; MAX_FRAME + 1],
    length: usize,
    /// The bytes the buffered frame needs before the next look: its header's next part, then
    /// its whole length (0: look at the next byte). The bytes before it need no look.
    expected: usize,
    /// The length of the frame at the buffer's front that the last `push` handed out: dropped
    /// by the next.
    handed_out: Option<usize>,
    /// What was seen so far.
    pub counters: FrameCounters,
}

/// The layout of a frame read from its header.
#[derive(Clone, Copy)]
struct Layout {
    version: Version,
    /// Header bytes before the payload: 10 (MAVLink 2) or 6.
    header: usize,
    /// Payload bytes.
    payload: usize,
    /// The whole frame, checksum and signature included.
    total: usize,
    message_id: u32,
}

/// What the bytes buffered so far are.
enum Buffered {
    /// The start of a frame: more bytes needed.
    Partial,
    /// A whole frame with a good checksum.
    Checked(Layout),
    /// A whole frame of a message we do not decode, a start byte after it: skip this many
    /// bytes.
    Unknown(usize),
    /// Not a frame we can take (bad checksum or flags, or a message we do not decode): drop
    /// the start byte.
    Bad,
}

impl Default for FrameReader {
    fn default() -> Self {
        Self::new()
    }
}

impl FrameReader {
    /// A reader looking for a start byte.
    pub const fn new() -> Self {
        FrameReader {
            buffer: [0; MAX_FRAME + 1],
            length: 0,
            expected: 0,
            handed_out: None,
            counters: FrameCounters {
                frames: 0,
                bad_checksum: 0,
                bad_flags: 0,
                unknown: 0,
                skipped_bytes: 0,
            },
        }
    }

    /// Takes the next byte of the stream; returns the frame it completes, if any.
    /// `extra_crc` gives the CRC_EXTRA of each message id we decode (`None`: not ours).
    pub fn push(&mut self, byte: u8, extra_crc: impl Fn(u32) -> Option<u8>) -> Option<Frame<'_>> {
        if let Some(length) = self.handed_out.take() {
            self.drop_front(length);
        }
        if self.length == 0 && byte != STX_V1 && byte != STX_V2 {
            self.counters.skipped_bytes = self.counters.skipped_bytes.wrapping_add(1);
            return None;
        }
        let slot = self.buffer.get_mut(self.length)?;
        *slot = byte;
        self.length += 1;
        if self.length < self.expected {
            return None;
        }
        loop {
            match self.examine(&extra_crc) {
                Buffered::Partial => return None,
                Buffered::Checked(layout) => {
                    self.counters.frames = self.counters.frames.wrapping_add(1);
                    self.handed_out = Some(layout.total);
                    return self.frame(layout);
                }
                Buffered::Unknown(total) => {
                    self.counters.unknown = self.counters.unknown.wrapping_add(1);
                    self.drop_front(total);
                }
                Buffered::Bad => {
                    self.counters.skipped_bytes = self.counters.skipped_bytes.wrapping_add(1);
                    self.drop_front(1);
                }
            }
            if self.length == 0 {
                return None;
            }
        }
    }

    /// Drops the first `n` buffered bytes, then (counted as skipped) any before the next start
    /// byte.
    fn drop_front(&mut self, n: usize) {
        let rest = self.buffer.get(n..self.length).unwrap_or(&[]);
        let start = rest.iter().position(|&b| b == STX_V1 || b == STX_V2);
        let skipped = start.unwrap_or(rest.len());
        self.expected = 0;
        self.counters.skipped_bytes = self.counters.skipped_bytes.wrapping_add(skipped as u32);
        // Bounded by the buffer's length so that the copy has no panic path.
        let end = self.length.min(MAX_FRAME + 1);
        let from = (n + skipped).min(end);
        self.buffer.copy_within(from..end, 0);
        self.length = end - from;
    }

    /// Classifies the buffered bytes.
    fn examine(&mut self, extra_crc: &impl Fn(u32) -> Option<u8>) -> Buffered {
        let b = self.buffer.get(..self.length).unwrap_or(&[]);
        // Where a part of the header is missing, `expected` says how many bytes the next look
        // needs: a frame is looked at four times, not at every byte of its header.
        let Some(&stx) = b.first() else {
            return Buffered::Partial;
        };
        let (version, header, signature, message_id) = if stx == STX_V2 {
            let Some(&flags) = b.get(2) else {
                self.expected = 3;
                return Buffered::Partial;
            };
            if flags & !IFLAG_SIGNED != 0 {
                self.counters.bad_flags = self.counters.bad_flags.wrapping_add(1);
                return Buffered::Bad;
            }
            let signature = if flags & IFLAG_SIGNED != 0 { 13 } else { 0 };
            let Some(id) = b.get(7..10) else {
                self.expected = 10;
                return Buffered::Partial;
            };
            let id = u32::from_le_bytes([id[0], id[1], id[2], 0]);
            (Version::V2, 10, signature, id)
        } else {
            let Some(&id) = b.get(5) else {
                self.expected = 6;
                return Buffered::Partial;
            };
            (Version::V1, 6, 0, u32::from(id))
        };
        // Present: the header's bytes are.
        let payload = usize::from(b.get(1).copied().unwrap_or(0));
        let total = header + payload + 2 + signature;
        if b.len() < total {
            self.expected = total;
            return Buffered::Partial;
        }
        let Some(extra) = extra_crc(message_id) else {
            return match b.get(total) {
                None => {
                    self.expected = total + 1;
                    Buffered::Partial
                }
                Some(&STX_V1 | &STX_V2) if version == Version::V2 => Buffered::Unknown(total),
                Some(_) => Buffered::Bad,
            };
        };
        let (Some(checked), Some(sent)) = (
            b.get(1..header + payload),
            b.get(header + payload..header + payload + 2),
        ) else {
            return Buffered::Bad;
        };
        if ::mavlink::calculate_crc(checked, extra) != u16::from_le_bytes([sent[0], sent[1]]) {
            self.counters.bad_checksum = self.counters.bad_checksum.wrapping_add(1);
            return Buffered::Bad;
        }
        Buffered::Checked(Layout {
            version,
            header,
            payload,
            total,
            message_id,
        })
    }

    /// The buffered frame of `layout` (after `examine` returned `Checked`).
    fn frame(&self, layout: Layout) -> Option<Frame<'_>> {
        let b = self.buffer.get(..self.length)?;
        // Sequence, system and component: bytes 4 to 6 (MAVLink 2) or 2 to 4.
        let at = match layout.version {
            Version::V2 => 4,
            Version::V1 => 2,
        };
        Some(Frame {
            version: layout.version,
            sequence: *b.get(at)?,
            system: *b.get(at + 1)?,
            component: *b.get(at + 2)?,
            message_id: layout.message_id,
            payload: b.get(layout.header..layout.header + layout.payload)?,
            signed: b.get(..layout.header + layout.payload + 2)?,
            signature: b
                .get(layout.header + layout.payload + 2..layout.total)
                .filter(|s| !s.is_empty()),
        })
    }
}
