//! The bench and on-target test images of twocars, and what the host shares with them.
//!
//! `cargo xtask bench` builds one small image per measurement (`src/bin/`), runs it in QEMU with
//! `-icount` so that SysTick counts instructions, and reads what it prints over semihosting;
//! `cargo xtask test` runs `tests/on_target.rs` the same way. The images run on QEMU's
//! mps2-an386 (Cortex-M4F) and micro:bit (Cortex-M0); `build.rs` picks the memory map from the
//! target.
//!
//! This library holds the fixed inputs, which xtask and the host tests use too: the bench
//! states ([`STATES`]), the paper's four cases and states that reach every branch of the law
//! (tail chase with four tied options, no valid tangent, the overshoot entry, far and near
//! states, both turn directions); with `serial`, the serial loop's session ([`main_loop`]);
//! with `mavlink`, the MAVLink endpoint's ([`mavlink`]) and a captured stream's replay
//! ([`replay`]). With `qemu` on a Cortex-M target,
//! `target` is the measuring harness the images share.
//!
//! Each state: pursuer (x, y, theta), evader (x, y, theta); metres, radians. Limits are the
//! paper's (v_pm = 2, w_pm = 2, v_em = 1, w_em = 1), control period 10 ms. Every state lies
//! inside every backend's envelope (fixed point: within 200 r_p = 100 m on each axis).
#![no_std]
#![deny(missing_docs)]

#[cfg(not(target_os = "none"))]
extern crate std;

#[cfg(feature = "serial")]
pub mod main_loop;
#[cfg(feature = "mavlink")]
pub mod mavlink;
#[cfg(feature = "mavlink")]
pub mod replay;
#[cfg(all(feature = "qemu", target_os = "none"))]
pub mod target;

/// The paper's limits: v_pm, w_pm, v_em, w_em.
pub const LIMITS: [f32; 4] = [2.0, 2.0, 1.0, 1.0];
/// Control period of the bench, seconds.
pub const DT: f32 = 0.01;

const HALF_PI: f32 = core::f32::consts::FRAC_PI_2;

/// The bench states.
pub const STATES: [([f32; 3], [f32; 3]); 12] = [
    ([0.0, 0.0, HALF_PI], [-3.0, -6.0, HALF_PI]),
    ([0.0, 0.0, HALF_PI], [6.0, 3.0, HALF_PI]),
    ([0.0, 0.0, HALF_PI], [0.0, -6.0, HALF_PI]),
    ([0.0, 0.0, HALF_PI], [0.0, 6.0, 2.094_395_1]),
    ([0.0, 0.0, 0.0], [20.0, 0.0, 0.0]),
    ([0.0, 0.0, 0.0], [-1.1336, -0.3115, -2.9591]),
    ([10.0, -4.0, 3.0], [-35.0, 22.0, -1.2]),
    ([-60.0, 40.0, -2.5], [30.0, -45.0, 0.7]),
    ([1.0, 1.0, 0.3], [2.5, 1.8, 2.9]),
    ([0.0, 0.0, -3.1], [0.5, -40.0, 1.0]),
    ([5.0, 5.0, 1.0], [4.0, 7.0, -2.0]),
    ([-7.0, 3.0, 2.2], [9.0, 14.0, -0.4]),
];

/// The bench's value table: the paper's game on a 21 x 21 x 24 grid, as `cargo xtask hj
/// --nodes 21 --eps 0.6 --table bench/table.tcv` writes it.
pub static TABLE: &[u8] = include_bytes!("../table.tcv");

/// Points of the reduced game (x, y in r_p, the relative heading in radians) where the bench
/// reads the value table [`TABLE`] (the `table` image): inside its box (+-6 r_p),
/// outside its capture disc, where it has a value, ahead and behind, both turn directions and
/// one tail chase (no preferred turn).
pub const TABLE_POINTS: [[f32; 3]; 8] = [
    [2.0, 0.0, 0.0],
    [1.2, -2.4, -2.0],
    [4.1, 3.3, -0.7],
    [0.4, 1.1, 1.6],
    [3.0, -4.0, 0.3],
    [-1.0, 2.0, 0.5],
    [-0.5, -1.5, -1.0],
    [3.5, 0.5, 3.0],
];

/// The estimator bench's fixes: a target on a slow left turn at 1 m/s, a fix every 200 ms,
/// each with a deterministic offset of up to 0.1 m and 0.05 rad (x, y metres, heading
/// radians), and the noise the estimator is told.
pub fn estimate_fix(i: u32) -> [f32; 3] {
    let k = i as f32;
    // A small integer hash for the offsets: the same on every target.
    let h = i.wrapping_mul(2_654_435_761) >> 16;
    let jitter = |bits: u32| ((bits & 0xFF) as f32 / 255.0 - 0.5) * 0.2;
    [
        0.2 * k + jitter(h),
        0.004 * k * k + jitter(h >> 8),
        0.04 * k + 0.5 * jitter(h >> 4),
    ]
}

/// Fixes the estimator bench takes.
pub const ESTIMATE_FIXES: u32 = 24;
/// Time between them, microseconds.
pub const ESTIMATE_INTERVAL_US: u32 = 200_000;
/// One sigma of their noise: position (m), heading (rad).
pub const ESTIMATE_NOISE: [f32; 2] = [0.1, 0.05];

/// Periods the team bench decides for each team size.
pub const TEAM_PERIODS: u32 = 12;

/// The team bench's sizes (pursuers).
pub const TEAM_SIZES: [usize; 3] = [2, 4, 8];

/// Pursuer `i` of the team bench (x, y metres, heading radians): 4 + 3 i m from the origin
/// at bearing 0.8 i rad, heading half a radian off the line back to it, so that the pursuers
/// sit both beyond and below the theorem's threshold (14.6 m) on both sides.
pub fn team_pursuer(i: usize) -> [f32; 3] {
    let k = i as f32;
    let (d, bearing) = (4.0 + 3.0 * k, 0.8 * k);
    let (sin, cos) = (libm::sinf(bearing), libm::cosf(bearing));
    [d * cos, d * sin, bearing + core::f32::consts::PI + 0.5]
}

/// The team bench's evader in period `k` of [`DT`]: from the origin along +x at 1 m/s, its
/// heading turning left 1 rad/s from 0.3 rad.
pub fn team_evader(k: u32) -> [f32; 3] {
    let t = k as f32 * DT;
    [t, 0.0, 0.3 + t]
}
