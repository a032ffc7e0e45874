//! The unit and ArduPilot SITL joined: the router between the unit's link and SITL's serial
//! port, signed where a key is given.

use twocars_sim::autopilot::HOME;

use super::sitl::{connect_serial1, setup_signing, Frame, Launch, Sitl};
use crate::harness::autopilot::message::UNIT_READS;
use crate::harness::autopilot::router::Router;
use crate::harness::autopilot::unit::{self, Unit};
use crate::image::signing::SigningKey;

/// The unit (the QEMU image or the companion), SITL instance 0 of `frame` at home running
/// `speedup` times the wall clock, and the router between them: signed both ways with `key`
/// where given; for ArduPlane, passing the unit only what it reads.
pub fn connect(
    binary: &std::path::Path,
    frame: Frame,
    speedup: u32,
    companion: bool,
    key: Option<&SigningKey>,
) -> Result<(Unit, Sitl, Router), String> {
    let (launched, unit) = unit::start(companion, key)?;
    let home = (f64::from(HOME.0) * 1e-7, f64::from(HOME.1) * 1e-7);
    let launch = Launch {
        frame,
        instance: 0,
        home,
        heading: 0.0,
        speedup,
    };
    let (sitl, mut serial0) = Sitl::start(binary, launch)?;
    let mut router = match key {
        None => Router::new(serial0, unit)?,
        Some(key) => {
            let key = key.bytes();
            // The key goes to ArduPilot on SERIAL0, as a ground station's USB link gives it;
            // the unit flies on SERIAL1, where ArduPilot signs and checks.
            setup_signing(&mut serial0, key)?;
            Router::new(connect_serial1(0)?, unit)?.with_signing(key, serial0)?
        }
    };
    // ArduPlane flies at 4x, where its whole stream (about 14.5 kB/s of wall clock) outruns
    // QEMU's UART, which takes it a byte at a time (docs/ardupilot.md).
    if frame == Frame::Plane {
        router.pass_to_unit(Some(&UNIT_READS));
    }
    Ok((launched, sitl, router))
}
