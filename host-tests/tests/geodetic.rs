//! The autopilot's fixes and headings in the law's frame (`twocars::geodetic`), against an
//! independent f64 reference: geodetic to earth-centred (WGS 84) to the exact local tangent plane
//! (east-north-up) at the reference fix.

use std::f64::consts::PI;
use twocars::geodetic::{
    bank_angle, course, heading_from_cdeg, yaw_from_quaternion, LocalFrame, HEADING_UNKNOWN,
};

const A: f64 = 6_378_137.0;
const F: f64 = 1.0 / 298.257_223_563;

/// Earth-centred, earth-fixed coordinates (metres) of a point on the WGS 84 ellipsoid.
fn ecef(lat: f64, lon: f64) -> [f64; 3] {
    let e2 = F * (2.0 - F);
    let n = A / (1.0 - e2 * lat.sin().powi(2)).sqrt();
    [
        n * lat.cos() * lon.cos(),
        n * lat.cos() * lon.sin(),
        n * (1.0 - e2) * lat.sin(),
    ]
}

/// (north, east) metres of (lat, lon) in the tangent plane at (lat0, lon0); radians.
fn tangent_plane(lat0: f64, lon0: f64, lat: f64, lon: f64) -> (f64, f64) {
    let (o, p) = (ecef(lat0, lon0), ecef(lat, lon));
    let d = [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
    let east = -lon0.sin() * d[0] + lon0.cos() * d[1];
    let north =
        -lat0.sin() * lon0.cos() * d[0] - lat0.sin() * lon0.sin() * d[1] + lat0.cos() * d[2];
    (north, east)
}

fn dege7(radians: f64) -> i32 {
    (radians.to_degrees() * 1e7).round() as i32
}

fn radians(dege7: i32) -> f64 {
    (f64::from(dege7) * 1e-7).to_radians()
}

/// The fix about `dn`, `de` metres from (lat0, lon0) degE7 (a spherical step: only a place to
/// look, the reference positions come from the fix itself).
fn fix_near(lat0: i32, lon0: i32, dn: f64, de: f64) -> (i32, i32) {
    let lat = radians(lat0) + dn / A;
    let mut lon = radians(lon0) + de / (A * radians(lat0).cos());
    if lon > PI {
        lon -= 2.0 * PI;
    } else if lon < -PI {
        lon += 2.0 * PI;
    }
    (dege7(lat), dege7(lon))
}

/// Within 10 km of the reference the projection's position error against the tangent plane is
/// second order, below d^2 (1 + tan |phi0|) / a (15.7 m (1 + tan |phi0|) at d = 10 km), and a
/// 100 m baseline anywhere in that disc keeps its length and direction within
/// 2 d (1 + tan |phi0|) / a of itself (relative): what the law sees is the baseline.
#[test]
fn within_10_km_the_projection_is_within_its_second_order_error() {
    let d = 10_000.0;
    println!("| latitude | worst position error within 10 km | worst 100 m baseline error |");
    for (lat_deg, lon_deg) in [
        (0.0, 0.0),
        (30.0, 12.5),
        (-45.0, 170.0),
        (60.0, -179.99),
        (75.0, 90.0),
    ] {
        let (lat0, lon0) = (
            dege7(f64::to_radians(lat_deg)),
            dege7(f64::to_radians(lon_deg)),
        );
        let frame = LocalFrame::new(lat0, lon0).expect("a valid reference");
        let slope = 1.0 + f64::to_radians(lat_deg).tan().abs();
        let (mut worst, mut worst_baseline) = (0.0_f64, 0.0_f64);
        for ring in [1.0, 10.0, 100.0, 1_000.0, 5_000.0, 9_900.0] {
            for k in 0..48 {
                let bearing = 2.0 * PI * f64::from(k) / 48.0;
                let (lat, lon) = fix_near(lat0, lon0, ring * bearing.cos(), ring * bearing.sin());
                let (n, e) = frame.to_local(lat, lon).expect("a valid fix");
                let (tn, te) =
                    tangent_plane(radians(lat0), radians(lon0), radians(lat), radians(lon));
                worst = worst.max((f64::from(n) - tn).hypot(f64::from(e) - te));
                // A 100 m baseline from there, across the bearing.
                let across = bearing + PI / 2.0;
                let (lat1, lon1) = fix_near(lat, lon, 100.0 * across.cos(), 100.0 * across.sin());
                let (n1, e1) = frame.to_local(lat1, lon1).expect("a valid fix");
                let (tn1, te1) =
                    tangent_plane(radians(lat0), radians(lon0), radians(lat1), radians(lon1));
                let ours = (f64::from(n1 - n), f64::from(e1 - e));
                let exact = (tn1 - tn, te1 - te);
                let error = (ours.0 - exact.0).hypot(ours.1 - exact.1) / exact.0.hypot(exact.1);
                worst_baseline = worst_baseline.max(error);
            }
        }
        println!("| {lat_deg} | {worst:.3} m | {:.2e} |", worst_baseline);
        assert!(worst <= d * d * slope / A, "{lat_deg}: {worst} m");
        assert!(
            worst_baseline <= 2.0 * d * slope / A,
            "{lat_deg}: {worst_baseline}"
        );
    }
}

/// Across the antimeridian the east offset is the short way round, and a fix beyond +-90 or
/// +-180 degrees is refused.
#[test]
fn the_antimeridian_is_crossed_the_short_way_and_bad_fixes_are_refused() {
    let frame = LocalFrame::new(0, 1_799_999_000).expect("valid");
    let (n, e) = frame.to_local(0, -1_799_999_000).expect("valid");
    let (_, te) = tangent_plane(0.0, radians(1_799_999_000), 0.0, radians(-1_799_999_000));
    assert!(n == 0.0 && (f64::from(e) - te).abs() < 1e-3, "{e} vs {te}");
    assert!(e > 22.0 && e < 23.0);
    assert_eq!(LocalFrame::new(900_000_001, 0), None);
    assert_eq!(LocalFrame::new(0, -1_800_000_001), None);
    assert_eq!(frame.to_local(-900_000_001, 0), None);
    assert!(LocalFrame::new(-900_000_000, 1_800_000_000).is_some());
}

/// Headings: centidegrees clockwise from north to radians in (-pi, pi]; unknown and
/// out-of-range values refused; course from a velocity; yaw from FOLLOW_TARGET's quaternion.
#[test]
fn headings_come_clockwise_from_north_and_unknowns_are_refused() {
    let close = |a: Option<f32>, b: f64| (f64::from(a.expect("a heading")) - b).abs() < 1e-5;
    assert!(close(heading_from_cdeg(0), 0.0));
    assert!(close(heading_from_cdeg(9_000), PI / 2.0));
    assert!(close(heading_from_cdeg(18_000), PI));
    assert!(close(heading_from_cdeg(27_000), -PI / 2.0));
    assert!(close(heading_from_cdeg(35_999), -0.01_f64.to_radians()));
    assert_eq!(heading_from_cdeg(36_000), None);
    assert_eq!(heading_from_cdeg(HEADING_UNKNOWN), None);

    assert!(close(course(5.0, 0.0, 0.5), 0.0));
    assert!(close(course(0.0, 5.0, 0.5), PI / 2.0));
    assert!(close(course(-3.0, -3.0, 0.5), -3.0 * PI / 4.0));
    assert_eq!(course(0.3, 0.3, 0.5), None);
    assert_eq!(course(0.0, 0.0, 0.0), None);
    assert_eq!(course(f32::NAN, 1.0, 0.5), None);

    // Yaw psi, then pitch and roll (ZYX): q = qz(psi) qy(theta) qx(phi).
    let quaternion = |psi: f64, theta: f64, phi: f64| {
        let (cy, sy) = ((psi / 2.0).cos(), (psi / 2.0).sin());
        let (cp, sp) = ((theta / 2.0).cos(), (theta / 2.0).sin());
        let (cr, sr) = ((phi / 2.0).cos(), (phi / 2.0).sin());
        [
            cr * cp * cy + sr * sp * sy,
            sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
        ]
        .map(|c| c as f32)
    };
    for psi in [-3.0, -1.2, 0.0, 0.5, PI / 2.0, 3.1] {
        for (theta, phi) in [(0.0, 0.0), (0.3, -0.4), (-0.2, 0.7)] {
            assert!(close(yaw_from_quaternion(quaternion(psi, theta, phi)), psi));
        }
    }
    assert_eq!(yaw_from_quaternion([0.0; 4]), None);
    assert_eq!(yaw_from_quaternion([f32::NAN, 0.0, 0.0, 1.0]), None);
}

/// The coordinated turn's bank angle, atan(v omega / g): right wing down for a clockwise turn.
#[test]
fn the_bank_angle_is_that_of_a_coordinated_turn() {
    let g = 9.806_65_f64;
    for (v, omega) in [(20.0_f32, 0.49_f32), (15.0, -0.3), (0.0, 1.0), (30.0, 2.0)] {
        let exact = (f64::from(v) * f64::from(omega) / g).atan();
        assert!(
            (f64::from(bank_angle(v, omega)) - exact).abs() < 1e-5,
            "{v} {omega}"
        );
    }
    assert!(bank_angle(20.0, 0.49) > 0.0 && bank_angle(20.0, -0.49) < 0.0);
}
