//! The serial guidance protocol: [`frame`] (COBS framing, CRC, the versioned header, field
//! readers and writers), [`message`] (the payloads: Configure, State, Teammate, Command, Error,
//! Counters), [`endpoint`] (the guidance unit: bytes in, replies out, its watchdog and
//! counters) and `team` (the unit's part in a team, feature `serial-team`). Byte-by-byte
//! layout in `docs/protocol.md`; the MAVLink endpoint is `twocars::mavlink` (feature
//! `mavlink`).

pub mod endpoint;
pub mod frame;
pub mod message;
#[cfg(feature = "serial-team")]
#[cfg_attr(docsrs, doc(cfg(feature = "serial-team")))]
pub mod team;
