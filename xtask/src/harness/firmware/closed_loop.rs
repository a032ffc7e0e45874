//! The closed loop with the firmware: the host integrates both vehicles exactly, sends a State
//! every control period over the serial link, applies the firmware's turn rates (the host law
//! plays a role the firmware does not compute), and stops at capture or timeout.

use std::collections::VecDeque;

use twocars::protocol::endpoint::Endpoint;
use twocars::protocol::message::{
    Configure, Counters, FieldConfig, StateMsg, TeamConfig, ROLE_EVADER, ROLE_PURSUER,
};
use twocars::value_tables::ValueTables;
use twocars::{Direction, Guidance, Law, Limits, Policy, Scalar, Variant};
use twocars_sim::adversary::{Adversary, EvaderKind, Opponent};
use twocars_sim::link::{self, Reply, ReplyDecoder};
use twocars_sim::sim::{closed_loop, SimParams, SimResult, StepCommand};

use crate::harness::firmware::emulator::Emulator;

/// A serial link to a guidance unit: the firmware in its emulator, or the same unit in this
/// process.
pub trait Link {
    /// Sends raw bytes.
    fn send(&mut self, bytes: &[u8]) -> Result<(), String>;
    /// The next reply.
    fn reply(&mut self) -> Result<Reply, String>;
}

impl Link for Emulator {
    fn send(&mut self, bytes: &[u8]) -> Result<(), String> {
        Emulator::send(self, bytes)
    }
    fn reply(&mut self) -> Result<Reply, String> {
        Emulator::reply(self)
    }
}

/// The guidance unit on backend `S` in this process, fed the frames a firmware image would be:
/// the host's twin of the image, for a bit-for-bit comparison (its clock stands still).
pub struct HostUnit<S> {
    unit: Endpoint<S>,
    decoder: ReplyDecoder,
    pending: VecDeque<Reply>,
}

impl<S: Scalar> HostUnit<S> {
    /// An unconfigured unit.
    pub fn new() -> Self {
        HostUnit {
            unit: Endpoint::new(),
            decoder: ReplyDecoder::default(),
            pending: VecDeque::new(),
        }
    }

    /// An unconfigured unit with value tables, as an image carrying them.
    pub fn with_tables(tables: &'static [ValueTables<'static>]) -> Self {
        let mut host = Self::new();
        host.unit.set_tables(tables);
        host
    }
}

impl<S: Scalar> Link for HostUnit<S> {
    fn send(&mut self, bytes: &[u8]) -> Result<(), String> {
        for &byte in bytes {
            if let Some(reply) = self.unit.receive(byte, 0) {
                for r in self.decoder.feed(reply.as_bytes()) {
                    self.pending
                        .push_back(r.map_err(|e| format!("undecodable reply: {e:?}"))?);
                }
            }
        }
        Ok(())
    }
    fn reply(&mut self) -> Result<Reply, String> {
        self.pending
            .pop_front()
            .ok_or_else(|| "the unit sent no reply".to_string())
    }
}

/// What one firmware run shows besides the simulation figures.
#[derive(Debug, Clone)]
pub struct FirmwareRun {
    /// Capture time, switches, sign flips, ...
    pub result: SimResult,
    /// The firmware's predicted capture time in its first Command, seconds.
    pub predicted: f64,
    /// State frames sent.
    pub states_sent: u64,
    /// Command frames received.
    pub commands_received: u64,
    /// Error frames received.
    pub errors_received: u64,
}

fn circle(code: u8) -> Option<Direction> {
    match code {
        0 => Some(Direction::Anticlockwise),
        1 => Some(Direction::Clockwise),
        _ => None,
    }
}

/// Configures the firmware and runs one closed loop.
pub fn run_case(
    unit: &mut impl Link,
    sequence: &mut u16,
    params: &SimParams,
    roles: u8,
    how: (Variant, Policy),
) -> Result<FirmwareRun, String> {
    run_against(unit, sequence, params, roles, how, None)
}

/// [`run_case`] with the evader played by an adversary of the suite (`opponent`, its seed)
/// in place of the firmware's or the host law's evader; the Configure's ack must say `policy`.
pub fn run_against(
    unit: &mut impl Link,
    sequence: &mut u16,
    params: &SimParams,
    roles: u8,
    (variant, policy): (Variant, Policy),
    opponent: Option<(EvaderKind, u64)>,
) -> Result<FirmwareRun, String> {
    let limits = configure(unit, sequence, params, roles, (variant, policy))?;
    let mut host = Guidance::new(
        Law::new(limits, variant),
        params.dt as f32,
        twocars::Policy::Paper,
    )
    .map_err(|_| "invalid dt".to_string())?
    .with_policy(policy);
    let mut run = FirmwareRun {
        result: SimResult::empty(twocars_sim::sim::SimStatus::Timeout, f64::INFINITY),
        predicted: f64::NAN,
        states_sent: 0,
        commands_received: 0,
        errors_received: 0,
    };
    let params = SimParams {
        limits: params.limits.map(|v| f64::from(v as f32)),
        ..*params
    };
    let mut adversary = opponent
        .map(|(kind, seed)| {
            let evader = Opponent::Evader(kind);
            Adversary::new(evader, params.limits, params.dt, params.eps, seed)
                .ok_or("no adversary for these limits")
        })
        .transpose()?;
    let [v_pm, _, v_em, _] = params.limits.map(|v| v as f32);
    let result = closed_loop(&params, false, |t, p, e| {
        let state = StateMsg::exact(
            (t * 1000.0).round() as u32,
            p.map(|v| v as f32),
            e.map(|v| v as f32),
        );
        let (rate_p, rate_e, choice) = exchange(unit, sequence, &mut run, t, &state)?;
        // The host law plays any role the firmware does not compute.
        let host_command = match limits.states(state.pursuer, state.evader) {
            Ok((ps, es)) => host.step(&ps, &es).command,
            Err(_) => twocars::Command::straight(),
        };
        let curvature = |role: u8, rate: f32, speed: f32, host: f32| {
            f64::from(if roles & role != 0 {
                rate / speed
            } else {
                host
            })
        };
        let pursuer = curvature(ROLE_PURSUER, rate_p, v_pm, host_command.pursuer);
        let evader = curvature(ROLE_EVADER, rate_e, v_em, host_command.evader);
        let mut command = StepCommand::full_speed(pursuer, evader, choice);
        if let Some(adversary) = adversary.as_mut() {
            let (w, v) = adversary.command(t, p, e);
            (command.evader, command.evader_speed) = (w, Some(v));
        }
        Ok::<_, String>(command)
    })?;
    run.result = result;
    Ok(run)
}

/// Configures the unit for `params`' limits and control period, `roles` and `how`; the
/// limits as the unit holds them (f32). Err unless it acknowledges with that policy.
fn configure(
    unit: &mut impl Link,
    sequence: &mut u16,
    params: &SimParams,
    roles: u8,
    (variant, policy): (Variant, Policy),
) -> Result<Limits<f32>, String> {
    let limits32 = params.limits.map(|v| v as f32);
    let configure = Configure {
        limits: limits32,
        dt: params.dt as f32,
        watchdog: 1.0,
        roles,
        variant: twocars::protocol::message::variant_byte(variant),
        policy: twocars::protocol::message::policy_byte(policy),
        field: FieldConfig::EXACT,
        team: TeamConfig::NONE,
    };
    *sequence = sequence.wrapping_add(1);
    unit.send(&link::configure(*sequence, &configure))?;
    match unit.reply()? {
        Reply::ConfigureAck(s, Some(p)) if s == *sequence && p == configure.policy => {}
        other => return Err(format!("Configure refused or another policy: {other:?}")),
    }
    let [v_pm, w_pm, v_em, w_em] = limits32;
    Limits::<f32>::new(v_pm, w_pm, v_em, w_em).map_err(|e| e.to_string())
}

/// The unit's answer to a State: the pursuer's and the evader's turn rates (rad/s) and their
/// circles, where it chose.
type Answer = (f32, f32, Option<(Direction, Direction)>);

/// Sends `state` and reads the unit's reply, counted in `run`; after an Error reply, straight
/// ahead and no circles.
fn exchange(
    unit: &mut impl Link,
    sequence: &mut u16,
    run: &mut FirmwareRun,
    t: f64,
    state: &StateMsg,
) -> Result<Answer, String> {
    *sequence = sequence.wrapping_add(1);
    unit.send(&link::state(*sequence, state))?;
    run.states_sent += 1;
    match unit.reply()? {
        Reply::Command(s, c) if s == *sequence => {
            run.commands_received += 1;
            if run.predicted.is_nan() {
                run.predicted = f64::from(c.predicted);
            }
            Ok((
                c.pursuer_rate,
                c.evader_rate,
                circle(c.row).zip(circle(c.col)),
            ))
        }
        Reply::Error(..) => {
            run.errors_received += 1;
            Ok((0.0, 0.0, None))
        }
        other => Err(format!("unexpected reply at t = {t}: {other:?}")),
    }
}

/// Reads the firmware's counters.
pub fn counters(unit: &mut impl Link, sequence: &mut u16) -> Result<Counters, String> {
    *sequence = sequence.wrapping_add(1);
    unit.send(&link::read_counters(*sequence))?;
    match unit.reply()? {
        Reply::Counters(_, c) => Ok(c),
        other => Err(format!("expected Counters, got {other:?}")),
    }
}

/// Ends the session: Shutdown, its acknowledgement, the emulator's exit code (0 for a flight
/// image, which serves on and whose emulator is stopped).
pub fn shutdown(mut emulator: Emulator, sequence: &mut u16) -> Result<i32, String> {
    *sequence = sequence.wrapping_add(1);
    emulator.send(&link::shutdown(*sequence))?;
    match emulator.reply()? {
        Reply::ShutdownAck(s) if s == *sequence => {}
        other => {
            return Err(format!(
                "expected the Shutdown acknowledgement, got {other:?}"
            ))
        }
    }
    if !emulator.exits_on_shutdown() {
        // A flight image serves on after its ShutdownAck: the emulator is stopped (on drop).
        return Ok(0);
    }
    let status = emulator.wait_exit()?;
    Ok(status.code().unwrap_or(-1))
}
