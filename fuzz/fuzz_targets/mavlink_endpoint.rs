//! Arbitrary bytes into the whole MAVLink endpoint (`twocars::mavlink::Endpoint`): frames,
//! parameters, fixes, staleness. Our clock advances 1 ms per byte and the loop's check runs
//! every 64 bytes. No panic; everything the endpoint sends reads back, through the frame
//! reader with the CRC_EXTRA of the five messages it sends, as whole MAVLink 2 frames, one per
//! frame sent, with no byte between them; and no setpoint carries a non-finite value.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mavlink::dialects::common::{
    HEARTBEAT_DATA, NAMED_VALUE_FLOAT_DATA, PARAM_VALUE_DATA, SET_ATTITUDE_TARGET_DATA,
    STATUSTEXT_DATA,
};
use mavlink::{MavlinkVersion, MessageData};
use twocars::mavlink::{Endpoint, FrameReader};

fn sent_extra_crc(id: u32) -> Option<u8> {
    Some(match id {
        HEARTBEAT_DATA::ID => HEARTBEAT_DATA::EXTRA_CRC,
        NAMED_VALUE_FLOAT_DATA::ID => NAMED_VALUE_FLOAT_DATA::EXTRA_CRC,
        PARAM_VALUE_DATA::ID => PARAM_VALUE_DATA::EXTRA_CRC,
        SET_ATTITUDE_TARGET_DATA::ID => SET_ATTITUDE_TARGET_DATA::EXTRA_CRC,
        STATUSTEXT_DATA::ID => STATUSTEXT_DATA::EXTRA_CRC,
        _ => return None,
    })
}

fuzz_target!(|data: &[u8]| {
    let mut endpoint = Endpoint::new();
    let mut out = Vec::new();
    let mut sent = 0_u32;
    for (i, &byte) in data.iter().enumerate() {
        let now = i as u32;
        let mut send = |frame: &[u8]| {
            out.extend_from_slice(frame);
            sent += 1;
        };
        if i % 64 == 0 {
            endpoint.poll(now, &mut send);
        }
        endpoint.receive(byte, now, &mut send);
    }
    let mut reader = FrameReader::new();
    for &byte in &out {
        if let Some(frame) = reader.push(byte, sent_extra_crc) {
            if frame.message_id == SET_ATTITUDE_TARGET_DATA::ID {
                let m = SET_ATTITUDE_TARGET_DATA::deser(MavlinkVersion::V2, frame.payload)
                    .expect("a setpoint decodes");
                assert!(m.body_yaw_rate.is_finite() && m.q.iter().all(|v| v.is_finite()));
                assert_eq!(m.thrust, 1.0);
            }
        }
    }
    assert_eq!(reader.counters.frames, sent);
    assert_eq!(reader.counters.skipped_bytes, 0);
});
