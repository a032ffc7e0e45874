//! The serial guidance protocol: [`frame`] (COBS framing, CRC, the versioned header, field
//! readers and writers), [`message`] (the payloads: Configure, State, Command, Error,
//! Counters) and [`endpoint`] (the guidance unit: bytes in, replies out, its watchdog and
//! counters). Byte-by-byte layout in `docs/protocol.md`; the MAVLink endpoint is
//! `twocars::mavlink` (feature `mavlink`).

pub mod endpoint;
pub mod frame;
pub mod message;
