//! The paper's simulation cases (Section "Numerical Simulations").

use std::f64::consts::PI;

/// The paper's limits: v_pm, w_pm, v_em, w_em (m/s, 1/m).
pub const PAPER_LIMITS: [f64; 4] = [2.0, 2.0, 1.0, 1.0];
/// The capture distance the closed-loop runs stop at, m: the paper's epsilon, which its cases'
/// capture times are stated for.
pub const EPS: f64 = 0.01;

/// A named initial state: pursuer and evader (x, y, theta) in metres and radians.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// Name, as `cargo xtask` accepts it.
    pub name: &'static str,
    /// Pursuer x, y, theta.
    pub pursuer: [f64; 3],
    /// Evader x, y, theta.
    pub evader: [f64; 3],
    /// Upper value from an independent f64 computation, seconds (5 digits).
    pub expected_value: f64,
}

/// The paper's four cases, p0 = (0, 0, pi/2).
pub fn paper_cases() -> [Case; 4] {
    let p0 = [0.0, 0.0, PI / 2.0];
    [
        Case {
            name: "paper1",
            pursuer: p0,
            evader: [-3.0, -6.0, PI / 2.0],
            expected_value: 5.6575,
        },
        Case {
            name: "paper2",
            pursuer: p0,
            evader: [6.0, 3.0, PI / 2.0],
            expected_value: 6.6072,
        },
        Case {
            name: "paper3",
            pursuer: p0,
            evader: [0.0, -6.0, PI / 2.0],
            expected_value: 5.1641,
        },
        Case {
            name: "paper4",
            pursuer: p0,
            evader: [0.0, 6.0, PI / 2.0 + PI / 6.0],
            expected_value: 5.9778,
        },
    ]
}

/// 3,000 seeded states from `threshold` out to `far` (r_p), each at a random bearing and
/// relative heading: (x, y, phi) in the Hamilton-Jacobi-Isaacs solver's frame, where the
/// theorem's comparison of V with the paper's value is made (`hji::paper::PaperValue::gaps`).
pub fn states_beyond(threshold: f64, far: f64) -> Vec<(f64, f64, f64)> {
    let mut rng = crate::rng::Rng::new(30);
    let pi = std::f64::consts::PI;
    (0..3_000)
        .map(|_| {
            let (d, bearing) = (rng.uniform(threshold, far), rng.uniform(-pi, pi));
            let phi = rng.uniform(-pi, pi);
            (d * bearing.cos(), d * bearing.sin(), phi)
        })
        .collect()
}
