//! Arbitrary bytes (split and concatenated frames, garbage) through the deframer, the frame
//! check and every message parser: no panic; every frame that passes its checks parses or is
//! refused with an error; fed in slices (cut where the first byte says), the deframer makes the
//! same frames and refusals as fed byte by byte.
#![no_main]

use libfuzzer_sys::fuzz_target;
use twocars::message::{kind, CommandMsg, Configure, Counters, ErrorMsg, StateMsg};
use twocars::wire::{Deframer, Feed, Frame, MAX_FRAME};

/// A feed as a value: `None` for `Pending`.
fn owned(feed: Feed<'_>) -> Option<Result<Vec<u8>, twocars::wire::WireError>> {
    match feed {
        Feed::Pending => None,
        Feed::Frame(f) => Some(Ok(f.to_vec())),
        Feed::Error(e) => Some(Err(e)),
    }
}

fuzz_target!(|data: &[u8]| {
    let cut = usize::from(data.first().copied().unwrap_or(1).max(1));
    let mut by_slice = Vec::new();
    let mut sliced = Deframer::<MAX_FRAME>::new();
    for chunk in data.chunks(cut) {
        let mut rest = chunk;
        while !rest.is_empty() {
            let (taken, feed) = sliced.push_slice(rest);
            assert!(taken >= 1 && taken <= rest.len());
            by_slice.extend(owned(feed));
            rest = rest.get(taken..).unwrap_or(&[]);
        }
    }
    let mut by_byte = Vec::new();
    let mut deframer = Deframer::<MAX_FRAME>::new();
    for &byte in data {
        let feed = deframer.push(byte);
        if let Feed::Frame(bytes) = feed {
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
        by_byte.extend(owned(feed));
    }
    assert_eq!(by_slice, by_byte);
});
