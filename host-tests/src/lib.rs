//! Host-side companions of the `twocars` core: an independent f64 reference of the law and the
//! paper's scenarios. The tests in `tests/` run the same core source the firmware runs.

pub mod adversary;
pub mod autopilot;
pub mod field;
pub mod kinematics;
pub mod link;
pub mod mavlink_spec;
pub mod peers;
pub mod reference;
pub mod rng;
pub mod scenarios;
pub mod session;
pub mod sim;
pub mod starts;
pub mod stats;
pub mod uart_model;
