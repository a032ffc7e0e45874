//! The autopilot's side of the MAVLink endpoint's frame: a simulated vehicle's local north-east
//! metres to the degE7 fix and centidegree heading an autopilot reports (f64, equirectangular
//! on WGS 84's radii about a home fix, the model `twocars::geodetic` inverts).

/// WGS 84 semi-major axis, metres.
const A: f64 = 6_378_137.0;
/// WGS 84 first eccentricity squared.
const E2: f64 = 6.694_379_990_14e-3;

/// Home of the simulations: PX4 SITL's default (Zurich), degE7.
pub const HOME: (i32, i32) = (473_977_420, 85_455_940);

/// A local north-east plane about a home fix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    home: (i32, i32),
    /// Metres per degE7 north and east.
    per_unit: (f64, f64),
}

impl Plane {
    /// The plane about `home` (degE7).
    pub fn new(home: (i32, i32)) -> Self {
        let lat = (f64::from(home.0) * 1e-7).to_radians();
        let w2 = 1.0 - E2 * lat.sin().powi(2);
        let meridian = A * (1.0 - E2) / (w2 * w2.sqrt());
        let prime_vertical = A / w2.sqrt();
        let radians_per_unit = 1e-7_f64.to_radians();
        Plane {
            home,
            per_unit: (
                meridian * radians_per_unit,
                prime_vertical * lat.cos() * radians_per_unit,
            ),
        }
    }

    /// The fix (degE7, rounded) `north`, `east` metres from home.
    pub fn fix(&self, north: f64, east: f64) -> (i32, i32) {
        (
            self.home.0 + (north / self.per_unit.0).round() as i32,
            self.home.1 + (east / self.per_unit.1).round() as i32,
        )
    }

    /// The metres north and east of home of a fix.
    pub fn local(&self, (lat, lon): (i32, i32)) -> (f64, f64) {
        (
            f64::from(lat - self.home.0) * self.per_unit.0,
            f64::from(lon - self.home.1) * self.per_unit.1,
        )
    }
}

/// A heading (rad, clockwise from north) in centidegrees within 0 to 35999, as
/// GLOBAL_POSITION_INT's `hdg`.
pub fn hdg_cdeg(theta: f64) -> u16 {
    let cdeg = (theta.rem_euclid(std::f64::consts::TAU).to_degrees() * 100.0).round();
    (cdeg as u32 % 36_000) as u16
}

/// A velocity (cm/s) north and east at `speed` m/s along heading `theta`.
pub fn velocity_cm_s(speed: f64, theta: f64) -> (i16, i16) {
    let cm = |v: f64| (v * 100.0).round().clamp(-32_767.0, 32_767.0) as i16;
    (cm(speed * theta.cos()), cm(speed * theta.sin()))
}
