//! MAVLink 2 message signing, as the protocol's message-signing page describes it: a 32-byte
//! secret key shared by the unit and its autopilot; every frame carries 13 bytes after its
//! checksum, the sender's link id, a 48-bit timestamp (10 us units since 2015-01-01 UTC) that
//! never goes back, and the first 48 bits of SHA-256(key + header + payload + checksum + link id
//! + timestamp).
//!
//! [`Verifier`] checks incoming frames: the signature, then the timestamp against the last one
//! of the same (system, component, link) stream; a stream it has not seen may start at most a
//! minute behind the newest timestamp it has accepted. [`Signer`] signs ours with timestamps
//! from the unit's millisecond clock, moved up to the newest accepted one (the unit has no
//! real-time clock: the spec's rule for such a system). SHA-256 is the `sha2` crate's.

use sha2::{Digest, Sha256};

pub use super::key_file::{parse_key, timestamp_from_unix_us, KEY_LEN};

/// The key and signing-clock start the image was built with (`TWOCARS_MAVLINK_KEY`, see
/// build.rs and docs/mavlink.md), or `None`.
mod provisioned {
    include!(concat!(env!("OUT_DIR"), "/mavlink_key.rs"));
}
pub use provisioned::PROVISIONED;

/// Our link id on the autopilot's link.
pub const LINK_ID: u8 = 0;

/// The signature block's length: link id, timestamp, signature.
pub const SIGNATURE_LEN: usize = 13;
/// How far behind the newest accepted timestamp a new stream may start: one minute, in 10 us.
pub const NEW_STREAM_SLACK: u64 = 6_000_000;
/// Streams remembered; the least recently seen is forgotten first.
pub const STREAMS: usize = 8;
/// Timestamps are 48 bits.
const TIMESTAMP_MASK: u64 = (1 << 48) - 1;

/// Why a frame's signature was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SignatureRefusal {
    /// Not signed, where signing is on.
    Unsigned,
    /// The signature does not match the frame under our key.
    BadSignature,
    /// The timestamp is not newer than the stream's last (a replay, or a clock gone back), or
    /// a new stream starts more than a minute behind.
    Stale,
}

/// The 48-bit signature of `signed` (header, payload and checksum of a frame whose
/// incompatibility flags say "signed") with `link_id` and `timestamp` under `key`.
pub fn signature(key: &[u8; KEY_LEN], signed: &[u8], link_id: u8, timestamp: u64) -> [u8; 6] {
    let mut hash = Sha256::new();
    hash.update(key);
    hash.update(signed);
    hash.update([link_id]);
    hash.update(&timestamp.to_le_bytes()[..6]);
    let digest = hash.finalize();
    let mut out = [0u8; 6];
    out.copy_from_slice(&digest[..6]);
    out
}

/// The 13-byte block for `signed` from `link_id` at `timestamp`.
pub fn block(
    key: &[u8; KEY_LEN],
    signed: &[u8],
    link_id: u8,
    timestamp: u64,
) -> [u8; SIGNATURE_LEN] {
    let mut out = [0u8; SIGNATURE_LEN];
    out[0] = link_id;
    out[1..7].copy_from_slice(&timestamp.to_le_bytes()[..6]);
    out[7..].copy_from_slice(&signature(key, signed, link_id, timestamp));
    out
}

/// The last timestamp of one (system, component, link) stream.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Stream {
    id: (u8, u8, u8),
    timestamp: u64,
    /// When it was last seen (a counter), for eviction.
    seen: u32,
}

/// Checks incoming signatures and timestamps.
#[derive(Clone, Debug)]
pub struct Verifier {
    key: [u8; KEY_LEN],
    streams: [Option<Stream>; STREAMS],
    /// The newest timestamp accepted (or the initial one).
    pub newest: u64,
    seen: u32,
}

impl Verifier {
    /// A verifier with `key`, its clock starting at `initial` (10 us since 2015).
    pub fn new(key: [u8; KEY_LEN], initial: u64) -> Self {
        Verifier {
            key,
            streams: [None; STREAMS],
            newest: initial & TIMESTAMP_MASK,
            seen: 0,
        }
    }

    /// Checks a frame from (`system`, `component`): `signed` its header, payload and checksum,
    /// `block` its 13 signature bytes (`None`: unsigned).
    pub fn check(
        &mut self,
        (system, component): (u8, u8),
        signed: &[u8],
        block: Option<&[u8]>,
    ) -> Result<(), SignatureRefusal> {
        let b = block.ok_or(SignatureRefusal::Unsigned)?;
        let (Some(&link), Some(ts), Some(sig)) = (b.first(), b.get(1..7), b.get(7..13)) else {
            return Err(SignatureRefusal::BadSignature);
        };
        let mut bytes = [0u8; 8];
        bytes[..6].copy_from_slice(ts);
        let timestamp = u64::from_le_bytes(bytes);
        if signature(&self.key, signed, link, timestamp) != sig {
            return Err(SignatureRefusal::BadSignature);
        }
        self.accept((system, component, link), timestamp)
    }

    /// The timestamp rule for stream `id`; records it where accepted.
    fn accept(&mut self, id: (u8, u8, u8), timestamp: u64) -> Result<(), SignatureRefusal> {
        self.seen = self.seen.wrapping_add(1);
        let known = self.streams.iter_mut().flatten().find(|s| s.id == id);
        match known {
            Some(s) if timestamp <= s.timestamp => return Err(SignatureRefusal::Stale),
            Some(s) => {
                s.timestamp = timestamp;
                s.seen = self.seen;
            }
            None => {
                if timestamp.saturating_add(NEW_STREAM_SLACK) < self.newest {
                    return Err(SignatureRefusal::Stale);
                }
                let stream = Stream {
                    id,
                    timestamp,
                    seen: self.seen,
                };
                // An empty slot, else the stream seen longest ago.
                let now = self.seen;
                let age = |s: &Option<Stream>| s.map_or(u32::MAX, |s| now.wrapping_sub(s.seen));
                if let Some(slot) = self.streams.iter_mut().max_by_key(|s| age(s)) {
                    *slot = Some(stream);
                }
            }
        }
        self.newest = self.newest.max(timestamp);
        Ok(())
    }
}

/// Signs our frames: our link id, and timestamps that never go back.
#[derive(Clone, Debug)]
pub struct Signer {
    key: [u8; KEY_LEN],
    /// Our link id.
    pub link_id: u8,
    last: u64,
}

impl Signer {
    /// A signer with `key` and `link_id`.
    pub fn new(key: [u8; KEY_LEN], link_id: u8) -> Self {
        Signer {
            key,
            link_id,
            last: 0,
        }
    }

    /// The next timestamp: `now` (10 us since 2015, from the clock the caller keeps), or one
    /// past the last where that is not later.
    pub fn next_timestamp(&mut self, now: u64) -> u64 {
        self.last = now.max(self.last + 1) & TIMESTAMP_MASK;
        self.last
    }

    /// The signature block for `signed` at `now`.
    pub fn sign(&mut self, signed: &[u8], now: u64) -> [u8; SIGNATURE_LEN] {
        let timestamp = self.next_timestamp(now);
        block(&self.key, signed, self.link_id, timestamp)
    }
}
