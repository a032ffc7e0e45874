//! Time to capture along a valid tangent (the paper's Algorithm 2).

use crate::law::geometry::Limits;
use crate::num::Scalar;

/// Which reading of Algorithm 2's second branch to use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Variant {
    /// The paper's literal value, also in the overshoot case (pursuer reaches the tangent first and
    /// would pass the evader's tangent point before the evader leaves its circle); it may be below
    /// t_e or negative (paper case 4: t_ca = -0.2580 s).
    #[default]
    Paper,
    /// In the overshoot case the capture is put at t_e, when the evader leaves its circle.
    Clamped,
}

/// Time to capture along one valid tangent, with the pieces Algorithm 2 builds it from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaptureTime<S> {
    /// Time to capture, seconds (the matrix entry).
    pub value: S,
    /// Heading angle the pursuer turns through to reach the tangent, radians in [0, 2 pi).
    pub pursuer_arc: S,
    /// Heading angle the evader turns through to reach the tangent, radians in [0, 2 pi).
    pub evader_arc: S,
    /// The overshoot case: t_p <= t_e and L - v_pm (t_e - t_p) < 0.
    pub overshoot: bool,
}

impl<S: Scalar> CaptureTime<S> {
    /// Times the pursuer and the evader spend on their circles, t_p = r_p alpha_p / v_pm and
    /// t_e = r_e alpha_e / v_em, seconds.
    pub fn turn_times(&self, limits: &Limits<S>) -> (S, S) {
        (
            limits.pursuer_turn_time(self.pursuer_arc),
            limits
                .evader
                .seconds_per_radian()
                .mul_small(self.evader_arc),
        )
    }
}

/// Algorithm 2: time to capture when both players turn through their arcs (radians) at full speed
/// and then run along a tangent of length `tangent_length` (metres).
pub fn capture_time<S: Scalar>(
    limits: &Limits<S>,
    tangent_length: S,
    pursuer_arc: S,
    evader_arc: S,
    variant: Variant,
) -> CaptureTime<S> {
    let e = &limits.evader;
    let mut result = CaptureTime {
        value: S::zero(),
        pursuer_arc,
        evader_arc,
        overshoot: false,
    };
    let (t_p, t_e) = result.turn_times(limits);
    let per_metre = limits.seconds_per_metre_closed();
    result.value = if t_p > t_e {
        // The evader is on the tangent first and runs v_em (t_p - t_e) ahead along it.
        t_p + (tangent_length + (t_p - t_e).mul_small(e.v_max())).mul_nonnegative(per_metre)
    } else {
        // The pursuer is on the tangent first and closes v_pm (t_e - t_p) before the evader leaves.
        let gap = tangent_length - limits.pursuer_run(t_e - t_p);
        result.overshoot = gap < S::zero();
        match (result.overshoot, variant) {
            (true, Variant::Clamped) => t_e,
            _ => t_e + gap.mul_nonnegative(per_metre),
        }
    };
    result
}
