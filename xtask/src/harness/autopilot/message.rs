//! The messages the ground station sends the autopilot, and the streams' rate it asks for.

use mavlink::dialects::common::{
    MavCmd, MavParamType, COMMAND_LONG_DATA, GLOBAL_POSITION_INT_DATA, HEARTBEAT_DATA,
    PARAM_SET_DATA, VFR_HUD_DATA,
};
use mavlink::MessageData;

use super::harness::AUTOPILOT;

/// The position and attitude streams' interval, us (20 Hz: the unit's control period).
pub const STREAM_INTERVAL_US: f32 = 50_000.0;

/// The autopilot's messages the unit reads (src/mavlink/endpoint.rs): its heartbeat, its
/// position and its airspeed. A port set up for the unit alone sends no more; where SITL runs
/// faster than the wall clock, the router passes the emulated unit only these
/// ([`super::router::Router::pass_to_unit`]), since QEMU takes its UART's bytes one at a time.
pub const UNIT_READS: [u32; 3] = [
    HEARTBEAT_DATA::ID,
    GLOBAL_POSITION_INT_DATA::ID,
    VFR_HUD_DATA::ID,
];

/// COMMAND_LONG `command` with `params` to the autopilot.
pub fn command(command: MavCmd, params: [f32; 7]) -> COMMAND_LONG_DATA {
    let [param1, param2, param3, param4, param5, param6, param7] = params;
    COMMAND_LONG_DATA {
        param1,
        param2,
        param3,
        param4,
        param5,
        param6,
        param7,
        command,
        target_system: AUTOPILOT.0,
        target_component: AUTOPILOT.1,
        confirmation: 0,
    }
}

/// PARAM_SET of `name` to `value` for (`system`, `component`).
pub fn param_set(target: (u8, u8), name: &str, value: f32) -> PARAM_SET_DATA {
    PARAM_SET_DATA {
        param_value: value,
        target_system: target.0,
        target_component: target.1,
        param_id: name.into(),
        param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
    }
}
