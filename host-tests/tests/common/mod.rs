//! Shared pieces of the host tests: seeded property runners and random scenes.
#![allow(dead_code)]

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::f64::consts::PI;

/// A property-test runner with a fixed seed; set TWOCARS_SEED to a number to vary it.
pub fn seeded_runner(cases: u32) -> TestRunner {
    let seed: u64 = std::env::var("TWOCARS_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x2CA5_2019);
    let mut bytes = [0u8; 32];
    for (i, chunk) in bytes.chunks_mut(8).enumerate() {
        chunk.copy_from_slice(&(seed.wrapping_add(i as u64)).to_le_bytes());
    }
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &bytes))
}

/// A random scene: limits (v_pm, w_pm, v_em, w_em) satisfying Assumption 1, and both states
/// within `extent` metres of the origin.
#[derive(Clone, Copy, Debug)]
pub struct Scene {
    pub limits: [f64; 4],
    pub pursuer: [f64; 3],
    pub evader: [f64; 3],
}

/// A value's error relative to the reference's magnitude, with a floor of 1 s: near zero (the
/// literal overshoot values of Algorithm 2) a value is a difference of terms seconds long.
pub fn relative_error(ours: f64, reference: f64) -> f64 {
    (ours - reference).abs() / reference.abs().max(1.0)
}

pub fn scene(extent: f64) -> impl Strategy<Value = Scene> {
    (
        0.5f64..3.0,
        1.1f64..3.0,
        0.2f64..2.0,
        1.1f64..4.0,
        [-extent..extent, -extent..extent, -PI..PI],
        [-extent..extent, -extent..extent, -PI..PI],
    )
        .prop_map(|(v_em, v_ratio, w_em, w_ratio, p, e)| Scene {
            limits: [v_em * v_ratio, w_em * w_ratio, v_em, w_em],
            pursuer: p,
            evader: e,
        })
}

/// Random scenes at the paper's limits.
pub fn paper_scene(extent: f64) -> impl Strategy<Value = Scene> {
    (
        [-extent..extent, -extent..extent, -PI..PI],
        [-extent..extent, -extent..extent, -PI..PI],
    )
        .prop_map(|(p, e)| Scene {
            limits: [2.0, 2.0, 1.0, 1.0],
            pursuer: p,
            evader: e,
        })
}

impl Scene {
    pub fn observation(&self) -> twocars::law::Observation {
        twocars::law::Observation {
            limits: self.limits.map(|v| v as f32),
            pursuer: self.pursuer.map(|v| v as f32),
            evader: self.evader.map(|v| v as f32),
        }
    }

    /// The scene as the f32 core sees it, widened back to f64 (so references see the same input).
    pub fn as_f32_rounded(&self) -> Scene {
        let r = |v: f64| f64::from(v as f32);
        Scene {
            limits: self.limits.map(r),
            pursuer: self.pursuer.map(r),
            evader: self.evader.map(r),
        }
    }

    pub fn law<S: twocars::Scalar>(
        &self,
    ) -> (
        twocars::Law<S>,
        twocars::VehicleState<S>,
        twocars::VehicleState<S>,
    ) {
        let s = twocars::law::validate::<S>(&self.observation()).expect("valid scene");
        (
            twocars::Law::new(s.limits, twocars::Variant::Paper),
            s.pursuer,
            s.evader,
        )
    }

    /// The f64 law on the scene's exact f64 states (limits pass through f32, as the door does).
    pub fn law_exact(
        &self,
    ) -> (
        twocars::Law<f64>,
        twocars::VehicleState<f64>,
        twocars::VehicleState<f64>,
    ) {
        let (law, _, _) = self.law::<f64>();
        let st = |[x, y, theta]: [f64; 3]| twocars::VehicleState { x, y, theta };
        (law, st(self.pursuer), st(self.evader))
    }

    pub fn reference(
        &self,
    ) -> (
        twocars_sim::reference::RefVehicle,
        twocars_sim::reference::RefVehicle,
    ) {
        let [v_pm, w_pm, v_em, w_em] = self.limits;
        let v = |v: f64, w: f64, s: [f64; 3]| twocars_sim::reference::RefVehicle {
            v,
            w,
            x: s[0],
            y: s[1],
            theta: s[2],
        };
        (v(v_pm, w_pm, self.pursuer), v(v_em, w_em, self.evader))
    }
}
