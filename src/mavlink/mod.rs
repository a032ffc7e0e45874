//! The MAVLink 2 guidance endpoint's pure core (issue 29; `../shared/CONTRACTS.md`, "MAVLink
//! endpoint"; docs/mavlink.md): frames found in the byte stream ([`frame`]) and the messages we
//! use decoded from them ([`messages`]) with the `mavlink` crate's common dialect, one message
//! type at a time (its whole dialect costs 51 KB of flash; docs/mavlink.md). The board shells,
//! parameters and outputs come next.

pub mod frame;
pub mod messages;

pub use frame::{Frame, FrameCounters, FrameReader, Version};
pub use messages::{decode, extra_crc, Message, MessageError};
