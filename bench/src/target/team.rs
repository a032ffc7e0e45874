//! The team's bench on the target: for each size of [`crate::TEAM_SIZES`], a team of the
//! paper's pursuers ([`crate::team_pursuer`]) deciding [`crate::TEAM_PERIODS`] periods
//! against [`crate::team_evader`], one line per period: `team <n> <k> <ticks> <empty ticks>
//! <stack> <chaser> <team time>` (the chaser's index, 255 for none; the team's time in
//! seconds as f32 bits, 0 for none), over f32 (`team`) or fixed point (`team_fixed`).

use core::hint::black_box;

use cortex_m_semihosting::hprintln;
use twocars::team::{Team, TeamDecision};
use twocars::{Guidance, Law, Limits, Policy, Scalar, Variant};

use super::probe;
use crate::{team_evader, team_pursuer, DT, LIMITS, TEAM_PERIODS};

/// Runs every team size over `S`, printing one `team` line per period, and exits.
pub fn run<S: Scalar>() -> ! {
    probe::start();
    sized::<S, 2>();
    sized::<S, 4>();
    sized::<S, 8>();
    probe::succeed()
}

fn sized<S: Scalar, const N: usize>() {
    let [v_pm, w_pm, v_em, w_em] = LIMITS;
    let guidance = Limits::<S>::new(v_pm, w_pm, v_em, w_em)
        .and_then(|limits| Guidance::new(Law::new(limits, Variant::Paper), DT, Policy::Flight));
    let Ok(mut team) = guidance.and_then(|g| Team::<S, N>::new([g; N], [LIMITS; N])) else {
        hprintln!("the bench team does not set up");
        probe::fail();
    };
    let pursuers: [[f32; 3]; N] = core::array::from_fn(team_pursuer);
    for k in 0..TEAM_PERIODS {
        let evader = team_evader(k);
        let start = probe::now();
        black_box(decide_nothing(
            black_box(&mut team),
            black_box(&pursuers),
            evader,
        ));
        let empty_ticks = probe::ticks_since(start);
        let bottom = probe::paint();
        let start = probe::now();
        let d = black_box(decide(
            black_box(&mut team),
            black_box(&pursuers),
            black_box(evader),
        ));
        let ticks = probe::ticks_since(start);
        let stack = probe::used(bottom);
        hprintln!(
            "team {} {} {} {} {} {} {:08x}",
            N,
            k,
            ticks,
            empty_ticks,
            stack,
            d.chaser.map_or(255, |c| c),
            d.team_time().unwrap_or(0.0).to_bits()
        );
    }
}

/// The timed region: one period's decision of the team.
#[inline(never)]
fn decide<S: Scalar, const N: usize>(
    team: &mut Team<S, N>,
    pursuers: &[[f32; 3]; N],
    evader: [f32; 3],
) -> TeamDecision<S, N> {
    team.decide(pursuers, evader)
}

/// The same call doing nothing: its ticks are the call overhead.
#[inline(never)]
fn decide_nothing<S: Scalar, const N: usize>(
    team: &mut Team<S, N>,
    pursuers: &[[f32; 3]; N],
    evader: [f32; 3],
) -> usize {
    black_box((team, pursuers, evader));
    0
}
