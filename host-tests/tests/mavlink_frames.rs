//! The MAVLink endpoint's input path (`twocars::mavlink`): frames written from the protocol's
//! specification (`twocars_sim::mavlink_spec`, independent of the `mavlink` crate the firmware
//! uses), found in a byte stream one byte at a time, through noise and corruption, and decoded.

use twocars::mavlink::{decode, extra_crc, FrameReader, Message, MessageError, Version};
use twocars_sim::mavlink_spec::{
    param_set_payload, position_payload, v1, v2, FOLLOW_TARGET, GLOBAL_POSITION_INT, HEARTBEAT,
    PARAM_REQUEST_LIST, PARAM_REQUEST_READ, PARAM_SET,
};
use twocars_sim::rng::Rng;

/// Every message decoded from `bytes`, pushed one at a time.
fn read_all(
    reader: &mut FrameReader,
    bytes: &[u8],
) -> Vec<(Version, u8, Result<Message, MessageError>)> {
    let mut out = Vec::new();
    for &b in bytes {
        if let Some(frame) = reader.push(b, extra_crc) {
            out.push((frame.version, frame.sequence, decode(&frame)));
        }
    }
    out
}

fn position(m: &Result<Message, MessageError>) -> (i32, i32, i16, i16, u16) {
    match m {
        Ok(Message::GlobalPosition(p)) => (p.lat, p.lon, p.vx, p.vy, p.hdg),
        other => panic!("not a position: {other:?}"),
    }
}

/// The crate's CRC_EXTRA for our messages is the specification's.
#[test]
fn crc_extras_are_the_specifications() {
    for (id, extra) in [
        GLOBAL_POSITION_INT,
        FOLLOW_TARGET,
        PARAM_SET,
        PARAM_REQUEST_READ,
        PARAM_REQUEST_LIST,
        HEARTBEAT,
    ] {
        assert_eq!(extra_crc(id), Some(extra), "message {id}");
    }
    assert_eq!(extra_crc(30), None); // ATTITUDE: not read
}

/// MAVLink 1 and 2 (truncated and signed) positions, through noise, are decoded field for field.
#[test]
fn positions_in_both_versions_come_through_noise() {
    let mut stream = vec![0x00, 0x55, 0xAA];
    stream.extend(v2(
        1,
        1,
        GLOBAL_POSITION_INT,
        &position_payload(473_977_420, 85_455_940, 150, -220, 9_000),
        false,
    ));
    stream.extend([0x11; 7]);
    // hdg 0 and vy 0 at the end: MAVLink 2 drops the trailing zero bytes.
    stream.extend(v2(
        2,
        2,
        GLOBAL_POSITION_INT,
        &position_payload(-1, 2, 3, 0, 0),
        false,
    ));
    stream.extend(v1(
        3,
        1,
        GLOBAL_POSITION_INT,
        &position_payload(10, -20, -1, 1, 35_999),
    ));
    stream.extend(v2(
        4,
        1,
        GLOBAL_POSITION_INT,
        &position_payload(5, 6, 7, 8, 9),
        true,
    ));
    let mut reader = FrameReader::new();
    let got = read_all(&mut reader, &stream);
    assert_eq!(got.len(), 4, "{got:?}");
    assert_eq!((got[0].0, got[0].1), (Version::V2, 1));
    assert_eq!(
        position(&got[0].2),
        (473_977_420, 85_455_940, 150, -220, 9_000)
    );
    assert_eq!(position(&got[1].2), (-1, 2, 3, 0, 0));
    assert_eq!(
        (got[2].0, position(&got[2].2)),
        (Version::V1, (10, -20, -1, 1, 35_999))
    );
    assert_eq!((got[3].1, position(&got[3].2)), (4, (5, 6, 7, 8, 9)));
    assert_eq!(reader.counters.frames, 4);
    assert_eq!(reader.counters.skipped_bytes, 10);
    assert_eq!(reader.counters.bad_checksum, 0);
}

/// A corrupt frame is dropped and counted; a frame that began inside it is still found; an
/// unknown message is counted and searched through; an unsupported incompatibility flag drops
/// the frame.
#[test]
fn corrupt_unknown_and_flagged_frames_are_counted_and_dropped() {
    let good = v2(
        9,
        1,
        GLOBAL_POSITION_INT,
        &position_payload(1, 2, 3, 4, 5),
        false,
    );
    let mut corrupt = v2(
        8,
        1,
        GLOBAL_POSITION_INT,
        &position_payload(7, 7, 7, 7, 7),
        false,
    );
    corrupt[14] ^= 0x40;
    // The good frame starts inside the corrupt one: cut the corrupt one short after 16 bytes.
    let mut stream = corrupt[..16].to_vec();
    stream.extend(&good);
    // An ATTITUDE (30) frame: not ours, counted and searched through.
    stream.extend(v2(10, 1, (30, 39), &[1; 28], false));
    let mut flagged = v2(
        11,
        1,
        GLOBAL_POSITION_INT,
        &position_payload(1, 1, 1, 1, 1),
        false,
    );
    flagged[2] = 0x02;
    stream.extend(&flagged);
    stream.extend(v2(12, 1, HEARTBEAT, &[0, 0, 0, 0, 18, 8, 0, 4, 3], false));
    let mut reader = FrameReader::new();
    let got = read_all(&mut reader, &stream);
    let sequences: Vec<u8> = got.iter().map(|g| g.1).collect();
    assert_eq!(sequences, vec![9, 12], "{got:?} {:?}", reader.counters);
    assert_eq!(position(&got[0].2), (1, 2, 3, 4, 5));
    assert!(matches!(got[1].2, Ok(Message::Heartbeat(_))));
    assert_eq!(reader.counters.unknown, 1);
    assert_eq!(reader.counters.bad_flags, 1);
    assert!(reader.counters.bad_checksum >= 1, "{:?}", reader.counters);
}

/// An autopilot's clean stream of messages the endpoint does not read, their payloads full of
/// start bytes, between positions: each unknown frame skipped whole, no phantom frame, and each
/// position handed out on its own last byte (nothing holds it up).
#[test]
fn unknown_frames_of_a_clean_stream_are_skipped_whole() {
    let mut reader = FrameReader::new();
    let mut rng = Rng::new(31);
    for k in 0..500_u32 {
        // An AHRS-like frame (id 163) of 28 bytes, a third of them start bytes.
        let payload: Vec<u8> = (0..28)
            .map(|_| match rng.next_u64() % 3 {
                0 => 0xFD,
                1 => 0xFE,
                _ => rng.next_u64() as u8,
            })
            .collect();
        let unknown = v2(k as u8, 1, (163, 127), &payload, false);
        assert!(read_all(&mut reader, &unknown).is_empty());
        let frame = v2(
            k as u8,
            1,
            GLOBAL_POSITION_INT,
            &position_payload(k as i32, 0, 0, 0, 1),
            false,
        );
        let (last, head) = frame.split_last().unwrap();
        assert!(
            read_all(&mut reader, head).is_empty(),
            "frame {k} came early"
        );
        let got = read_all(&mut reader, &[*last]);
        assert_eq!(got.len(), 1, "frame {k}: {:?}", reader.counters);
        assert_eq!(position(&got[0].2).0, k as i32);
    }
    let c = reader.counters;
    assert_eq!((c.frames, c.unknown), (500, 500), "{c:?}");
    assert_eq!(
        (c.bad_checksum, c.bad_flags, c.skipped_bytes),
        (0, 0, 0),
        "{c:?}"
    );
}

/// Random bytes with good frames among them: no panic, and every good frame found (noise would
/// have to form a frame with a good checksum, 1 in 65,536 per start byte, to hide one).
#[test]
fn random_noise_never_panics_and_good_frames_survive() {
    let mut rng = Rng::new(29);
    let mut reader = FrameReader::new();
    let (mut sent, mut found) = (0, 0);
    for k in 0..2_000_u32 {
        let noise: Vec<u8> = (0..(rng.next_u64() % 40))
            .map(|_| rng.next_u64() as u8)
            .collect();
        let frame = v2(
            k as u8,
            1,
            GLOBAL_POSITION_INT,
            &position_payload(k as i32, 0, 0, 0, 1),
            false,
        );
        sent += 1;
        found += read_all(&mut reader, &noise).len();
        found += read_all(&mut reader, &frame).len();
    }
    // Noise that starts a frame (0xFD or 0xFE) claims a length that runs into the good frame
    // behind it; the search resumes after that start byte and finds the good one.
    println!("{found} of {sent} found, {:?}", reader.counters);
    assert_eq!(found, sent, "{:?}", reader.counters);
    assert_eq!(reader.counters.frames as usize, found);
}

/// A message we read but whose field is out of range (PARAM_SET with a parameter type the
/// dialect does not define) decodes to an error, not a value.
#[test]
fn an_undefined_enum_value_is_malformed() {
    // param_type 200: not a MAV_PARAM_TYPE.
    let payload = param_set_payload((1, 191), "TC_V_PM", 1.5, 200);
    let mut reader = FrameReader::new();
    let got = read_all(&mut reader, &v2(1, 255, PARAM_SET, &payload, false));
    assert_eq!(got.len(), 1);
    assert_eq!(got[0].2, Err(MessageError::Malformed(23)));
    // 9: MAV_PARAM_TYPE_REAL32.
    let payload = param_set_payload((1, 191), "TC_V_PM", 1.5, 9);
    let got = read_all(&mut reader, &v2(2, 255, PARAM_SET, &payload, false));
    match &got[0].2 {
        Ok(Message::ParamSet(p)) => assert_eq!((p.param_value, p.target_component), (1.5, 191)),
        other => panic!("{other:?}"),
    }
}
