//! MAVLink 2 message signing on the endpoint (`twocars::mavlink::signing`): the signature
//! against pymavlink's for the same frame, then the endpoint with signing on: a signed request
//! answered with signed frames; unsigned, wrongly keyed, replayed, older and truncated frames
//! refused and counted.

use twocars::mavlink::signing::{signature, SignatureRefusal, Verifier, KEY_LEN, SIGNATURE_LEN};
use twocars::mavlink::{Endpoint, SIGNATURE_COUNTERS};
use twocars_sim::mavlink_spec::{
    param_set_payload, read_v2, v2_from, NAMED_VALUE_FLOAT, PARAM_SET, PARAM_VALUE,
    SENT_BY_ENDPOINT,
};

/// The key of the vector below: bytes 0 to 31.
fn key() -> [u8; KEY_LEN] {
    core::array::from_fn(|i| i as u8)
}

/// PARAM_SET (1, 191) TC_TIMEOUT 0.5 from (1, 1), sequence 0, signed by pymavlink 2.4.49 with
/// key 0..31, link id 3, timestamp 123456789 (`MAVLink.param_set_send` with `signing`).
const PYMAVLINK_FRAME: &str = "fd1701000001011700000000003f01bf54435f54494d454f55540000000000000928430315cd5b07000093f4a29aae82";

fn hex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

/// A frame of `message` from `sender`, signed under `key` with `link` at `timestamp`.
fn signed(
    sender: (u8, u8),
    sequence: u8,
    payload: &[u8],
    key: &[u8; KEY_LEN],
    (link, timestamp): (u8, u64),
) -> Vec<u8> {
    let mut f = v2_from(sequence, sender, PARAM_SET, payload, true);
    let body = f.len() - SIGNATURE_LEN;
    let block = twocars::mavlink::signing::block(key, &f[..body], link, timestamp);
    f[body..].copy_from_slice(&block);
    f
}

fn set_timeout(value: f32) -> Vec<u8> {
    param_set_payload((1, 191), "TC_TIMEOUT", value, 9)
}

/// Feeds `bytes`; what the endpoint sent, its signature blocks checked with `key` and removed.
fn feed(endpoint: &mut Endpoint, bytes: &[u8], now_ms: u32) -> Vec<u8> {
    let mut out = Vec::new();
    for &b in bytes {
        endpoint.receive(b, now_ms, &mut |f| out.extend_from_slice(f));
    }
    out
}

/// Splits signed frames: each checked by a verifier with `key`, returned unsigned.
fn unsign(stream: &[u8], verifier: &mut Verifier) -> Vec<u8> {
    let (mut at, mut plain) = (0, Vec::new());
    while at < stream.len() {
        let f = &stream[at..];
        assert_eq!(
            (f[0], f[2]),
            (0xFD, 0x01),
            "an unsigned frame from the endpoint"
        );
        let body = 12 + usize::from(f[1]);
        let block = &f[body..body + SIGNATURE_LEN];
        assert_eq!(
            verifier.check((f[5], f[6]), &f[..body], Some(block)),
            Ok(())
        );
        let mut unsigned = f[..body].to_vec();
        unsigned[2] = 0;
        // The checksum covers the flags: recompute it for the plain reader.
        let id = u32::from_le_bytes([f[7], f[8], f[9], 0]);
        let extra = SENT_BY_ENDPOINT.iter().find(|m| m.0 == id).unwrap().1;
        let mut checked = unsigned[1..body - 2].to_vec();
        checked.push(extra);
        let crc = twocars_sim::mavlink_spec::x25(&checked).to_le_bytes();
        unsigned[body - 2..].copy_from_slice(&crc);
        plain.extend(unsigned);
        at += body + SIGNATURE_LEN;
    }
    plain
}

#[test]
fn the_signature_is_pymavlinks() {
    let frame = hex(PYMAVLINK_FRAME);
    let body = frame.len() - SIGNATURE_LEN;
    assert_eq!(frame[body], 3);
    assert_eq!(
        signature(&key(), &frame[..body], 3, 123_456_789),
        frame[body + 7..]
    );
    let mut verifier = Verifier::new(key(), 123_000_000);
    assert_eq!(
        verifier.check((1, 1), &frame[..body], Some(&frame[body..])),
        Ok(())
    );
    assert_eq!(
        verifier.check((1, 1), &frame[..body], Some(&frame[body..])),
        Err(SignatureRefusal::Stale),
        "the same frame again is a replay"
    );
}

#[test]
fn a_signed_request_gets_signed_answers_and_the_pymavlink_frame_is_taken() {
    let mut endpoint = Endpoint::new().with_signing(key(), 7, 123_000_000);
    let out = feed(&mut endpoint, &hex(PYMAVLINK_FRAME), 0);
    let mut verifier = Verifier::new(key(), 0);
    let replies = read_v2(&unsign(&out, &mut verifier), &SENT_BY_ENDPOINT).unwrap();
    assert_eq!(replies.len(), 1);
    assert_eq!(replies[0].id, PARAM_VALUE.0);
    assert_eq!(replies[0].f32(0), 0.5);
    // Our own frames: link 7, timestamps from the newest accepted on, strictly increasing.
    let mut heartbeats = Vec::new();
    endpoint.poll(0, &mut |f| heartbeats.extend_from_slice(f));
    endpoint.poll(1000, &mut |f| heartbeats.extend_from_slice(f));
    unsign(&heartbeats, &mut verifier);
    assert!(verifier.newest > 123_456_789);
}

#[test]
fn unsigned_wrongly_keyed_replayed_older_and_truncated_frames_are_refused_and_counted() {
    let mut endpoint = Endpoint::new().with_signing(key(), 1, 1_000_000);
    let gcs = (255, 190);
    let good = |seq, ts| signed(gcs, seq, &set_timeout(0.5), &key(), (0, ts));
    assert!(!feed(&mut endpoint, &good(0, 2_000_000), 0).is_empty());

    let cases: [(&str, Vec<u8>); 6] = [
        (
            "unsigned",
            v2_from(1, gcs, PARAM_SET, &set_timeout(0.7), false),
        ),
        (
            "wrong key",
            signed(gcs, 2, &set_timeout(0.7), &[9; KEY_LEN], (0, 3_000_000)),
        ),
        ("replayed", good(0, 2_000_000)),
        ("older", good(3, 1_999_999)),
        ("signature damaged", {
            let mut f = good(4, 4_000_000);
            let n = f.len();
            f[n - 3..].copy_from_slice(&[0, 0, 0]);
            f
        }),
        // Cut short by 6 bytes: it takes the next frame's first 6 as its signature, which
        // fails; the rest of that frame is line noise.
        ("signature truncated", {
            let mut f = good(5, 5_000_000);
            f.truncate(f.len() - 6);
            f.extend(good(6, 6_000_000));
            f
        }),
    ];
    for (name, frame) in &cases {
        assert!(
            feed(&mut endpoint, frame, 10).is_empty(),
            "{name} was answered"
        );
    }
    let c = endpoint.counters();
    assert_eq!((c.unsigned, c.bad_signature, c.stale_signature), (1, 3, 2));
    assert_eq!(endpoint.params().get(7), Some(0.5), "TC_TIMEOUT kept");
    // The heartbeat's named values say the same, each refusal also in TC_BADFRM.
    let mut beat = Vec::new();
    endpoint.poll(15, &mut |f| beat.extend_from_slice(f));
    let sent = read_v2(
        &unsign(&beat, &mut Verifier::new(key(), 0)),
        &SENT_BY_ENDPOINT,
    )
    .unwrap();
    let named: Vec<(String, f32)> = sent
        .iter()
        .filter(|m| m.id == NAMED_VALUE_FLOAT.0)
        .map(|m| (m.text(8, 10), m.f32(4)))
        .collect();
    let [nosig, badsig, oldsig] = SIGNATURE_COUNTERS.map(String::from);
    assert_eq!(
        named,
        [
            ("TC_BADFRM".to_string(), 6.0),
            (nosig, 1.0),
            (badsig, 3.0),
            (oldsig, 2.0)
        ]
    );
    // A newer signed frame is still taken.
    assert!(!feed(&mut endpoint, &good(7, 7_000_000), 20).is_empty());
    assert_eq!(endpoint.params().get(7), Some(0.5));
}

#[test]
fn a_new_stream_may_start_at_most_a_minute_behind() {
    let mut verifier = Verifier::new(key(), 100_000_000);
    let frame = signed((2, 1), 0, &set_timeout(1.0), &key(), (0, 93_000_000));
    let body = frame.len() - SIGNATURE_LEN;
    assert_eq!(
        verifier.check((2, 1), &frame[..body], Some(&frame[body..])),
        Err(SignatureRefusal::Stale)
    );
    let frame = signed((2, 1), 0, &set_timeout(1.0), &key(), (0, 95_000_000));
    assert_eq!(
        verifier.check((2, 1), &frame[..body], Some(&frame[body..])),
        Ok(())
    );
}

#[test]
fn without_a_key_the_endpoint_takes_unsigned_frames_and_signs_nothing() {
    let mut endpoint = Endpoint::new();
    assert!(!endpoint.signing());
    let out = feed(
        &mut endpoint,
        &v2_from(0, (255, 190), PARAM_SET, &set_timeout(0.5), false),
        0,
    );
    let replies = read_v2(&out, &SENT_BY_ENDPOINT).unwrap();
    assert_eq!(replies[0].f32(0), 0.5);
}
