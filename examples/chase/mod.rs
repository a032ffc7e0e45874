//! The control loop the `cortex_m4f` and `cortex_m0` examples share: a firmware's code, set up
//! once, then each period states in and turn rates out, on the backend the example picks. The
//! "sensors" are a simulation of both vehicles on exact Dubins arcs from the paper's case 1; the
//! chase ends when the pursuer is within 1 cm.

use cortex_m_semihosting::{debug, hprintln};
use twocars::{Guidance, Law, Limits, Policy, Scalar, Variant};

/// Control period, seconds.
const DT: f32 = 0.01;
/// v_pm, w_pm, v_em, w_em: m/s and 1/m.
const LIMITS: [f32; 4] = [2.0, 2.0, 1.0, 1.0];

/// The control loop: the capture time, seconds, or why the law was not set up.
pub fn chase<S: Scalar>() -> Result<f32, twocars::Error> {
    let [v_pm, w_pm, v_em, w_em] = LIMITS;
    let limits = Limits::<S>::new(v_pm, w_pm, v_em, w_em)?;
    let mut guidance = Guidance::new(Law::new(limits, Variant::Paper), DT, Policy::Flight)?;
    let half_pi = core::f32::consts::FRAC_PI_2;
    let (mut pursuer, mut evader) = ([0.0, 0.0, half_pi], [-3.0, -6.0, half_pi]);
    for period in 0..3000u16 {
        if libm::hypotf(evader[0] - pursuer[0], evader[1] - pursuer[1]) <= 0.01 {
            return Ok(f32::from(period) * DT);
        }
        // Each period: both states in metres and radians, the turn rates (rad/s) out.
        let (p, e) = limits.states(pursuer, evader)?;
        let decision = guidance.decide(&p, &e);
        let [rate_p, rate_e] = guidance.turn_rates(&decision);
        pursuer = advance(pursuer, v_pm, rate_p);
        evader = advance(evader, v_em, rate_e);
    }
    Ok(f32::INFINITY)
}

/// (x, y, theta) after one period at speed `v` (m/s) and turn rate `rate` (rad/s).
fn advance([x, y, theta]: [f32; 3], v: f32, rate: f32) -> [f32; 3] {
    let turned = theta + rate * DT;
    if rate == 0.0 {
        let (sin, cos) = libm::sincosf(theta);
        return [x + v * DT * cos, y + v * DT * sin, theta];
    }
    let radius = v / rate;
    let x1 = x + radius * (libm::sinf(turned) - libm::sinf(theta));
    let y1 = y + radius * (libm::cosf(theta) - libm::cosf(turned));
    [x1, y1, turned]
}

/// Runs the chase on backend `S`, prints its outcome over semihosting and exits QEMU.
pub fn run<S: Scalar>() -> ! {
    let code = match chase::<S>() {
        Ok(t) => {
            hprintln!("captured at {} s", t);
            debug::EXIT_SUCCESS
        }
        Err(e) => {
            hprintln!("guidance not set up: {}", e);
            debug::EXIT_FAILURE
        }
    };
    debug::exit(code);
    loop {
        cortex_m::asm::wfi();
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::wfi();
    }
}
