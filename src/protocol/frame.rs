//! The serial wire protocol: COBS frames delimited by 0x00, each carrying a versioned, CRC-checked
//! message with little-endian fields. Byte-by-byte layout in `docs/protocol.md`.
//!
//! A frame before COBS encoding is
//! `version (u8) | type (u8) | sequence (u16) | payload | crc (u16)`, the CRC-16/CCITT-FALSE of
//! every byte before it. Parsing never panics: every malformed input is a [`WireError`].

/// Protocol version carried in every frame the unit writes unasked, and the one its hosts
/// should speak: version 3 adds the team (Configure's team, Teammate, Command's chaser).
pub const VERSION: u8 = 3;
/// The field's version: the target fix's time in State and the field's settings in Configure.
/// Still read, and answered in version 2.
pub const VERSION_2: u8 = 2;
/// The first protocol version, exact states only: still read, and answered in version 1.
pub const VERSION_1: u8 = 1;
/// Largest decoded frame (header, payload and CRC), bytes.
pub const MAX_FRAME: usize = 96;
/// Largest encoded frame on the wire: COBS overhead and the 0x00 delimiter included.
pub const MAX_ENCODED: usize = MAX_FRAME + MAX_FRAME / 254 + 2;
/// Header bytes: version, type, sequence.
pub const HEADER_LEN: usize = 4;
/// CRC bytes.
pub const CRC_LEN: usize = 2;

/// Why an input could not be used. The code (`as u8`) goes on the wire in an Error message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
#[repr(u8)]
pub enum WireError {
    /// CRC mismatch.
    BadCrc = 1,
    /// Not a valid COBS encoding.
    BadFraming = 2,
    /// Shorter than its header and CRC, or than its message type needs.
    Truncated = 3,
    /// Longer than [`MAX_FRAME`], or longer than its message type.
    Oversized = 4,
    /// Unknown message type.
    UnknownType = 5,
    /// Unknown protocol version (not 1, 2 or 3).
    BadVersion = 6,
    /// NaN or infinity in a field.
    NonFiniteField = 7,
    /// A field outside the law's envelope (coordinates, headings, limits, period).
    OutOfRangeField = 8,
    /// A State arrived before any valid Configure, or a Teammate before one of a team.
    NotConfigured = 9,
    /// Configure with limits that violate v_pm > v_em > 0 and w_pm > w_em > 0.
    InvalidLimits = 10,
    /// Configure with a control period or watchdog time that is not finite and positive, or a
    /// role, variant or policy byte out of range.
    InvalidConfig = 11,
}

/// Number of [`WireError`] kinds (codes 1 ..= ERROR_KINDS).
pub const ERROR_KINDS: usize = 11;

impl WireError {
    /// All kinds, in code order.
    pub const ALL: [WireError; ERROR_KINDS] = [
        WireError::BadCrc,
        WireError::BadFraming,
        WireError::Truncated,
        WireError::Oversized,
        WireError::UnknownType,
        WireError::BadVersion,
        WireError::NonFiniteField,
        WireError::OutOfRangeField,
        WireError::NotConfigured,
        WireError::InvalidLimits,
        WireError::InvalidConfig,
    ];

    /// The kind for a wire code.
    pub fn from_code(code: u8) -> Option<Self> {
        Self::ALL.iter().copied().find(|e| *e as u8 == code)
    }
}

const CRC_TABLE: [u16; 256] = crc_table();

const fn crc_table() -> [u16; 256] {
    let mut table = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut crc = (i as u16) << 8;
        let mut bit = 0;
        while bit < 8 {
            crc = if crc & 0x8000 != 0 {
                (crc << 1) ^ 0x1021
            } else {
                crc << 1
            };
            bit += 1;
        }
        table[i] = crc;
        i += 1;
    }
    table
}

/// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor) of `bytes`. Out of
/// line: inlined into the serial loop, its table's address competed for registers there and was
/// reloaded on every byte.
#[inline(never)]
pub fn crc16(bytes: &[u8]) -> u16 {
    bytes.iter().fold(0xFFFF, |crc: u16, &b| {
        let index = usize::from((crc >> 8) as u8 ^ b);
        (crc << 8) ^ CRC_TABLE.get(index).copied().unwrap_or(0)
    })
}

/// COBS-encodes `input` into `out` and appends the 0x00 delimiter; returns the encoded length,
/// or `None` if `out` is too small.
pub fn cobs_encode(input: &[u8], out: &mut [u8]) -> Option<usize> {
    // Indices only grow by one after a successful write into `out`, so `checked_add` never fails
    // in practice; it keeps the function free of overflow panics when overflow checks are on.
    let mut code_at = 0;
    let mut len: usize = 1;
    let mut code: u8 = 1;
    for &byte in input {
        if byte == 0 {
            *out.get_mut(code_at)? = code;
            code_at = len;
            len = len.checked_add(1)?;
            code = 1;
        } else {
            *out.get_mut(len)? = byte;
            len = len.checked_add(1)?;
            code = code.checked_add(1)?;
            if code == 0xFF {
                *out.get_mut(code_at)? = code;
                code_at = len;
                len = len.checked_add(1)?;
                code = 1;
            }
        }
    }
    *out.get_mut(code_at)? = code;
    *out.get_mut(len)? = 0;
    len.checked_add(1)
}

/// Outcome of feeding one byte to a [`Deframer`].
#[derive(Debug, PartialEq, Eq)]
pub enum Feed<'a> {
    /// More bytes needed.
    Pending,
    /// A complete, COBS-decoded frame (header, payload, CRC; not yet checked).
    Frame(&'a [u8]),
    /// A delimited frame that could not be decoded; the deframer is ready for the next one.
    Error(WireError),
}

/// Accumulates UART bytes into frames, COBS-decoding each byte as it arrives (no second pass
/// over the frame); resynchronises on every 0x00 delimiter, so garbage costs at most the frame it
/// lands in. Holds up to `N` decoded bytes.
#[derive(Debug)]
pub struct Deframer<const N: usize> {
    buf: [u8; N],
    /// Decoded bytes so far; beyond `N` once the frame overflowed (until its delimiter).
    len: usize,
    /// Data bytes still to come in the current COBS block (0: the next byte is a code byte).
    block_left: u8,
    /// The current block ends in an implied zero (its code is below 0xFF), written when another
    /// block follows: the last block's zero is the delimiter itself.
    zero_after_block: bool,
}

impl<const N: usize> Default for Deframer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Deframer<N> {
    /// An empty deframer.
    pub const fn new() -> Self {
        Deframer {
            buf: [0; N],
            len: 0,
            block_left: 0,
            zero_after_block: false,
        }
    }

    /// Feeds one byte.
    pub fn push(&mut self, byte: u8) -> Feed<'_> {
        self.push_slice(&[byte]).1
    }

    /// Feeds `bytes` up to and including the first delimiter: how many it took, and the outcome
    /// (`Pending` when it took them all without a delimiter). The decoder's state stays in
    /// registers over the bytes (fed one at a time it is loaded and stored per byte).
    pub fn push_slice(&mut self, bytes: &[u8]) -> (usize, Feed<'_>) {
        let (mut len, mut block_left, mut zero_after_block) =
            (self.len, self.block_left, self.zero_after_block);
        let mut taken = 0;
        for &byte in bytes {
            taken += 1;
            if byte == 0 {
                self.len = 0;
                self.block_left = 0;
                self.zero_after_block = false;
                return (taken, self.end_frame(len, block_left, zero_after_block));
            }
            let decoded = if block_left > 0 {
                block_left -= 1;
                Some(byte)
            } else {
                // A code byte: the previous block's zero, then `byte - 1` data bytes.
                let zero = zero_after_block.then_some(0);
                zero_after_block = byte != 0xFF;
                block_left = byte - 1;
                zero
            };
            if let Some(decoded) = decoded {
                match self.buf.get_mut(len) {
                    Some(slot) => {
                        *slot = decoded;
                        // Below N after a successful `get_mut`: cannot wrap.
                        len = len.wrapping_add(1);
                    }
                    // Overflowed: `len` stays beyond N until the delimiter.
                    None => len = N.wrapping_add(1),
                }
            }
        }
        self.len = len;
        self.block_left = block_left;
        self.zero_after_block = zero_after_block;
        (taken, Feed::Pending)
    }

    /// The outcome of a delimiter after `len` decoded bytes (beyond N: overflowed), with
    /// `block_left` data bytes of the last block missing and its pending zero.
    fn end_frame(&self, len: usize, block_left: u8, zero_after_block: bool) -> Feed<'_> {
        if len > N {
            return Feed::Error(WireError::Oversized);
        }
        if len == 0 && block_left == 0 && !zero_after_block {
            // Back-to-back delimiters (no code byte between): an empty frame, used by senders to
            // resynchronise.
            return Feed::Pending;
        }
        if block_left > 0 {
            // The last block's code ran past the delimiter.
            return Feed::Error(WireError::BadFraming);
        }
        match self.buf.get(..len) {
            Some(decoded) => Feed::Frame(decoded),
            None => Feed::Error(WireError::Oversized),
        }
    }
}

/// Byte offsets of the frame header.
mod field {
    pub const VERSION: usize = 0;
    pub const TYPE: usize = 1;
    pub const SEQUENCE: core::ops::Range<usize> = 2..4;
}

/// The sequence number in a decoded frame's header (0 where the frame is shorter): readable
/// wherever the CRC held, a frame of another protocol version included.
pub(crate) fn header_sequence(bytes: &[u8]) -> u16 {
    let s = bytes.get(field::SEQUENCE).unwrap_or(&[0, 0]);
    u16::from_le_bytes([
        s.first().copied().unwrap_or(0),
        s.get(1).copied().unwrap_or(0),
    ])
}

/// A checked view of a decoded frame: header and CRC verified, payload length not yet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Frame<'a> {
    bytes: &'a [u8],
}

impl<'a> Frame<'a> {
    /// Checks length, CRC and version of a decoded frame.
    ///
    /// # Errors
    /// `Truncated` below header plus CRC, `Oversized` above [`MAX_FRAME`], `BadCrc`, `BadVersion`.
    pub fn new_checked(bytes: &'a [u8]) -> Result<Self, WireError> {
        if bytes.len() < HEADER_LEN + CRC_LEN {
            return Err(WireError::Truncated);
        }
        if bytes.len() > MAX_FRAME {
            return Err(WireError::Oversized);
        }
        let body_len = bytes.len() - CRC_LEN;
        let (body, crc) = bytes.split_at(body_len);
        let received = u16::from_le_bytes([
            crc.first().copied().unwrap_or(0),
            crc.get(1).copied().unwrap_or(0),
        ]);
        if crc16(body) != received {
            return Err(WireError::BadCrc);
        }
        if !matches!(body.get(field::VERSION), Some(&(VERSION_1..=VERSION))) {
            return Err(WireError::BadVersion);
        }
        Ok(Frame { bytes: body })
    }

    /// Protocol version: [`VERSION_1`], [`VERSION_2`] or [`VERSION`].
    pub fn version(&self) -> u8 {
        self.bytes.get(field::VERSION).copied().unwrap_or(VERSION)
    }

    /// Message type byte.
    pub fn message_type(&self) -> u8 {
        self.bytes.get(field::TYPE).copied().unwrap_or(0)
    }

    /// Sequence number.
    pub fn sequence(&self) -> u16 {
        header_sequence(self.bytes)
    }

    /// Payload bytes.
    pub fn payload(&self) -> &'a [u8] {
        self.bytes.get(HEADER_LEN..).unwrap_or(&[])
    }
}

/// Little-endian field reader over a payload; every read is bounds-checked.
#[derive(Debug)]
pub(crate) struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    /// A reader at the start of `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Reader { bytes, at: 0 }
    }
    fn take<const K: usize>(&mut self) -> Result<[u8; K], WireError> {
        let end = self.at.checked_add(K).ok_or(WireError::Truncated)?;
        let slice = self.bytes.get(self.at..end).ok_or(WireError::Truncated)?;
        let mut out = [0; K];
        out.copy_from_slice(slice);
        self.at = end;
        Ok(out)
    }
    /// Reads a u8.
    pub fn u8(&mut self) -> Result<u8, WireError> {
        Ok(self.take::<1>()?[0])
    }
    /// Reads a little-endian u32.
    pub fn u32(&mut self) -> Result<u32, WireError> {
        Ok(u32::from_le_bytes(self.take()?))
    }
    /// Reads a little-endian f32.
    pub fn f32(&mut self) -> Result<f32, WireError> {
        Ok(f32::from_le_bytes(self.take()?))
    }
    /// Succeeds only if every byte was read.
    pub fn finish(&self) -> Result<(), WireError> {
        if self.at == self.bytes.len() {
            Ok(())
        } else {
            Err(WireError::Oversized)
        }
    }
}

/// Little-endian field writer into a frame buffer; fails rather than truncates.
#[derive(Debug)]
pub struct Writer<'a> {
    bytes: &'a mut [u8],
    at: usize,
}

impl<'a> Writer<'a> {
    /// A writer at the start of `bytes`.
    pub fn new(bytes: &'a mut [u8]) -> Self {
        Writer { bytes, at: 0 }
    }
    /// Appends raw bytes.
    pub fn put(&mut self, data: &[u8]) -> Option<()> {
        let end = self.at.checked_add(data.len())?;
        self.bytes.get_mut(self.at..end)?.copy_from_slice(data);
        self.at = end;
        Some(())
    }
    /// Appends a u8.
    pub fn u8(&mut self, v: u8) -> Option<()> {
        self.put(&[v])
    }
    /// Appends a little-endian u16.
    pub fn u16(&mut self, v: u16) -> Option<()> {
        self.put(&v.to_le_bytes())
    }
    /// Appends a little-endian u32.
    pub fn u32(&mut self, v: u32) -> Option<()> {
        self.put(&v.to_le_bytes())
    }
    /// Appends a little-endian f32.
    pub fn f32(&mut self, v: f32) -> Option<()> {
        self.put(&v.to_le_bytes())
    }
    /// Bytes written so far.
    pub fn len(&self) -> usize {
        self.at
    }
    /// Whether nothing was written.
    pub fn is_empty(&self) -> bool {
        self.at == 0
    }
}

/// Builds a complete wire frame: header, `payload` (written by the closure), CRC, COBS, delimiter.
/// Returns the number of bytes to send, or `None` if `out` is too small or the frame is longer
/// than [`MAX_FRAME`].
///
/// The frame is written at `out[1..]` and COBS-encoded where it lies: a frame below 254 bytes is
/// one COBS block, whose encoding is the frame with each zero replaced by the distance to the
/// next zero (or to the delimiter), one code byte in front and the delimiter behind. The same
/// bytes as [`cobs_encode`] of the frame, without a second buffer or a copy.
pub fn encode_frame(
    message_type: u8,
    sequence: u16,
    payload: impl FnOnce(&mut Writer<'_>) -> Option<()>,
    out: &mut [u8],
) -> Option<usize> {
    encode_frame_as(VERSION, message_type, sequence, payload, out)
}

/// [`encode_frame`] in protocol `version` (a reply is written in its request's version).
pub fn encode_frame_as(
    version: u8,
    message_type: u8,
    sequence: u16,
    payload: impl FnOnce(&mut Writer<'_>) -> Option<()>,
    out: &mut [u8],
) -> Option<usize> {
    const { assert!(MAX_FRAME < 254) };
    let body_len = {
        let mut w = Writer::new(out.get_mut(1..)?);
        w.u8(version)?;
        w.u8(message_type)?;
        w.u16(sequence)?;
        payload(&mut w)?;
        w.len()
    };
    let crc = crc16(out.get(1..1 + body_len)?);
    let total = body_len + CRC_LEN;
    if total > MAX_FRAME {
        return None;
    }
    out.get_mut(1 + body_len..1 + total)?
        .copy_from_slice(&crc.to_le_bytes());
    // Zeros become distances, from the back; `next` is where the following zero (or the
    // delimiter) is. Distances are at most MAX_FRAME + 1 < 256.
    // Counted in a u8 down from the delimiter, over the frame's slice (no index checks).
    let mut distance: u8 = 1;
    for byte in out.get_mut(1..=total)?.iter_mut().rev() {
        if *byte == 0 {
            *byte = distance;
            distance = 1;
        } else {
            distance = distance.wrapping_add(1);
        }
    }
    *out.get_mut(0)? = distance;
    *out.get_mut(total + 1)? = 0;
    Some(total + 2)
}
