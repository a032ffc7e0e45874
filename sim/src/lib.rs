//! The `twocars` core's host side, used by the tests (`host-tests/`), the commands (`xtask/`),
//! the fuzz targets and the companion's tests: the exact closed-loop Dubins simulator
//! ([`sim`], [`kinematics`]), the adversary suite of evaders and pursuers ([`adversary`]), the
//! field's late, sparse, noisy fixes and the peers a user would fly instead ([`field`],
//! [`peers`]), an independent f64 reference of the law ([`reference`]), the paper's cases and
//! random starts ([`scenarios`], [`starts`], [`rng`], [`stats`]), our serial link and its UART
//! ([`link`], [`session`], [`uart_model`]), and MAVLink frames written from the specification
//! with an autopilot's view of a vehicle ([`mavlink_spec`], [`autopilot`]).

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
pub mod team;
pub mod uart_model;
