//! The MAVLink endpoint's bench session (`cargo xtask bench`, the `mavlink` image): the bench
//! states as an autopilot would report them, a target GLOBAL_POSITION_INT (system 2) and an own
//! one (system 1, component 1) per control period, through the firmware's serial path (the UART
//! interrupt's handler, the queues, [`twocars::mavlink::service::service`]) with a scripted UART.
//! The same session with the positions from systems the endpoint ignores times their parsing
//! alone; the empty session, the fixed cost (one heartbeat). Each runs twice: unsigned, and
//! signed both ways under [`KEY`] (every position's signature checked, every frame sent signed).

use ::mavlink::dialects::common::GLOBAL_POSITION_INT_DATA;

use crate::main_loop::ScriptedUart;
use crate::STATES;
use twocars::geodetic::LocalFrame;
use twocars::mavlink::service::service;
use twocars::mavlink::signing::{Signer, KEY_LEN};
use twocars::mavlink::Endpoint;
use twocars::mavlink::Outbox;
use twocars::serial::{Board, Line};

/// Script bytes: 24 position frames of at most 53 bytes (40 and a signature).
pub const SCRIPT_CAPACITY: usize = 1280;
/// The signed sessions' key.
pub const KEY: [u8; KEY_LEN] = [0x5a; KEY_LEN];
/// The signed sessions' signing clock at the start (10 us since 2015-01-01: 2026-11-27).
const SIGNING_START: u64 = 37_550_000_000_000;
/// Control periods in the session.
pub const PERIODS: usize = STATES.len();
/// The home fix of the script, degE7 (PX4 SITL's).
const HOME: (i32, i32) = (473_977_420, 85_455_940);
/// Bytes arriving between two passes of the loop (1.4 ms at 230400 baud).
const BURST: usize = 32;

/// Which positions the session carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Session {
    /// None: the heartbeat only.
    Empty,
    /// Every bench state from systems the endpoint ignores (parsing only).
    Ignored,
    /// Every bench state from the autopilot and the target: one setpoint each.
    Guided,
}

/// Every session the bench runs: each kind unsigned, then signed.
pub const SESSIONS: [(Session, bool); 6] = [
    (Session::Empty, false),
    (Session::Ignored, false),
    (Session::Guided, false),
    (Session::Empty, true),
    (Session::Ignored, true),
    (Session::Guided, true),
];

/// Writes the session's frames into `out`, signed under [`KEY`] where `signed`; their length,
/// `None` if they do not fit.
pub fn script(session: Session, signed: bool, out: &mut [u8]) -> Option<usize> {
    let frame = LocalFrame::new(HOME.0, HOME.1)?;
    let (own, target) = match session {
        Session::Empty => return Some(0),
        Session::Ignored => ((1, 2), (3, 1)),
        Session::Guided => ((1, 1), (2, 1)),
    };
    let mut outbox = Outbox::default();
    if signed {
        outbox.signer = Some(Signer::new(KEY, 1));
        outbox.timestamp = SIGNING_START;
    }
    let mut len = 0;
    let mut fits = true;
    for (i, &(pursuer, evader)) in STATES.iter().enumerate() {
        for (sender, state) in [(target, evader), (own, pursuer)] {
            let (lat, lon) = frame.to_fix(state[0], state[1])?;
            // Heading (rad, clockwise from north in the script's frame) in centidegrees.
            let turn = core::f32::consts::TAU;
            let heading = libm::fmodf(libm::fmodf(state[2], turn) + turn, turn);
            let cdeg = libm::roundf(heading * (18_000.0 / core::f32::consts::PI));
            let position = GLOBAL_POSITION_INT_DATA {
                time_boot_ms: 20 * i as u32,
                lat,
                lon,
                alt: 100_000,
                relative_alt: 10_000,
                vx: 0,
                vy: 0,
                vz: 0,
                hdg: (cdeg as u32 % 36_000) as u16,
            };
            outbox.send_as(
                sender,
                &position,
                &mut |bytes| match out.get_mut(len..len + bytes.len()) {
                    Some(slot) => {
                        slot.copy_from_slice(bytes);
                        len += bytes.len();
                    }
                    None => fits = false,
                },
            );
        }
    }
    fits.then_some(len)
}

/// What a session sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Outcome {
    /// Frames the endpoint sent.
    pub frames: u32,
    /// Digest of the bytes sent.
    pub digest: u32,
}

/// A clock that stands still.
struct StillBoard;

impl Board for StillBoard {
    fn now_ms(&self) -> u32 {
        0
    }
    fn start_transmit(&self) {}
}

/// The firmware's serial path over `script` with a fresh endpoint (signing under [`KEY`] where
/// `signed`): 32 bytes (`BURST`) raised as receive interrupts, then a pass of the loop, then
/// transmit interrupts until the queue is empty. Out of line, so that the bench's stack paint
/// sees the endpoint.
#[inline(never)]
pub fn serve_script(line: &mut Line, script: &[u8], signed: bool) -> Outcome {
    let (mut interrupt, mut main) = line.split();
    let mut uart = ScriptedUart::new(script);
    let mut endpoint = Endpoint::new();
    if signed {
        endpoint = endpoint.with_signing(KEY, 0, SIGNING_START);
    }
    serve_bytes(
        &mut interrupt,
        &mut main,
        &mut uart,
        &StillBoard,
        &mut endpoint,
    );
    Outcome {
        frames: endpoint.frames_sent(),
        digest: uart.digest,
    }
}

/// The serial path over what `uart` has still to receive: `BURST` bytes raised as receive
/// interrupts, a pass of the loop, transmit interrupts until the queue is empty; again until
/// the script is over.
#[inline(always)]
pub(crate) fn serve_bytes<B: Board>(
    interrupt: &mut twocars::serial::InterruptEnd<'_>,
    main: &mut twocars::serial::LoopEnd<'_>,
    uart: &mut ScriptedUart<'_>,
    board: &B,
    endpoint: &mut Endpoint,
) {
    loop {
        let mut arrived = 0;
        while arrived < BURST && uart.arrive().is_some() {
            interrupt.on_interrupt(uart);
            arrived += 1;
        }
        service(main, board, endpoint);
        loop {
            uart.tx_empty = true;
            interrupt.on_interrupt(uart);
            if uart.tx_empty {
                break;
            }
        }
        if arrived == 0 {
            break;
        }
    }
}
