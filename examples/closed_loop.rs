//! A closed loop on the host: every 10 ms both players take the sampled command of one
//! guidance (the pursuer's flight policy; the evader plays the paper's law) and move along
//! exact Dubins arcs, from the paper's case 1 until the pursuer is within 1 cm.
//!
//! ```sh
//! cargo run --example closed_loop
//! ```

use twocars::{Guidance, Law, Limits, Policy, Status, Variant};

/// Control period, seconds.
const DT: f32 = 0.01;
/// Capture radius, metres.
const CAPTURE: f32 = 0.01;

/// (x, y, theta) after `dt` seconds at speed `v` (m/s) and curvature `w` (1/m).
fn advance([x, y, theta]: [f32; 3], v: f32, w: f32, dt: f32) -> [f32; 3] {
    let turned = theta + v * w * dt;
    if w == 0.0 {
        [x + v * dt * theta.cos(), y + v * dt * theta.sin(), theta]
    } else {
        let (x1, y1) = (
            x + (turned.sin() - theta.sin()) / w,
            y + (theta.cos() - turned.cos()) / w,
        );
        [x1, y1, turned]
    }
}

fn main() -> Result<(), twocars::Error> {
    let [v_pm, w_pm, v_em, w_em] = [2.0, 2.0, 1.0, 1.0];
    let limits = Limits::<f32>::new(v_pm, w_pm, v_em, w_em)?;
    let mut guidance = Guidance::new(Law::new(limits, Variant::Paper), DT, Policy::Flight)?;
    let half_pi = core::f32::consts::FRAC_PI_2;
    let (mut pursuer, mut evader) = ([0.0, 0.0, half_pi], [-3.0, -6.0, half_pi]);
    let mut predicted = None;
    for period in 0..3000u32 {
        let t = period as f32 * DT;
        let distance = (evader[0] - pursuer[0]).hypot(evader[1] - pursuer[1]);
        if distance <= CAPTURE {
            let predicted = predicted.unwrap_or(f32::INFINITY);
            println!("captured at {t:.2} s (the law predicted {predicted:.4} s at t = 0)");
            return Ok(());
        }
        let (p, e) = limits.states(pursuer, evader)?;
        let decision = guidance.decide(&p, &e);
        if predicted.is_none() && decision.status == Status::Ok {
            predicted = decision.value_seconds();
        }
        let [w_p, w_e] = decision.curvatures();
        pursuer = advance(pursuer, v_pm, w_p, DT);
        evader = advance(evader, v_em, w_e, DT);
    }
    println!("not captured within 30 s");
    Ok(())
}
