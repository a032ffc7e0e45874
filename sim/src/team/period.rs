//! One period of the pursuers without roles, and what the team's chase and its evaders share:
//! each pursuer's guidance, the host's states narrowed to the guidance's f32.

use twocars::{Guidance, Law, Limits, Policy, Variant};

/// Each pursuer's flight-policy guidance at period `dt`, told the capture radius `eps`.
pub(super) fn guidance<const N: usize>(
    limits: &[[f64; 4]; N],
    dt: f64,
    eps: f64,
) -> Option<[Guidance<f32>; N]> {
    let mut out = Vec::with_capacity(N);
    for l in limits {
        let limits = Limits::<f32>::new(l[0] as f32, l[1] as f32, l[2] as f32, l[3] as f32).ok()?;
        let g = Guidance::new(Law::new(limits, Variant::Paper), dt as f32, Policy::Flight).ok()?;
        out.push(g.with_capture_radius(eps as f32).ok()?);
    }
    out.try_into().ok()
}

pub(super) fn narrow<const K: usize>(s: [f64; K]) -> [f32; K] {
    s.map(|v| v as f32)
}

/// One period's commands of the pursuers (curvature, 1/m; 0 for those not taking part), the
/// law's evader's turn against the one it thinks captures, and the team's predicted time.
pub(super) struct Period<const N: usize> {
    pub curvatures: [f64; N],
    pub law_evader: f64,
    pub predicted: Option<f32>,
}

/// The independent (or lone) pursuers' period: each on its own guidance.
pub(super) fn independent<const N: usize>(
    own: &mut [Guidance<f32>; N],
    active: &[bool; N],
    pursuers: &[[f64; 3]; N],
    evader: [f64; 3],
) -> Period<N> {
    let mut out = Period {
        curvatures: [0.0; N],
        law_evader: 0.0,
        predicted: None,
    };
    for i in (0..N).filter(|&i| active[i]) {
        let limits = own[i].law().limits;
        let Ok((p, e)) = limits.states(narrow(pursuers[i]), narrow(evader)) else {
            continue;
        };
        let d = own[i].decide(&p, &e);
        let [w_p, w_e] = d.curvatures();
        out.curvatures[i] = f64::from(w_p);
        if let Some(time) = d.value_seconds() {
            if out.predicted.is_none_or(|b| time < b) {
                out.predicted = Some(time);
                out.law_evader = f64::from(w_e);
            }
        }
    }
    out
}
