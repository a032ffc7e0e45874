//! Arbitrary bytes through the MAVLink endpoint's input path (`twocars::mavlink`): the frame
//! search and the decoder of every message it hands out. No panic; every frame handed out is
//! one of ours (a known CRC_EXTRA) with at most 255 payload bytes; the reader's frame count is
//! the number handed out; and the same frames, decoding or failing alike, come out when the
//! bytes are fed again after a reset (the search keeps no state beyond its buffer).
#![no_main]

use libfuzzer_sys::fuzz_target;
use twocars::mavlink::{decode, extra_crc, FrameReader};

fuzz_target!(|data: &[u8]| {
    let run = |reader: &mut FrameReader| {
        let mut out = Vec::new();
        for &byte in data {
            if let Some(frame) = reader.push(byte, extra_crc) {
                assert!(frame.payload.len() <= 255);
                assert!(extra_crc(frame.message_id).is_some());
                // Compared by their bytes: a decoded NaN field is not equal to itself.
                let decoded = decode(&frame).map(|_| ());
                out.push((
                    frame.message_id,
                    frame.sequence,
                    frame.payload.to_vec(),
                    decoded,
                ));
            }
        }
        out
    };
    let mut first = FrameReader::new();
    let once = run(&mut first);
    assert_eq!(first.counters.frames as usize, once.len());
    assert_eq!(once, run(&mut FrameReader::new()));
});
