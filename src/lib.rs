//! # twocars: the time-optimal feedback law for the game of two cars
//!
//! A fast, agile Dubins pursuer chases a slower, less agile Dubins evader (v_pm > v_em,
//! w_pm > w_em). At every instant, after the paper "The game of two cars" (its Algorithms 1 and 2
//! and Table 1):
//!
//! 1. each vehicle has an anticlockwise (A) and a clockwise (C) minimum-radius turning circle;
//! 2. each of the four pursuer/evader circle pairs has one valid directed common tangent;
//! 3. turning onto it and running along it gives a time to capture per pair: a 2x2 matrix game;
//! 4. the pursuer plays the min-max row, the evader the max-min column;
//! 5. each turns at +-w_max on its chosen circle until on the tangent, then goes straight.
//!
//! Units: metres, seconds, radians anticlockwise from +x. `w` is curvature in 1/m, as in the
//! paper (theta_dot = v w, turning radius 1 / w_max); a turn rate in rad/s is v w.
//!
//! The law is written once over [`num::Scalar`]; it is `no_std`, allocation-free and panic-free.
//!
//! A controller sets the law up once (limits, control period, policy), then every control
//! period gives both vehicles' states in metres and radians (in a frame near the engagement:
//! f32 resolves 1e-7 of the distance from the origin) and acts on the decision:
//!
//! ```
//! use twocars::{Guidance, Law, Limits, Policy, Status, Variant};
//!
//! # fn main() -> Result<(), twocars::Error> {
//! // v_pm, w_pm, v_em, w_em: the paper's limits (m/s and 1/m).
//! let limits = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0)?;
//! let mut guidance = Guidance::new(Law::new(limits, Variant::Paper), 0.01, Policy::Flight)?;
//! // (x, y, theta) of the pursuer and the evader, metres and radians: the paper's case 1.
//! let half_pi = core::f32::consts::FRAC_PI_2;
//! let (pursuer, evader) = limits.states([0.0, 0.0, half_pi], [-3.0, -6.0, half_pi])?;
//! let decision = guidance.decide(&pursuer, &evader);
//! assert_eq!(decision.status, Status::Ok);
//! let seconds = decision.value_seconds().expect("a finite value");
//! assert!((seconds - 5.6575).abs() < 1e-3);
//! // The command as turn rates for a yaw-rate setpoint, rad/s (v_max w).
//! let [pursuer_rate, evader_rate] = guidance.turn_rates(&decision);
//! assert!(pursuer_rate.abs() <= 4.0 && evader_rate.abs() <= 1.0);
//! # Ok(())
//! # }
//! ```
//!
//! The same code runs on every backend: `Limits::<Fixed>` (Q17.14, for cores without an FPU)
//! or `Limits::<Micro>` (micromath's f32 functions, feature `micromath`) in place of
//! `Limits::<f32>`; [`Limits::states`] is the one way in from metres for each of them, and
//! [`Decision::value_seconds`], [`Decision::curvatures`] and [`Guidance::turn_rates`] the way
//! back to SI units as f32 (with integers on fixed point). [`Policy::Flight`] is the policy to
//! fly; [`Policy::Paper`] is the paper's law everywhere, the reference. [`Guidance::step`]
//! returns the decision with the per-pair report (tangents, arcs, the matrix) the host tools
//! print.
//!
//! ## The modules, in the order the data flows
//!
//! | module | what it holds | feature |
//! |---|---|---|
//! | [`status`] | the statuses every door reports, and the crate's [`Error`] | |
//! | [`num`] | the number types the law is written over: f32, f64, [`Fixed`] (Q17.14), `Micro` | `micromath` for `Micro` |
//! | [`law`] | the paper's law: turning circles, tangents, capture times, the matrix game | |
//! | [`geodetic`] | GPS fixes (degE7) to metres on a local plane and back | |
//! | [`estimate`] | states for now from late, sparse, noisy fixes: one track per vehicle | |
//! | [`value_tables`] | the game's value below the theorem's threshold, read from tables in flash | `value-tables` to play them |
//! | [`guidance`] | the decision each control period: the sampled command, the policies, the near field | |
//! | [`team`] | several pursuers against one evader: each on its own guidance, a chaser named with hysteresis | |
//! | [`protocol`] | the serial protocol: COBS frames, messages, the guidance unit that answers them | |
//! | `serial` | the firmware's interrupt-driven UART path over `heapless` queues | `firmware` |
//! | `polled` | the unit over any embedded-hal serial port, polled | `polled` |
//! | `mavlink` | the MAVLink 2 endpoint beside a PX4 or ArduPilot autopilot | `mavlink` |
//! | `board` | the board shells: QEMU mps2-an386, STM32F405, micro:bit, RP2040 | `board-*` |
//!
//! Each module imports only those above it in this table (`cargo xtask imports` checks that
//! there is no cycle). Without features the crate is the law, the estimator, the guidance and
//! the serial protocol, for any target; the features are below.
//!
//! `unsafe` is in two places: the board shells (registers) and, on Cortex-M cores with an FPU,
//! the square root's one `vsqrt.f32` instruction (`num::f32_math`); everything else is safe
//! code, `#![deny(unsafe_code)]`.
//!
#![doc = include_str!("../docs/features.md")]
#![cfg_attr(not(test), no_std)]
#![cfg_attr(docsrs, feature(doc_cfg))]
#![deny(missing_docs)]
// A public signature names only public items: nothing private or crate-only shows in the docs.
#![deny(private_interfaces, private_bounds)]
// Board shells need `unsafe` for registers, the FPU's square root one instruction; everything
// else is safe code.
#![deny(unsafe_code)]

#[cfg(any(
    feature = "board-qemu",
    feature = "board-stm32f405",
    feature = "board-microbit",
    feature = "board-rp2040"
))]
pub mod board;
mod error;
pub mod estimate;
pub mod geodetic;
pub mod guidance;
pub mod law;
#[cfg(feature = "firmware")]
mod log;
#[cfg(feature = "mavlink")]
pub mod mavlink;
pub mod num;
#[cfg(feature = "polled")]
pub mod polled;
pub mod protocol;
#[cfg(feature = "firmware")]
pub mod serial;
pub mod status;
pub mod team;
pub mod value_tables;

pub use error::Error;

/// README's Rust blocks, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

/// docs/field.md's Rust block, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../docs/field.md")]
pub struct FieldDoctests;

/// docs/team.md's Rust block, compiled and run as a doctest.
#[cfg(doctest)]
#[doc = include_str!("../docs/team.md")]
pub struct TeamDoctests;
pub use guidance::{Guidance, Policy};
pub use law::capture::{CaptureTime, Variant};
pub use law::game::{GameSolution, MatrixGame};
pub use law::geometry::{
    CirclePairs, Direction, Limits, Point, TurningCircle, Units, ValidTangent, VehicleLimits,
    VehicleState,
};
pub use law::{Command, Decision, Evaluation, GameReport, Law};
pub use num::fixed::Fixed;
#[cfg(feature = "micromath")]
pub use num::micro::Micro;
pub use num::Scalar;
pub use status::Status;
