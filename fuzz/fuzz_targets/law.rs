//! The law on arbitrary f32 bit patterns for limits and states, on the f32 and the fixed-point
//! backends: no panic; statuses agree with an independent check of the input; commands finite and
//! within +-w_max (in 1/m, whatever the backend's units); the sampled command too, under both
//! policies, over two periods. Built with overflow checks (`fuzz/Cargo.toml`): the fixed-point
//! backend's unchecked `+`, `-`, `*` would panic here if the envelope let one overflow.
#![no_main]

use libfuzzer_sys::fuzz_target;
use twocars::num::fixed::Fixed;
use twocars::{Guidance, Law, Policy, Scalar, Status, Variant};
use twocars::law::{evaluate_observation, Observation};

/// Checks one backend; `slack` is the relative tolerance of |w| <= w_max after unit conversion.
fn check<S: Scalar>(observation: &Observation, period: f32, slack: f64) {
    let ev = evaluate_observation::<S>(observation, Variant::Paper);
    let units = ev.units;
    let (wp, we) = (
        units.curvature(ev.command.pursuer),
        units.curvature(ev.command.evader),
    );
    assert!(wp.is_finite() && we.is_finite());
    let fields = observation
        .limits
        .iter()
        .chain(&observation.pursuer)
        .chain(&observation.evader);
    let non_finite = fields.clone().any(|v| !v.is_finite());
    let [v_pm, w_pm, v_em, w_em] = observation.limits;
    let assumption = v_pm > v_em && v_em > 0.0 && w_pm > w_em && w_em > 0.0;
    let (w_pm, w_em) = (
        f64::from(w_pm) * (1.0 + slack),
        f64::from(w_em) * (1.0 + slack),
    );
    if non_finite {
        assert_eq!(ev.status, Status::NonFiniteInput);
    } else if !assumption {
        assert_eq!(ev.status, Status::InvalidLimits);
    }
    if ev.status == Status::Ok || ev.status == Status::NoValidTangent {
        assert!(wp.abs() <= w_pm && we.abs() <= w_em, "{wp} {we}");
        if let Some(r) = ev.report {
            for v in r.matrix().entries.iter().flatten().flatten() {
                assert!(units.seconds(*v).is_finite(), "entry {v:?}");
            }
        }
    } else {
        assert_eq!((wp, we), (0.0, 0.0), "safe command for {:?}", ev.status);
    }
    // The sampled command of a stateful caller, with the fuzzed period.
    if let Ok(scene) = twocars::law::validate::<S>(observation) {
        for policy in [Policy::Paper, Policy::Flight] {
            let Ok(g) = Guidance::new(
                Law::new(scene.limits, Variant::Clamped),
                period,
                twocars::Policy::Paper,
            ) else {
                break;
            };
            let mut g = g.with_policy(policy);
            // Two periods: the second compares with what the first remembered.
            for _ in 0..2 {
                let s = g.step(&scene.pursuer, &scene.evader);
                let (sp, se) = (
                    s.units.curvature(s.command.pursuer),
                    s.units.curvature(s.command.evader),
                );
                assert!(sp.is_finite() && sp.abs() <= w_pm, "{sp}");
                assert!(se.is_finite() && se.abs() <= w_em, "{se}");
            }
        }
    }
}

fuzz_target!(|data: [u32; 11]| {
    let f = data.map(f32::from_bits);
    let observation = Observation {
        limits: [f[0], f[1], f[2], f[3]],
        pursuer: [f[4], f[5], f[6]],
        evader: [f[7], f[8], f[9]],
    };
    check::<f32>(&observation, f[10], 0.0);
    check::<Fixed>(&observation, f[10], 1e-6);
});
