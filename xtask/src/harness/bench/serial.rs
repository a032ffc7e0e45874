//! The serial path's rows of `cargo xtask bench`: the firmware's loop fed a scripted session on
//! the Cortex-M4F and the Cortex-M0, its replies checked against the same unit on the host.

use twocars::num::fixed::Fixed;
use twocars::Scalar;
use twocars_bench::main_loop::{script_as, serve_script_on, Outcome, SCRIPT_CAPACITY};

use crate::harness::bench::image::{build_and_print, M0, M4F};

/// The session of `twocars_bench::main_loop` served on the host, by a unit with `tables`.
fn host_session<S: Scalar>(
    version: u8,
    with_states: bool,
    tables: &'static [twocars::value_tables::ValueTables<'static>],
) -> Result<Outcome, String> {
    let mut bytes = [0u8; SCRIPT_CAPACITY];
    let n = script_as(version, with_states, !tables.is_empty(), &mut bytes)
        .ok_or("the script does not fit")?;
    let outcome = serve_script_on::<S>(&mut twocars::serial::Line::new(), &bytes[..n], tables);
    if !outcome.shutdown {
        return Err("the host's session ended without its Shutdown".to_string());
    }
    Ok(outcome)
}

/// The firmware's serial loop on the Cortex-M4F (`serial` image), its replies checked
/// against the host's.
#[derive(Clone, Copy, Debug)]
pub struct LoopMeasured {
    /// Instructions per State frame: deframing, CRC, parsing, the law for both roles, the
    /// Command encoded and written (the session with the states minus the one without, over
    /// its State frames).
    pub per_state: f64,
    /// The same in the current protocol version (the states through the unit's estimator),
    /// where the image serves it.
    pub per_state_field: Option<f64>,
    /// The loop's stack high-water mark in the current version's session, bytes.
    pub stack_field: u64,
    /// Instructions of the session without the states (two Configures, four refused inputs,
    /// ReadCounters, Shutdown).
    pub rest: f64,
    /// Stack high-water mark of the loop (its unit, buffers and the law), bytes.
    pub stack: u64,
    /// Replies of the session with the states.
    pub replies: u32,
}

/// The serial loop's images: the Cortex-M4F with the f32 law, the Cortex-M0 with fixed point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoopImage {
    /// mps2-an386, f32.
    M4fFloat,
    /// micro:bit, Q17.14.
    M0Fixed,
    /// mps2-an386, f32, the unit with the bench's value table (`serial_tables`): the session
    /// plays it at the table points.
    M4fTables,
}

/// The bench's value table (`bench/table.tcv`), as the `serial_tables` image carries it.
fn bench_tables() -> Result<&'static [twocars::value_tables::ValueTables<'static>], String> {
    static TABLE: &[u8] = twocars_bench::TABLE;
    let set = twocars::value_tables::ValueTables::parse(TABLE)
        .map_err(|e| format!("bench/table.tcv: {e:?}"))?;
    Ok(Box::leak(Box::new([set])))
}

/// Runs the serial loop's bench session on `image`'s CPU; an error where its replies, their
/// digest or its counters differ from the host's (the same unit and backend on the host).
pub fn measure_loop(image: LoopImage) -> Result<LoopMeasured, String> {
    let (cpu, bin) = match image {
        LoopImage::M4fFloat => (M4F, "serial"),
        LoopImage::M0Fixed => (M0, "serial_fixed"),
        LoopImage::M4fTables => (M4F, "serial_tables"),
    };
    let tables = image == LoopImage::M4fTables;
    let (out, _) = build_and_print(cpu, bin)?;
    // Ticks by [version 1, the current version][without, with the states].
    let mut ticks = [[None, None], [None, None]];
    let (mut stack, mut stack_field) = (0, 0);
    let mut replies = 0;
    for line in out.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let ["loop", v, with, t, s, r, d, a, x] = fields.as_slice() else {
            continue;
        };
        let bad = || format!("bad line {line}");
        let with_states = *with == "1";
        let version: u8 = v.parse().map_err(|_| bad())?;
        let got = Outcome {
            // The image prints a line only for a session that ended at its Shutdown.
            shutdown: true,
            replies: r.parse().map_err(|_| bad())?,
            digest: u32::from_str_radix(d, 16).map_err(|_| bad())?,
            accepted: a.parse().map_err(|_| bad())?,
            refused: x.parse().map_err(|_| bad())?,
        };
        let want = match image {
            LoopImage::M4fFloat => host_session::<f32>(version, with_states, &[])?,
            LoopImage::M0Fixed => host_session::<Fixed>(version, with_states, &[])?,
            LoopImage::M4fTables => host_session::<f32>(version, with_states, bench_tables()?)?,
        };
        if got != want {
            return Err(format!(
                "serial loop (version {version}, with states: {with_states}): {} {got:?}, \
                 host {want:?}",
                cpu.name
            ));
        }
        let slot = ticks.get_mut(usize::from(version != 1)).ok_or_else(bad)?;
        slot[usize::from(with_states)] = Some(t.parse::<f64>().map_err(|_| bad())?);
        if with_states && version != 1 {
            stack_field = s.parse().map_err(|_| bad())?;
        }
        if with_states && version == 1 {
            stack = s.parse().map_err(|_| bad())?;
            replies = got.replies;
        }
    }
    let [[Some(without), Some(with)], current] = ticks else {
        return Err(format!(
            "the serial loop's image did not report both sessions:\n{out}"
        ));
    };
    let per_instruction = cpu.ticks_per_instruction;
    let frames = twocars_bench::main_loop::state_frames(tables) as f64;
    Ok(LoopMeasured {
        per_state: (with - without) / per_instruction / frames,
        per_state_field: match current {
            [Some(without), Some(with)] => Some((with - without) / per_instruction / frames),
            _ => None,
        },
        stack_field,
        rest: without / per_instruction,
        stack,
        replies,
    })
}

/// The current version's sentence of a loop's paragraph: what a State frame costs through the
/// unit's estimator.
fn field_sentence(l: &LoopMeasured) -> String {
    l.per_state_field.map_or(String::new(), |field| {
        format!(
            " In protocol version {} (the Configure with exact field settings and no team, \
             each State with its evader fix's time: the states go through the unit's \
             estimator, both tracks taken and carried to the frame's time), the same session \
             costs **{field:.0} instructions per State frame**, {:+.0} for the estimator's \
             path; stack {} B.",
            twocars::protocol::frame::VERSION,
            field - l.per_state,
            l.stack_field
        )
    })
}

/// The serial loop's paragraph of the report for `image`.
pub(crate) fn section(image: LoopImage) -> Result<String, String> {
    let l = measure_loop(image)?;
    let field = field_sentence(&l);
    Ok(match image {
        LoopImage::M4fFloat => format!(
            "Main loop (Cortex-M4F, f32; `serial` image: the firmware's serial path, the \
             UART interrupt's handler and `twocars::serial::service` over the `heapless` \
             queues, fed the script of `bench/src/main_loop.rs` by a scripted UART one byte \
             per interrupt: the bench states as State frames under each policy, {} replies, \
             all equal to the host's): **{:.0} instructions per State frame** (each byte \
             queued by the handler and dequeued by the loop, deframe, CRC, parse, the law \
             for both roles, the Command encoded, queued and handed to the transmitter by \
             the handler; exception entry and return are not instructions: the session's \
             instructions less those of the same session without its State frames, {:.0}, \
             over its State frames); **stack \
             {} B** (the unit, its buffers and the law below the loop's frame, as in the \
             firmware's `main`; the queues are statics; an interrupt adds its exception frame, 104 B with the FPU \
             context (108 B when realigned), and its handler's).{field} Where a frame's \
             instructions go (QEMU's exec log by function): docs/optimisation.md, \"The serial \
             path\".",
            l.replies, l.per_state, l.rest, l.stack
        ),
        LoopImage::M0Fixed => format!(
            "Main loop (Cortex-M0, fixed point; the same session on the micro:bit, `serial_fixed` \
             with the Q17.14 law, the wire's f32 values converted with integers only, {} \
             replies, all equal to the same unit's on the host): **{:.0} instructions per \
             State frame** (the session without its State frames: {:.0}); **stack {} B**.{field}",
            l.replies, l.per_state, l.rest, l.stack
        ),
        LoopImage::M4fTables => format!(
            "Main loop with the value tables (Cortex-M4F, f32; `serial_tables` image: the \
             unit carries `bench/table.tcv` and one Configure selects it, policy 2; the \
             {} table points of the bench below as State frames, the pursuer at the origin, \
             so that both players' turns are read from the table, {} replies, all equal to \
             the host's): **{:.0} instructions per State frame** (the session without its \
             State frames: {:.0}); **stack {} B**.",
            twocars_bench::main_loop::state_frames(true),
            l.replies,
            l.per_state,
            l.rest,
            l.stack
        ),
    })
}
