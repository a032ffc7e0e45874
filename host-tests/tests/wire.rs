//! The wire format: golden bytes, round trips, and every refusal.

use twocars::protocol::frame::{
    cobs_encode, crc16, encode_frame, Deframer, Feed, Frame, WireError, MAX_ENCODED, MAX_FRAME,
    VERSION,
};
use twocars::protocol::message::{
    CommandMsg, Configure, FieldConfig, StateMsg, TeamConfig, TeammateMsg, NO_MEMBER,
};

/// The one frame a deframer of `N` decoded bytes makes of `encoded` (delimiter included), or its
/// refusal; panics unless exactly the last byte ends it.
fn deframe<const N: usize>(encoded: &[u8]) -> Result<Vec<u8>, WireError> {
    let mut d = Deframer::<N>::new();
    let (last, body) = encoded.split_last().expect("a delimiter");
    for &b in body {
        assert_eq!(d.push(b), Feed::Pending, "ended before its delimiter");
    }
    match d.push(*last) {
        Feed::Frame(f) => Ok(f.to_vec()),
        Feed::Error(e) => Err(e),
        Feed::Pending => panic!("no frame"),
    }
}

#[test]
fn crc16_ccitt_false_matches_its_check_value() {
    // The catalogue check value of CRC-16/CCITT-FALSE over "123456789".
    assert_eq!(crc16(b"123456789"), 0x29B1);
}

#[test]
fn cobs_round_trips_and_matches_known_encodings() {
    let cases: [(&[u8], &[u8]); 4] = [
        (&[0x00], &[0x01, 0x01, 0x00]),
        (
            &[0x11, 0x22, 0x00, 0x33],
            &[0x03, 0x11, 0x22, 0x02, 0x33, 0x00],
        ),
        (
            &[0x11, 0x00, 0x00, 0x00],
            &[0x02, 0x11, 0x01, 0x01, 0x01, 0x00],
        ),
        (&[], &[0x01, 0x00]),
    ];
    for (plain, encoded) in cases {
        let mut out = [0u8; 16];
        let n = cobs_encode(plain, &mut out).unwrap();
        assert_eq!(&out[..n], encoded, "{plain:?}");
        assert_eq!(deframe::<16>(encoded).unwrap(), plain);
    }
    let long: Vec<u8> = (1..=255u8).chain(1..=20).collect();
    let mut out = [0u8; 300];
    let n = cobs_encode(&long, &mut out).unwrap();
    assert!(!out[..n - 1].contains(&0));
    assert_eq!(deframe::<300>(&out[..n]).unwrap(), long);
    // One decoded byte more than the deframer holds: refused, not truncated.
    assert_eq!(deframe::<274>(&out[..n]), Err(WireError::Oversized));
    // A code that runs past the delimiter.
    assert_eq!(
        deframe::<16>(&[0x03, 0x11, 0x00]),
        Err(WireError::BadFraming)
    );
}

/// `encode_frame` COBS-encodes in place; its bytes must be `cobs_encode` of the frame (header,
/// payload, CRC) for every payload length it accepts and zeros anywhere (none, some, all), and it
/// must refuse a frame longer than `MAX_FRAME` or an output buffer too short; the deframer decodes
/// every frame it makes.
#[test]
fn encode_frame_is_cobs_of_the_frame_and_refuses_what_does_not_fit() {
    for len in 0..=MAX_FRAME {
        for pattern in 0..5u32 {
            let payload: Vec<u8> = (0..len as u32)
                .map(|i| match pattern {
                    0 => 0,
                    1 => (i as u8).wrapping_add(1).max(1),
                    2 => {
                        if i % 3 == 0 {
                            0
                        } else {
                            i as u8 | 0x80
                        }
                    }
                    3 => {
                        if i == 0 || i + 1 == len as u32 {
                            0
                        } else {
                            0x5A
                        }
                    }
                    _ => (i.wrapping_mul(2_654_435_761) >> 24) as u8,
                })
                .collect();
            let (message_type, sequence) = (pattern as u8, (len as u16) << 8);
            let mut out = [0xEEu8; MAX_ENCODED + 8];
            let got = encode_frame(message_type, sequence, |w| w.put(&payload), &mut out);
            let mut frame = vec![VERSION, message_type];
            frame.extend(sequence.to_le_bytes());
            frame.extend(&payload);
            let crc = crc16(&frame);
            frame.extend(crc.to_le_bytes());
            if frame.len() > MAX_FRAME {
                assert_eq!(got, None, "{len} bytes of payload");
                continue;
            }
            let n = got.expect("a frame within MAX_FRAME is encoded");
            let mut want = [0u8; MAX_ENCODED + 8];
            let m = cobs_encode(&frame, &mut want).unwrap();
            assert_eq!(&out[..n], &want[..m], "payload {payload:?}");
            // And the unit's deframer gives the frame back, up to MAX_FRAME bytes.
            assert_eq!(deframe::<MAX_FRAME>(&out[..n]), Ok(frame.clone()));
            // One byte too few for the encoding: refused, not truncated.
            let mut short = vec![0u8; n - 1];
            assert_eq!(
                encode_frame(message_type, sequence, |w| w.put(&payload), &mut short),
                None
            );
        }
    }
}

#[test]
fn golden_state_frame() {
    let state = StateMsg {
        evader_time_ms: 0x0A0B_0C0D,
        ..StateMsg::exact(1, [0.0, 0.0, 1.0], [-3.0, -6.0, 1.0])
    };
    let bytes = twocars_sim::link::state(0x0102, &state);
    // version 3, type 2, seq 0x0102 LE, t = 1 LE, then f32s, then the evader's fix time;
    // zeros stuffed by COBS.
    let decoded = &deframe::<MAX_FRAME>(&bytes).unwrap()[..];
    assert_eq!(
        &decoded[..8],
        &[0x03, 0x02, 0x02, 0x01, 0x01, 0x00, 0x00, 0x00]
    );
    assert_eq!(&decoded[16..20], &1.0f32.to_le_bytes());
    assert_eq!(&decoded[20..24], &(-3.0f32).to_le_bytes());
    assert_eq!(&decoded[32..36], &[0x0D, 0x0C, 0x0B, 0x0A]);
    assert_eq!(decoded.len(), 4 + StateMsg::LEN + 2);
    let crc = crc16(&decoded[..decoded.len() - 2]);
    assert_eq!(&decoded[decoded.len() - 2..], &crc.to_le_bytes());
    assert_eq!(*bytes.last().unwrap(), 0);
    let frame = Frame::new_checked(decoded).unwrap();
    assert_eq!(frame.sequence(), 0x0102);
    assert_eq!(frame.version(), 3);
    assert_eq!(StateMsg::parse(frame.payload()).unwrap(), state);
    // Version 1's State is the first 28 bytes, its evader fixed at the timestamp.
    let v1 = StateMsg::parse_v1(&frame.payload()[..StateMsg::LEN_V1]).unwrap();
    assert_eq!(v1, StateMsg::exact(1, state.pursuer, state.evader));
    assert_eq!(
        StateMsg::parse_v1(frame.payload()),
        Err(WireError::Oversized)
    );
}

#[test]
fn messages_round_trip() {
    let c = Configure {
        limits: [2.0, 2.0, 1.0, 1.0],
        dt: 0.01,
        watchdog: 0.5,
        roles: 3,
        variant: 1,
        policy: 0,
        field: FieldConfig {
            target_lag: 0.2,
            target_sigma: 0.1,
            target_heading_sigma: 0.05,
            own_lead: 0.3,
        },
        team: TeamConfig { size: 3, own: 2 },
    };
    let mut buf = [0u8; 64];
    let mut w = twocars::protocol::frame::Writer::new(&mut buf);
    c.emit(&mut w).unwrap();
    let n = w.len();
    assert_eq!(n, Configure::LEN);
    assert_eq!(Configure::parse(&buf[..n]).unwrap(), c);
    assert_eq!(Configure::parse(&buf[..n - 1]), Err(WireError::Truncated));
    // Version 2 is the same first 43 bytes, without the team.
    let v2 = Configure::parse_v2(&buf[..Configure::LEN_V2]).unwrap();
    assert_eq!(
        v2,
        Configure {
            team: TeamConfig::NONE,
            ..c
        }
    );
    // Version 1 is the same first 27 bytes, without the field's settings.
    let v1 = Configure::parse_v1(&buf[..Configure::LEN_V1]).unwrap();
    assert_eq!(
        v1,
        Configure {
            field: FieldConfig::EXACT,
            team: TeamConfig::NONE,
            ..c
        }
    );
    assert_eq!(
        Configure::parse(&buf[..Configure::LEN_V1]),
        Err(WireError::Truncated)
    );
    let cmd = CommandMsg {
        status: 0,
        roles: 3,
        pursuer_rate: 4.0,
        evader_rate: -1.0,
        row: 0,
        col: 1,
        predicted: 5.5,
        upper: 5.5,
        lower: f32::INFINITY,
        chaser: 2,
    };
    let mut buf = [0u8; 64];
    let mut w = twocars::protocol::frame::Writer::new(&mut buf);
    cmd.emit(&mut w).unwrap();
    let n = w.len();
    assert_eq!(n, CommandMsg::LEN);
    assert_eq!(CommandMsg::parse(&buf[..n]).unwrap(), cmd);
    let mut long = buf[..n].to_vec();
    long.push(0);
    assert_eq!(CommandMsg::parse(&long), Err(WireError::Oversized));
    // Versions 1 and 2: the first 24 bytes, no chaser.
    let v2 = CommandMsg::parse(&buf[..CommandMsg::LEN_V2]).unwrap();
    assert_eq!(
        v2,
        CommandMsg {
            chaser: NO_MEMBER,
            ..cmd
        }
    );
    let mate = TeammateMsg {
        index: 1,
        time_ms: 70_000,
        state: [3.0, -4.0, 0.5],
    };
    let mut w = twocars::protocol::frame::Writer::new(&mut buf);
    mate.emit(&mut w).unwrap();
    let n = w.len();
    assert_eq!(n, TeammateMsg::LEN);
    assert_eq!(TeammateMsg::parse(&buf[..n]).unwrap(), mate);
    assert_eq!(TeammateMsg::parse(&buf[..n - 1]), Err(WireError::Truncated));
}

#[test]
fn frame_checks_refuse_each_defect() {
    assert_eq!(Frame::new_checked(&[1, 2, 0]), Err(WireError::Truncated));
    assert_eq!(
        Frame::new_checked(&[0u8; MAX_FRAME + 1]),
        Err(WireError::Oversized)
    );
    let mut good = [1u8, 2, 7, 0, 0, 0];
    let crc = crc16(&good[..4]).to_le_bytes();
    good[4..].copy_from_slice(&crc);
    assert!(Frame::new_checked(&good).is_ok());
    let mut bad_crc = good;
    bad_crc[2] ^= 0x40;
    assert_eq!(Frame::new_checked(&bad_crc), Err(WireError::BadCrc));
    assert_eq!(Frame::new_checked(&good).unwrap().version(), 1);
    let mut bad_version = good;
    bad_version[0] = 9;
    let crc = crc16(&bad_version[..4]).to_le_bytes();
    bad_version[4..].copy_from_slice(&crc);
    assert_eq!(Frame::new_checked(&bad_version), Err(WireError::BadVersion));
}

#[test]
fn deframer_resynchronises_after_garbage_and_overflow() {
    let state = StateMsg::exact(7, [1.0, 2.0, 3.0], [4.0, 5.0, 6.0]);
    let good = twocars_sim::link::state(9, &state);
    let mut stream = vec![0x13, 0x37, 0xFF, 0x00]; // garbage, then a delimiter
    stream.extend(std::iter::repeat_n(0x55, 100)); // oversized garbage
    stream.push(0);
    stream.extend(&good);
    let mut d = Deframer::<64>::new();
    let mut seen = Vec::new();
    for b in stream {
        match d.push(b) {
            Feed::Pending => {}
            Feed::Error(e) => seen.push(Err(e)),
            Feed::Frame(f) => seen.push(Ok(StateMsg::parse(
                Frame::new_checked(f).unwrap().payload(),
            )
            .unwrap())),
        }
    }
    assert_eq!(seen.len(), 3, "{seen:?}");
    // Back-to-back delimiters are no frame at all; a lone code byte is an empty one.
    assert!((0..3).all(|_| d.push(0) == Feed::Pending));
    assert_eq!(d.push(0x01), Feed::Pending);
    assert_eq!(d.push(0), Feed::Frame(&[]));
    assert!(seen[0].is_err());
    assert_eq!(seen[1], Err(WireError::Oversized));
    assert_eq!(seen[2], Ok(state));
}

#[test]
fn error_codes_are_stable_and_distinct() {
    for (i, e) in WireError::ALL.iter().enumerate() {
        assert_eq!(*e as u8, i as u8 + 1);
        assert_eq!(WireError::from_code(*e as u8), Some(*e));
    }
    assert_eq!(WireError::from_code(0), None);
}

/// `push_slice` (the firmware's loop) and `push` (one byte at a time) make the same frames and
/// refusals of the same stream, cut into slices of every length from 1 to past the stream's.
#[test]
fn deframing_slices_gives_what_deframing_bytes_gives() {
    let state = StateMsg::exact(3, [0.0, -2.5, 1.0], [7.0, 0.0, -3.0]);
    let mut stream = vec![0x13, 0x37, 0xFF, 0x00, 0x00];
    stream.extend(twocars_sim::link::state(1, &state));
    stream.extend(std::iter::repeat_n(0x55, 100));
    stream.push(0);
    stream.extend([0x01, 0x00, 0x03, 0x11, 0x00]);
    stream.extend(twocars_sim::link::state(2, &state));
    let by_byte = twocars_sim::link::deframe(&stream, None);
    assert_eq!(by_byte.len(), 6, "{by_byte:?}");
    for cut in 1..=stream.len() + 1 {
        let by_slice = twocars_sim::link::deframe(&stream, Some(cut));
        assert_eq!(by_slice, by_byte, "slices of {cut}");
    }
}

/// Counters grew by the line's six fault counts (76 bytes), the board's status (80 bytes) and
/// the estimator's two counts (88 bytes): payloads of 52, 76 and 80 bytes still parse (what
/// they lack is 0), each is a prefix of the new layout, and any other length is refused.
#[test]
fn counters_append_the_line_faults_and_the_board_status_and_read_the_old_lengths() {
    use twocars::protocol::message::{Counters, LineCounts};
    let mut c = Counters {
        accepted: 7,
        stale: 1,
        ..Counters::default()
    };
    c.count(WireError::BadCrc);
    c.line = LineCounts {
        overrun: 2,
        framing: 3,
        noise: 4,
        parity: 5,
        rx_full: 6,
        tx_full: 8,
    };
    c.board = 1;
    c.coasted = 9;
    c.fixes_refused = 10;
    let mut buf = [0u8; Counters::LEN];
    let mut w = twocars::protocol::frame::Writer::new(&mut buf);
    c.emit(&mut w).unwrap();
    assert_eq!(w.len(), 88);
    assert_eq!(Counters::parse(&buf), Ok(c));
    assert_eq!(&buf[76..80], &1u32.to_le_bytes());
    assert_eq!(&buf[80..84], &9u32.to_le_bytes());
    assert_eq!(&buf[84..88], &10u32.to_le_bytes());
    let v3 = Counters::parse(&buf[..Counters::LEN_V3]).unwrap();
    assert_eq!((v3.board, v3.coasted, v3.fixes_refused), (1, 0, 0));
    let v2 = Counters::parse(&buf[..Counters::LEN_V2]).unwrap();
    assert_eq!((v2.line, v2.board), (c.line, 0));
    assert_eq!(&buf[52..56], &2u32.to_le_bytes());
    assert_eq!(&buf[72..76], &8u32.to_le_bytes());
    let old = Counters::parse(&buf[..Counters::LEN_V1]).unwrap();
    assert_eq!(old.line, LineCounts::default());
    assert_eq!((old.accepted, old.stale, old.errors), (7, 1, c.errors));
    assert_eq!(Counters::parse(&buf[..60]), Err(WireError::Truncated));
    let mut long = buf.to_vec();
    long.push(0);
    assert_eq!(Counters::parse(&long), Err(WireError::Oversized));
}
