//! Bench firmware: times one full evaluation of the law (both roles, four tangents, the game,
//! the sampled commands: `Guidance::decide`, the firmware's path, or with `bench-report`
//! `Guidance::step` and its per-pair report; limits validated beforehand) per bench state with
//! SysTick on the processor clock,
//! under QEMU `-icount` so ticks count instructions; paints the stack to find the law's peak
//! use. Prints `state <i> <ticks> <stack bytes> <upper> <w_p> <w_e>` lines over semihosting (the
//! last three as f32 bit patterns in hex, in seconds and 1/m: what the host compares), then exits.
//! With `bench-empty` the law is replaced by nothing: its ticks are the call overhead, its image
//! the baseline of the law's flash. The numeric backend: f32, or `Fixed` with `bench-fixed`, or
//! micromath with `bench-micromath`.
//!
//! With `bench-loop` it runs the firmware's serial path instead (the UART interrupt's handler and
//! `twocars::serial::service` over the queues, fed the script of `twocars::bench::main_loop` by a
//! scripted UART, with and without the bench states) and prints one `loop` line per session: its
//! ticks, the loop's stack and a digest of its replies. With `bench-mavlink` it runs the MAVLink
//! endpoint's serial path over the sessions of `twocars::bench::mavlink` instead; with
//! `bench-table` it reads the value table `src/bench/table.tcv` at `twocars::bench::TABLE_POINTS`;
//! with both `bench-loop` and `bench-table`, the serial loop's unit carries that table and its
//! session plays it.
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_semihosting::debug::{exit, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::hprintln;
#[cfg(not(any(feature = "bench-loop", feature = "bench-table")))]
use twocars::bench::STATES;

const PAINT: u32 = 0xA5A5_5A5A;
/// Bytes of stack painted below the caller's frame.
const PAINT_BYTES: usize = 4096;

#[cfg(all(
    feature = "bench-fixed",
    not(any(feature = "bench-loop", feature = "bench-table"))
))]
type Number = twocars::num::fixed::Fixed;
#[cfg(all(feature = "bench-micromath", not(feature = "bench-fixed")))]
type Number = twocars::num::micro::Micro;
#[cfg(not(any(
    feature = "bench-fixed",
    feature = "bench-micromath",
    feature = "bench-loop",
    feature = "bench-table"
)))]
type Number = f32;

/// The law and one bench state, prepared outside the timed region.
#[cfg(not(any(feature = "bench-loop", feature = "bench-table")))]
type Prepared = (
    twocars::Guidance<Number>,
    twocars::VehicleState<Number>,
    twocars::VehicleState<Number>,
);

#[cfg(not(any(feature = "bench-loop", feature = "bench-table")))]
fn prepare(i: usize) -> Option<Prepared> {
    let &(p, e) = STATES.get(i)?;
    let [v_pm, w_pm, v_em, w_em] = twocars::bench::LIMITS;
    let limits = twocars::Limits::<Number>::new(v_pm, w_pm, v_em, w_em).ok()?;
    let (p, e) = limits.states(p, e).ok()?;
    let law = twocars::Law::new(limits, twocars::Variant::Paper);
    let guidance = twocars::Guidance::new(law, twocars::bench::DT).ok()?;
    Some((guidance, p, e))
}

/// What the timed region returns: the decision, or with `bench-report` the whole evaluation.
#[cfg(not(any(
    feature = "bench-loop",
    feature = "bench-report",
    feature = "bench-table"
)))]
type Output = twocars::Decision<Number>;
#[cfg(all(
    not(any(feature = "bench-loop", feature = "bench-table")),
    feature = "bench-report"
))]
type Output = twocars::Evaluation<Number>;

/// The timed region: one `Guidance::decide` (or `Guidance::step`), returned in the caller's
/// slot. With `bench-empty` only a safe evaluation is returned there (the call and return
/// overhead).
#[cfg(not(any(feature = "bench-loop", feature = "bench-table")))]
#[inline(never)]
fn evaluate(prepared: &mut Prepared) -> Output {
    #[cfg(feature = "bench-empty")]
    #[allow(clippy::useless_conversion)] // `Output` is `Evaluation` itself with `bench-report`.
    {
        black_box(prepared);
        twocars::Evaluation::safe(twocars::Status::Captured).into()
    }
    #[cfg(all(not(feature = "bench-empty"), not(feature = "bench-report")))]
    {
        let (guidance, p, e) = prepared;
        guidance.decide(p, e)
    }
    #[cfg(all(not(feature = "bench-empty"), feature = "bench-report"))]
    {
        let (guidance, p, e) = prepared;
        guidance.step(p, e)
    }
}

/// Upper value (s) and both commands (1/m) as f32 bit patterns (infinity without a game).
#[cfg(not(any(feature = "bench-loop", feature = "bench-table")))]
fn outputs(ev: impl Into<twocars::Decision<Number>>) -> [u32; 3] {
    let ev: twocars::Decision<Number> = ev.into();
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

fn paint() -> usize {
    let sp = cortex_m::register::msp::read() as usize;
    let bottom = sp - PAINT_BYTES;
    let mut a = bottom;
    while a < sp - 64 {
        // SAFETY: below the live stack pointer, inside RAM: unused stack.
        unsafe { core::ptr::write_volatile(a as *mut u32, PAINT) };
        a += 4;
    }
    bottom
}

fn used(bottom: usize) -> usize {
    let sp = cortex_m::register::msp::read() as usize;
    let mut a = bottom;
    // SAFETY: reads of the painted region.
    while a < sp && unsafe { core::ptr::read_volatile(a as *const u32) } == PAINT {
        a += 4;
    }
    sp - a
}

#[cortex_m_rt::entry]
fn main() -> ! {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        exit(EXIT_FAILURE);
        loop {
            cortex_m::asm::nop();
        }
    };
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(0x00FF_FFFF);
    cp.SYST.clear_current();
    cp.SYST.enable_counter();
    #[cfg(not(any(feature = "bench-loop", feature = "bench-table")))]
    bench_law();
    #[cfg(all(feature = "bench-loop", not(feature = "bench-mavlink")))]
    bench_loop();
    #[cfg(feature = "bench-mavlink")]
    bench_mavlink();
    #[cfg(all(feature = "bench-table", not(feature = "bench-loop")))]
    bench_table();
    exit(EXIT_SUCCESS);
    loop {
        cortex_m::asm::nop();
    }
}

/// SysTick ticks from `start` to now (the counter counts down, 24 bits).
fn ticks_since(start: u32) -> u32 {
    start.wrapping_sub(cortex_m::peripheral::SYST::get_current()) & 0x00FF_FFFF
}

/// One `state` line per bench state.
#[cfg(not(any(feature = "bench-loop", feature = "bench-table")))]
fn bench_law() {
    for i in 0..STATES.len() {
        let Some(mut prepared) = prepare(black_box(i)) else {
            hprintln!("state {} unusable", i);
            continue;
        };
        let bottom = paint();
        let start = cortex_m::peripheral::SYST::get_current();
        let out = evaluate(black_box(&mut prepared));
        let ticks = ticks_since(start);
        let stack = used(bottom);
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
}

/// One `loop` line per session (with the bench states, then without):
/// `loop <with states> <ticks> <stack bytes> <replies> <digest> <accepted> <refused>`.
#[cfg(all(feature = "bench-loop", not(feature = "bench-mavlink")))]
fn bench_loop() {
    use twocars::bench::main_loop::{script, SCRIPT_CAPACITY};
    let mut bytes = [0u8; SCRIPT_CAPACITY];
    // The queues are a static on a board, outside the loop's stack.
    let Some(line) = cortex_m::singleton!(: twocars::serial::Line = twocars::serial::Line::new())
    else {
        return;
    };
    // With `bench-table` the unit carries the bench's value table, and the script plays it.
    #[cfg(feature = "bench-table")]
    let tables = match bench_tables() {
        Some(set) => core::slice::from_ref(set),
        None => {
            hprintln!("the bench table does not parse");
            return;
        }
    };
    #[cfg(not(feature = "bench-table"))]
    let tables: &'static [twocars::value_tables::ValueTables<'static>] = &[];
    for with_states in [true, false] {
        let Some(script) =
            script(with_states, !tables.is_empty(), &mut bytes).and_then(|n| bytes.get(..n))
        else {
            hprintln!("script does not fit");
            continue;
        };
        let bottom = paint();
        let start = cortex_m::peripheral::SYST::get_current();
        #[cfg(not(feature = "bench-fixed"))]
        let session = twocars::bench::main_loop::serve_script(line, black_box(script), tables);
        #[cfg(feature = "bench-fixed")]
        let session = twocars::bench::main_loop::serve_script_fixed(line, black_box(script));
        let ticks = ticks_since(start);
        let stack = used(bottom);
        if !session.shutdown {
            hprintln!("session ended without Shutdown");
            continue;
        }
        hprintln!(
            "loop {} {} {} {} {:08x} {} {}",
            u8::from(with_states),
            ticks,
            stack,
            session.replies,
            session.digest,
            session.accepted,
            session.refused
        );
    }
}

/// One `mavlink` line per session (empty, ignored positions, guided):
/// `mavlink <session> <ticks> <stack bytes> <frames sent> <digest>`.
#[cfg(feature = "bench-mavlink")]
fn bench_mavlink() {
    use twocars::bench::mavlink::{script, serve_script, Session, SCRIPT_CAPACITY};
    let mut bytes = [0u8; SCRIPT_CAPACITY];
    let Some(line) = cortex_m::singleton!(: twocars::serial::Line = twocars::serial::Line::new())
    else {
        return;
    };
    for (i, session) in [Session::Empty, Session::Ignored, Session::Guided]
        .into_iter()
        .enumerate()
    {
        let Some(script) = script(session, &mut bytes).and_then(|n| bytes.get(..n)) else {
            hprintln!("script does not fit");
            continue;
        };
        let bottom = paint();
        let start = cortex_m::peripheral::SYST::get_current();
        let outcome = serve_script(line, black_box(script));
        let ticks = ticks_since(start);
        let stack = used(bottom);
        hprintln!(
            "mavlink {} {} {} {} {:08x}",
            i,
            ticks,
            stack,
            outcome.frames,
            outcome.digest
        );
    }
}

/// One `table` line per point of `twocars::bench::TABLE_POINTS`:
/// `table <i> <ticks> <empty ticks> <stack bytes> <value bits> <turn>`, the value table of
/// `src/bench/table.tcv` read (V and the pursuer's optimal turn) against the same call that
/// reads nothing.
#[cfg(all(feature = "bench-table", not(feature = "bench-loop")))]
fn bench_table() {
    let Some(table) = bench_tables() else {
        hprintln!("the bench table does not parse");
        return;
    };
    for (i, &point) in twocars::bench::TABLE_POINTS.iter().enumerate() {
        let start = cortex_m::peripheral::SYST::get_current();
        let empty = read_nothing(black_box(table), black_box(point));
        let empty_ticks = ticks_since(start);
        black_box(empty);
        let bottom = paint();
        let start = cortex_m::peripheral::SYST::get_current();
        let (value, turn) = read_table(black_box(table), black_box(point));
        let ticks = ticks_since(start);
        let stack = used(bottom);
        hprintln!(
            "table {} {} {} {} {:08x} {}",
            i,
            ticks,
            empty_ticks,
            stack,
            value.to_bits(),
            turn
        );
    }
}

/// The value table of `src/bench/table.tcv`, parsed once into a static; `None` if it does not
/// parse (or on a second call).
#[cfg(feature = "bench-table")]
fn bench_tables() -> Option<&'static twocars::value_tables::ValueTables<'static>> {
    use twocars::value_tables::ValueTables;
    static TABLE: &[u8] = include_bytes!("../bench/table.tcv");
    let table = ValueTables::parse(black_box(TABLE)).ok()?;
    cortex_m::singleton!(: ValueTables<'static> = table).map(|t| &*t)
}

/// The timed region: V and the pursuer's optimal turn at `point` (r_p, r_p, rad).
#[cfg(all(feature = "bench-table", not(feature = "bench-loop")))]
#[inline(never)]
fn read_table(table: &twocars::value_tables::ValueTables<'_>, [x, y, phi]: [f32; 3]) -> (f32, f32) {
    (
        table.value(x, y, phi).unwrap_or(f32::INFINITY),
        table.pursuer_turn(x, y, phi).unwrap_or(f32::NAN),
    )
}

/// The same call reading nothing: its ticks are the call overhead.
#[cfg(all(feature = "bench-table", not(feature = "bench-loop")))]
#[inline(never)]
fn read_nothing(table: &twocars::value_tables::ValueTables<'_>, point: [f32; 3]) -> (f32, f32) {
    black_box((table, point));
    (0.0, 0.0)
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    exit(EXIT_FAILURE);
    loop {
        cortex_m::asm::nop();
    }
}
