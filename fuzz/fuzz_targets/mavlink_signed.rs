//! Signed MAVLink 2 into the endpoint with signing on (`Endpoint::with_signing`). The input is
//! records: an op byte, a length byte and that many bytes. By `op % 4`: 0, the bytes on the line
//! as they are (noise, forged or unsigned frames); 1, a frame made of them (sender, one of the
//! messages the endpoint reads, payload) signed under the key at the next timestamp; 2, the same
//! at a timestamp the input gives (older, newer, or a new stream's); 3, the last signed frame
//! again (a replay). Our clock advances 1 ms per record and the loop's poll runs after each.
//!
//! No panic; every parameter holds its default or a value that a PARAM_SET signed under the key
//! asked for (nothing unsigned or forged changes one); everything the endpoint sends is whole
//! MAVLink 2 frames, one per frame sent, each signed with link id 0, a timestamp later than the
//! last and a signature recomputed here from the specification (SHA-256 of the key, the frame
//! up to its checksum, the link id and the timestamp, first 6 bytes) under the key.
#![no_main]

use twocars_sim::mavlink_spec::{
    v2_from, FOLLOW_TARGET, GLOBAL_POSITION_INT, HEARTBEAT, PARAM_REQUEST_LIST, PARAM_REQUEST_READ,
    PARAM_SET, SENT_BY_ENDPOINT,
};
use libfuzzer_sys::fuzz_target;
use sha2::{Digest, Sha256};
use twocars::mavlink::signing::{block, KEY_LEN, SIGNATURE_LEN};
use twocars::mavlink::{Endpoint, FrameReader, SPECS};

const KEY: [u8; KEY_LEN] = [0xA5; KEY_LEN];
/// The messages a signed record may carry.
const MESSAGES: [(u32, u8); 6] = [
    PARAM_SET,
    GLOBAL_POSITION_INT,
    FOLLOW_TARGET,
    PARAM_REQUEST_LIST,
    PARAM_REQUEST_READ,
    HEARTBEAT,
];

/// The unit's signing clock at its start: 2026-11-27, in 10 us since 2015-01-01.
const START: u64 = 37_550_000_000_000;

/// A frame of `bytes` (system, component, message, payload) signed at `timestamp`.
fn signed_frame(sequence: u8, bytes: &[u8], timestamp: u64) -> Vec<u8> {
    let [system, component, kind, payload @ ..] = bytes else {
        return Vec::new();
    };
    let message = MESSAGES[usize::from(*kind) % MESSAGES.len()];
    let mut frame = v2_from(sequence, (*system, *component), message, payload, true);
    let body = frame.len() - SIGNATURE_LEN;
    let signature = block(&KEY, &frame[..body], 2, timestamp);
    frame[body..].copy_from_slice(&signature);
    frame
}

/// The PARAM_SET (name, value) a signed frame asks for, if it is one.
fn asked(bytes: &[u8]) -> Option<(Vec<u8>, f32)> {
    let [_, _, kind, payload @ ..] = bytes else {
        return None;
    };
    if MESSAGES[usize::from(*kind) % MESSAGES.len()] != PARAM_SET {
        return None;
    }
    let mut p = payload.to_vec();
    p.resize(23, 0);
    let value = f32::from_le_bytes([p[0], p[1], p[2], p[3]]);
    let name: Vec<u8> = p[6..22].iter().copied().take_while(|&b| b != 0).collect();
    Some((name, value))
}

/// Every frame the endpoint sent: signed, link 0, timestamps increasing, the signature ours.
fn check_sent(out: &[u8], sent: u32) {
    let extra = |id| SENT_BY_ENDPOINT.iter().find(|m| m.0 == id).map(|m| m.1);
    let mut reader = FrameReader::new();
    let (mut frames, mut last) = (0, 0_u64);
    for &byte in out {
        if let Some(frame) = reader.push(byte, extra) {
            let block = frame.signature.expect("an unsigned frame went out");
            let mut ts = [0u8; 8];
            ts[..6].copy_from_slice(&block[1..7]);
            let timestamp = u64::from_le_bytes(ts);
            assert_eq!(block[0], 0, "link id");
            assert!(timestamp > last, "timestamp {timestamp} after {last}");
            last = timestamp;
            let digest = Sha256::new()
                .chain_update(KEY)
                .chain_update(frame.signed)
                .chain_update(&block[..7])
                .finalize();
            assert_eq!(&digest[..6], &block[7..13], "signature");
            frames += 1;
        }
    }
    assert_eq!((frames, reader.counters.skipped_bytes), (sent, 0));
}

fuzz_target!(|data: &[u8]| {
    let start = START;
    let mut endpoint = Endpoint::new().with_signing(KEY, 0, start);
    let (mut out, mut sent) = (Vec::new(), 0_u32);
    let (mut timestamp, mut last) = (start + 1, Vec::new());
    let mut allowed: Vec<(Vec<u8>, f32)> = Vec::new();
    let mut rest = data;
    let mut now = 0_u32;
    while let [op, len, tail @ ..] = rest {
        let n = usize::from(*len).min(tail.len());
        let (bytes, next) = tail.split_at(n);
        rest = next;
        let line = match op % 4 {
            0 => bytes.to_vec(),
            1 | 2 => {
                let at = match (op % 4, bytes) {
                    (2, [a, b, c, ..]) => start.wrapping_add_signed(
                        i64::from(i16::from_le_bytes([*a, *b])) * i64::from(*c) * 1000,
                    ),
                    _ => {
                        timestamp += 1;
                        timestamp
                    }
                };
                let body = if op % 4 == 2 {
                    bytes.get(3..).unwrap_or(&[])
                } else {
                    bytes
                };
                allowed.extend(asked(body));
                last = signed_frame(now as u8, body, at);
                last.clone()
            }
            _ => last.clone(),
        };
        let mut send = |frame: &[u8]| {
            out.extend_from_slice(frame);
            sent += 1;
        };
        for &byte in &line {
            endpoint.receive(byte, now, &mut send);
        }
        endpoint.poll(now, &mut send);
        now += 1;
    }
    for (i, spec) in SPECS.iter().enumerate() {
        let value = endpoint.params().get(i).unwrap();
        let asked_for = |(name, v): &(Vec<u8>, f32)| name == spec.name.as_bytes() && *v == value;
        assert!(
            value == spec.default || allowed.iter().any(asked_for),
            "{} = {value}, which no signed PARAM_SET asked for",
            spec.name
        );
    }
    check_sent(&out, sent);
});
