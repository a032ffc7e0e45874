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
//! A controller validates the limits once, then asks for a decision every control period with
//! both vehicles' states (positions in a frame near the engagement: f32 resolves 1e-7 of the
//! distance from the origin):
//!
//! ```
//! use twocars::{Guidance, Law, Limits, Status, Variant};
//!
//! // v_pm, w_pm, v_em, w_em: the paper's limits (m/s and 1/m).
//! let limits = Limits::<f32>::new(2.0, 2.0, 1.0, 1.0).expect("valid limits");
//! let law = Law::new(limits, Variant::Paper);
//! let mut guidance = Guidance::new(law, 0.01).expect("dt = 10 ms");
//! // (x, y, theta) of the pursuer and the evader: the paper's case 1.
//! let (pursuer, evader) = limits
//!     .states([0.0, 0.0, core::f32::consts::FRAC_PI_2], [-3.0, -6.0, core::f32::consts::FRAC_PI_2])
//!     .expect("inside the envelope");
//! let decision = guidance.decide(&pursuer, &evader);
//! assert_eq!(decision.status, Status::Ok);
//! let upper = decision.solution.and_then(|s| s.upper).expect("a finite value");
//! assert!((upper - 5.6575).abs() < 1e-3); // seconds
//! // Curvature commands (1/m), at most w_max: a turn rate is v_max w.
//! assert!(decision.command.pursuer.abs() <= 2.0 && decision.command.evader.abs() <= 1.0);
//! ```
//!
//! [`Guidance::step`] returns the same with the per-pair report (tangents, arcs, the matrix),
//! for tools that print or plot it.
#![no_std]
#![deny(missing_docs)]
// Board shells need `unsafe` for registers; everything else is safe code.
#![deny(unsafe_code)]

#[cfg(any(
    feature = "board-qemu",
    feature = "board-stm32f405",
    feature = "board-microbit",
    feature = "board-rp2040"
))]
pub mod board;
pub mod geodetic;
pub mod guidance;
pub mod law;
mod log;
#[cfg(feature = "mavlink")]
pub mod mavlink;
pub mod num;
pub mod protocol;
#[cfg(feature = "firmware")]
pub mod serial;
pub mod status;
pub mod value_tables;

pub use guidance::{Guidance, Policy};
pub use law::capture::{CaptureTime, Variant};
pub use law::game::{GameSolution, MatrixGame};
pub use law::geometry::{
    CirclePairs, Direction, Limits, Point, TurningCircle, Units, ValidTangent, VehicleLimits,
    VehicleState,
};
pub use law::{evaluate_observation, Command, Decision, Evaluation, GameReport, Law, Observation};
pub use num::Scalar;
pub use status::Status;
