//! The law on arbitrary f32 bit patterns for limits and states: no panic; statuses agree with an
//! independent check of the input; commands finite and within +-w_max; the sampled command too.
#![no_main]

use libfuzzer_sys::fuzz_target;
use twocars::{evaluate_observation, Guidance, Law, Observation, Status, Variant};

fuzz_target!(|data: [u32; 11]| {
    let f = data.map(f32::from_bits);
    let observation = Observation {
        limits: [f[0], f[1], f[2], f[3]],
        pursuer: [f[4], f[5], f[6]],
        evader: [f[7], f[8], f[9]],
    };
    let ev = evaluate_observation::<f32>(&observation, Variant::Paper);
    let c = ev.command;
    assert!(c.pursuer.is_finite() && c.evader.is_finite());
    let non_finite = f[..10].iter().any(|v| !v.is_finite());
    let [v_pm, w_pm, v_em, w_em] = observation.limits;
    let assumption = v_pm > v_em && v_em > 0.0 && w_pm > w_em && w_em > 0.0;
    if non_finite {
        assert_eq!(ev.status, Status::NonFiniteInput);
    } else if !assumption {
        assert_eq!(ev.status, Status::InvalidLimits);
    }
    if ev.status == Status::Ok || ev.status == Status::NoValidTangent {
        assert!(c.pursuer.abs() <= w_pm && c.evader.abs() <= w_em);
        if let Some(r) = ev.report {
            for v in r.matrix.entries.iter().flatten().flatten() {
                assert!(v.is_finite(), "entry {v}");
            }
        }
    } else {
        assert_eq!((c.pursuer, c.evader), (0.0, 0.0), "safe command for {:?}", ev.status);
    }
    // The sampled command of a stateful caller, with a period from the last word.
    if let Ok(scene) = twocars::law::validate::<f32>(&observation) {
        if let Ok(mut g) = Guidance::new(Law::new(scene.limits, Variant::Clamped), f[10]) {
            let s = g.step(&scene.pursuer, &scene.evader).command;
            assert!(s.pursuer.is_finite() && s.pursuer.abs() <= w_pm);
            assert!(s.evader.is_finite() && s.evader.abs() <= w_em);
        }
    }
});
