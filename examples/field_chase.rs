//! A chase on a radio's fixes, on the host: the target's fixes come 5 times a second, each
//! 0.2 s old and off by about 0.1 m and 0.05 rad; the own fixes every control period. The
//! estimator carries both to each decision's time and `decide_estimated` steers on them, so
//! that the noise does not flip the turn. The target circles (radius 5 m) at its top speed.
//!
//! ```sh
//! cargo run --example field_chase
//! ```

use twocars::estimate::{Estimator, FieldSettings, Fix, FixNoise};
use twocars::{Guidance, Law, Limits, Policy, Variant};

/// Control period, microseconds.
const PERIOD_US: u32 = 10_000;
/// The target's fixes: one every 200 ms, taken 200 ms before they arrive.
const FIX_EVERY_US: u32 = 200_000;
const LAG_US: u32 = 200_000;
/// Capture radius, metres.
const CAPTURE: f32 = 0.3;
/// The paper's limits: v_pm, w_pm, v_em, w_em (m/s, 1/m).
const LIMITS: [f32; 4] = [2.0, 2.0, 1.0, 1.0];

/// (x, y, theta) after `dt` seconds at speed `v` (m/s) and curvature `w` (1/m).
fn advance([x, y, theta]: [f32; 3], v: f32, w: f32, dt: f32) -> [f32; 3] {
    if w == 0.0 {
        return [x + v * dt * theta.cos(), y + v * dt * theta.sin(), theta];
    }
    let turned = theta + v * w * dt;
    let x1 = x + (turned.sin() - theta.sin()) / w;
    let y1 = y + (theta.cos() - turned.cos()) / w;
    [x1, y1, turned]
}

/// A small generator of noise in [-1, 1): the example needs no crate for it.
struct Noise(u32);

impl Noise {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (self.0 >> 8) as f32 / (1u32 << 23) as f32 - 1.0
    }
}

fn main() -> Result<(), twocars::Error> {
    let [v_pm, w_pm, v_em, w_em] = LIMITS;
    let limits = Limits::<f32>::new(v_pm, w_pm, v_em, w_em)?;
    let mut guidance = Guidance::new(Law::new(limits, Variant::Paper), 0.01, Policy::Flight)?
        .with_capture_radius(CAPTURE)?;
    let settings = FieldSettings {
        target_noise: FixNoise {
            position: 0.1,
            heading: 0.05,
        },
        ..FieldSettings::exact(1.0)
    };
    let mut estimator = Estimator::new(LIMITS, settings)?;
    let mut noise = Noise(2019);
    let (mut pursuer, mut evader) = ([0.0, 0.0, 1.57], [4.0, 6.0, 0.0]);
    let mut history = Vec::new();
    for k in 0..6_000u32 {
        let now_us = k * PERIOD_US;
        history.push(evader);
        let _ = estimator.own_fix(&Fix {
            state: pursuer,
            time_us: now_us,
        });
        // The fix taken LAG_US ago arrives now, with its time.
        if now_us >= LAG_US && (now_us - LAG_US) % FIX_EVERY_US == 0 {
            let [x, y, theta] = history[((now_us - LAG_US) / PERIOD_US) as usize];
            let state = [
                x + 0.1 * noise.next(),
                y + 0.1 * noise.next(),
                theta + 0.05 * noise.next(),
            ];
            let time_us = now_us - LAG_US;
            let _ = estimator.target_fix(&Fix { state, time_us });
        }
        let w = match estimator.states(now_us) {
            Ok(estimated) => {
                let decision = guidance.decide_estimated(&estimated)?;
                guidance.turn_rates(&decision)[0] / v_pm
            }
            // No target fix yet (or a stale one): the safe command, straight on.
            Err(_) => 0.0,
        };
        pursuer = advance(pursuer, v_pm, w, 0.01);
        evader = advance(evader, v_em, 0.2, 0.01);
        let distance = (pursuer[0] - evader[0]).hypot(pursuer[1] - evader[1]);
        if distance <= CAPTURE {
            println!(
                "captured within {CAPTURE} m at {:.2} s",
                now_us as f32 / 1e6
            );
            return Ok(());
        }
    }
    println!("not captured in 60 s");
    Ok(())
}
