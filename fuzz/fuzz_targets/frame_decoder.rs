//! Arbitrary bytes (split and concatenated frames, garbage) through the deframer, the frame
//! check and every message parser: no panic; every frame that passes its checks parses or is
//! refused with an error; fed in slices (cut where the first byte says), the deframer makes the
//! same frames and refusals as fed byte by byte.
#![no_main]

use libfuzzer_sys::fuzz_target;
use twocars::protocol::frame::{Deframer, Feed, Frame, MAX_FRAME};
use twocars::protocol::message::{kind, CommandMsg, Configure, Counters, ErrorMsg, StateMsg};

fuzz_target!(|data: &[u8]| {
    let cut = usize::from(data.first().copied().unwrap_or(1));
    let by_slice = twocars_sim::link::deframe(data, Some(cut));
    let mut deframer = Deframer::<MAX_FRAME>::new();
    for &byte in data {
        if let Feed::Frame(bytes) = deframer.push(byte) {
            assert!(bytes.len() <= MAX_FRAME);
            if let Ok(frame) = Frame::new_checked(bytes) {
                let payload = frame.payload();
                let _ = match frame.message_type() {
                    kind::CONFIGURE => Configure::parse(payload).map(|_| ()),
                    kind::STATE => StateMsg::parse(payload).map(|_| ()),
                    kind::COMMAND => CommandMsg::parse(payload).map(|_| ()),
                    kind::COUNTERS => Counters::parse(payload).map(|_| ()),
                    kind::ERROR => ErrorMsg::parse(payload).map(|_| ()),
                    _ => Ok(()),
                };
            }
        }
    }
    assert_eq!(by_slice, twocars_sim::link::deframe(data, None));
});
