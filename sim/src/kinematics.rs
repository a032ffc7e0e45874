//! Exact Dubins motion and the angles and distances the simulators share.

/// Exact Dubins motion for `t` seconds at speed `v` (m/s) and curvature `w` (1/m).
pub fn advance(state: [f64; 3], v: f64, w: f64, t: f64) -> [f64; 3] {
    let [x, y, theta] = state;
    let turned = v * w * t;
    if turned.abs() < 1e-9 {
        // Straight, plus the second-order term of the arc.
        let mid = theta + 0.5 * turned;
        return [x + v * t * mid.cos(), y + v * t * mid.sin(), theta + turned];
    }
    let th = theta + turned;
    [
        x + (th.sin() - theta.sin()) / w,
        y - (th.cos() - theta.cos()) / w,
        th,
    ]
}

/// The smallest angle (radians, in [0, pi]) between two headings: how far `got` is from `want`
/// round the circle, so that -pi and pi are 0 apart.
pub fn angle_error(got: f64, want: f64) -> f64 {
    wrap_pi(got - want).abs()
}

/// An angle reduced to (-pi, pi], radians.
pub fn wrap_pi(theta: f64) -> f64 {
    let t = theta.rem_euclid(std::f64::consts::TAU);
    if t > std::f64::consts::PI {
        t - std::f64::consts::TAU
    } else {
        t
    }
}

/// The distance (m) between two states' positions.
pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}
