//! An autopilot's fixes and headings in the law's frame (the MAVLink endpoint).
//!
//! MAVLink gives positions as latitude and longitude in degE7 (1e-7 degree) and headings in
//! centidegrees clockwise from north. Here they become metres in a local north-east plane about
//! a reference fix (the first own fix): **x = north, y = east, theta = the heading clockwise
//! from north**, in radians. The law's kinematics (x' = v cos theta, y' = v sin theta,
//! theta' = v w) hold unchanged in that frame; since it is mirrored against the usual
//! anticlockwise x-y plane, a positive turn rate turns the vehicle **clockwise seen from
//! above**, which is also the sign of MAVLink's body yaw rate (NED, z down).
//!
//! The projection is equirectangular about the reference, on the WGS 84 ellipsoid's radii of
//! curvature there: north = M(phi0) dphi, east = N(phi0) cos(phi0) dlambda. Its error against
//! the exact local tangent plane (geodetic to earth-centred to east-north-up, in f64) within
//! 10 km of the reference is bounded in `host-tests/tests/geodetic.rs` and stated in
//! docs/mavlink.md. Degree differences are formed in integers (exact, across the antimeridian
//! too) before they are scaled.

use crate::num::Scalar;

/// WGS 84 semi-major axis, metres.
const WGS84_A: f32 = 6_378_137.0;
/// WGS 84 first eccentricity squared.
const WGS84_E2: f32 = 6.694_38e-3;
/// One degE7 in radians.
const RADIANS_PER_DEGE7: f32 = core::f32::consts::PI / 180.0e7;
/// 180 degrees in degE7: latitude spans +-half of it, longitude +-all of it.
const HALF_TURN_DEGE7: i64 = 1_800_000_000;
/// MAVLink's "heading unknown" (GLOBAL_POSITION_INT.hdg).
pub const HEADING_UNKNOWN: u16 = u16::MAX;
/// Standard gravity, m/s^2: the coordinated turn's bank angle.
pub const STANDARD_GRAVITY: f32 = 9.806_65;

/// A local north-east plane about a reference fix: metres per degE7 along each axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalFrame {
    /// The reference latitude and longitude, degE7.
    origin: (i32, i32),
    /// M(phi0) per degE7 of latitude, metres.
    north_per_unit: f32,
    /// N(phi0) cos(phi0) per degE7 of longitude, metres.
    east_per_unit: f32,
}

impl LocalFrame {
    /// The plane about the fix (`lat`, `lon`) in degE7; `None` outside +-90 and +-180 degrees.
    pub fn new(lat: i32, lon: i32) -> Option<Self> {
        if !valid_fix(lat, lon) {
            return None;
        }
        let (sin, cos) = Scalar::sin_cos(lat as f32 * RADIANS_PER_DEGE7);
        let w2 = 1.0 - WGS84_E2 * sin * sin;
        let w = Scalar::sqrt(w2);
        // Meridian radius M = a (1 - e^2) / w^3, prime vertical radius N = a / w.
        let meridian = WGS84_A * (1.0 - WGS84_E2) / (w2 * w);
        let prime_vertical = WGS84_A / w;
        Some(LocalFrame {
            origin: (lat, lon),
            north_per_unit: meridian * RADIANS_PER_DEGE7,
            east_per_unit: prime_vertical * cos * RADIANS_PER_DEGE7,
        })
    }

    /// The fix (`lat`, `lon`) in degE7 as (north, east) metres from the reference; `None`
    /// outside +-90 and +-180 degrees. Longitude differences wrap across the antimeridian.
    pub fn to_local(&self, lat: i32, lon: i32) -> Option<(f32, f32)> {
        if !valid_fix(lat, lon) {
            return None;
        }
        let north_units = i64::from(lat) - i64::from(self.origin.0);
        let mut east_units = i64::from(lon) - i64::from(self.origin.1);
        if east_units > HALF_TURN_DEGE7 {
            east_units -= 2 * HALF_TURN_DEGE7;
        } else if east_units < -HALF_TURN_DEGE7 {
            east_units += 2 * HALF_TURN_DEGE7;
        }
        // Both within +-180 degrees (1.8e9 degE7), so i32 holds them: its conversion to f32
        // is one instruction on an FPU, where i64's is a library call.
        let (north_units, east_units) = (north_units as i32, east_units as i32);
        Some((
            north_units as f32 * self.north_per_unit,
            east_units as f32 * self.east_per_unit,
        ))
    }
}

impl LocalFrame {
    /// The fix (degE7, rounded) `north`, `east` metres from the reference: the inverse of
    /// [`LocalFrame::to_local`] (a simulated autopilot's report); `None` off the globe.
    pub fn to_fix(&self, north: f32, east: f32) -> Option<(i32, i32)> {
        let lat = i64::from(self.origin.0) + libm::roundf(north / self.north_per_unit) as i64;
        let lon = i64::from(self.origin.1) + libm::roundf(east / self.east_per_unit) as i64;
        let (lat, lon) = (i32::try_from(lat).ok()?, i32::try_from(lon).ok()?);
        valid_fix(lat, lon).then_some((lat, lon))
    }
}

/// Whether a fix's latitude is within +-90 degrees and its longitude within +-180: integer
/// comparisons alone, cheap enough to check every fix on arrival.
pub fn valid_fix(lat: i32, lon: i32) -> bool {
    i64::from(lat).abs() <= HALF_TURN_DEGE7 / 2 && i64::from(lon).abs() <= HALF_TURN_DEGE7
}

/// A heading in centidegrees clockwise from north (GLOBAL_POSITION_INT.hdg) in radians,
/// within (-pi, pi]; `None` for [`HEADING_UNKNOWN`] or beyond 359.99 degrees.
pub fn heading_from_cdeg(hdg: u16) -> Option<f32> {
    if hdg >= 36_000 {
        return None;
    }
    let degrees = if hdg > 18_000 {
        f32::from(hdg) - 36_000.0
    } else {
        f32::from(hdg)
    };
    Some(degrees * (core::f32::consts::PI / 18_000.0))
}

/// The course over ground (radians clockwise from north, within (-pi, pi]) of a velocity
/// `north`, `east` (any one unit); `None` below `min_speed` (same unit) or not finite: there
/// the direction of travel is noise.
pub fn course(north: f32, east: f32, min_speed: f32) -> Option<f32> {
    let speed_squared = north * north + east * east;
    (speed_squared.is_finite() && speed_squared >= min_speed * min_speed && speed_squared > 0.0)
        .then(|| <f32 as Scalar>::atan2(east, north))
}

/// The yaw (radians clockwise from north, within (-pi, pi]) of an attitude quaternion
/// (w, x, y, z) from the body frame (x forward, z down) to north-east-down, as FOLLOW_TARGET
/// carries it; `None` when not finite or far from unit length (|q|^2 outside 0.9 to 1.1: an
/// unset attitude is all zeros).
pub fn yaw_from_quaternion([w, x, y, z]: [f32; 4]) -> Option<f32> {
    let norm_squared = w * w + x * x + y * y + z * z;
    if !(0.9..=1.1).contains(&norm_squared) {
        return None;
    }
    Some(<f32 as Scalar>::atan2(
        2.0 * (w * z + x * y),
        1.0 - 2.0 * (y * y + z * z),
    ))
}

/// The bank angle (radians, positive right wing down) of a coordinated level turn at `speed`
/// (m/s) and turn rate `turn_rate` (rad/s, positive clockwise from above):
/// phi = atan(v omega / g).
pub fn bank_angle(speed: f32, turn_rate: f32) -> f32 {
    <f32 as Scalar>::atan2(speed * turn_rate, STANDARD_GRAVITY)
}
