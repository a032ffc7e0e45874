//! The MAVLink 2 guidance endpoint's pure core (docs/mavlink.md; the shared contract's "MAVLink
//! endpoint"; docs/mavlink.md): frames found in the byte stream ([`frame`]), the messages we
//! use decoded from them ([`messages`]) with the `mavlink` crate's common dialect, one message
//! type at a time (its whole dialect costs 51 KB of flash; docs/mavlink.md), the parameters
//! ([`params`]), the frames we send ([`outgoing`]) and the state machine that joins them
//! ([`endpoint`]). The board shells feed it bytes and a clock.

pub mod endpoint;
pub mod frame;
pub mod messages;
pub mod outgoing;
pub mod params;
#[cfg(feature = "firmware")]
pub mod service;

pub use endpoint::{Endpoint, EndpointCounters, Halt};
pub use frame::{Frame, FrameCounters, FrameReader, Version};
pub use messages::{decode, extra_crc, Message, MessageError};
pub use params::{Params, Refusal, SPECS};
