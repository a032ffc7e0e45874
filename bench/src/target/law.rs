//! The law's bench on the target: one full evaluation of the law (both roles, four tangents,
//! the game, the sampled commands; limits validated beforehand) per bench state, each timed and
//! its stack painted, printed as `state <i> <ticks> <stack bytes> <upper> <w_p> <w_e>` lines (the
//! last three as f32 bit patterns in hex, in seconds and 1/m: what the host compares).
//!
//! Each image passes its own timed region (`evaluate`, `#[inline(never)]` in the image): the
//! law on a numeric backend, `Guidance::step` with its report, or nothing at all (the empty
//! images: their ticks are the call overhead, their flash the baseline of the law's).

use core::hint::black_box;

use cortex_m_semihosting::hprintln;
use twocars::{Decision, Guidance, Law, Limits, Scalar, Variant, VehicleState};

use super::probe;
use crate::{DT, LIMITS, STATES};

/// The law and one bench state, prepared outside the timed region.
pub type Prepared<N> = (Guidance<N>, VehicleState<N>, VehicleState<N>);

/// The law at the paper's limits and bench state `i`, in backend `N`.
fn prepare<N: Scalar>(i: usize) -> Option<Prepared<N>> {
    let &(p, e) = STATES.get(i)?;
    let [v_pm, w_pm, v_em, w_em] = LIMITS;
    let limits = Limits::<N>::new(v_pm, w_pm, v_em, w_em).ok()?;
    let (p, e) = limits.states(p, e).ok()?;
    let law = Law::new(limits, Variant::Paper);
    let guidance = Guidance::new(law, DT, twocars::Policy::Paper).ok()?;
    Some((guidance, p, e))
}

/// Upper value (s) and both commands (1/m) as f32 bit patterns (infinity without a game).
fn outputs<N: Scalar>(ev: impl Into<Decision<N>>) -> [u32; 3] {
    let ev: Decision<N> = ev.into();
    let units = ev.units;
    let upper = ev
        .solution
        .and_then(|s| s.upper)
        .map_or(f64::INFINITY, |v| units.seconds(v));
    [
        upper,
        units.curvature(ev.command.pursuer),
        units.curvature(ev.command.evader),
    ]
    .map(|v| (v as f32).to_bits())
}

/// Times `evaluate` on every bench state, prints one `state` line each, and exits.
pub fn run<N: Scalar, O: Into<Decision<N>>>(evaluate: impl Fn(&mut Prepared<N>) -> O) -> ! {
    probe::start();
    for i in 0..STATES.len() {
        let Some(mut prepared) = prepare::<N>(black_box(i)) else {
            hprintln!("state {} unusable", i);
            continue;
        };
        let bottom = probe::paint();
        let start = probe::now();
        let out = evaluate(black_box(&mut prepared));
        let ticks = probe::ticks_since(start);
        let stack = probe::used(bottom);
        let [upper, w_p, w_e] = outputs(black_box(out));
        hprintln!(
            "state {} {} {} {:08x} {:08x} {:08x}",
            i,
            ticks,
            stack,
            upper,
            w_p,
            w_e
        );
    }
    probe::succeed()
}
