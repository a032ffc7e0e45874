//! `cargo xtask bench`: instructions per law evaluation on Cortex-M4F and Cortex-M0 (QEMU with
//! `-icount`), flash of the law and of each image, the law's stack, host throughput. Prints a
//! table and writes it to `docs/bench.md` (regenerated, never edited by hand).

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use twocars::bench::main_loop::{script, serve_script_on, Outcome, SCRIPT_CAPACITY};
use twocars::bench::{DT, LIMITS, STATES};
use twocars::num::fixed::Fixed;
use twocars::num::micro::Micro;
use twocars::{Guidance, Law, Limits, Scalar, Variant, VehicleState};

use crate::progress::Progress;
use crate::qemu::{self, root};

/// One emulated CPU the bench runs on.
#[derive(Clone, Copy)]
pub struct Cpu {
    name: &'static str,
    target: &'static str,
    machine: &'static [&'static str],
    board_features: &'static str,
    /// SysTick ticks per instruction under `-icount shift=6` (64 ns per instruction).
    pub(crate) ticks_per_instruction: f64,
}

impl Cpu {
    /// Its name in the tables.
    pub fn name(&self) -> &'static str {
        self.name
    }
    /// QEMU on this CPU's machine, headless, semihosting to the host, loading `elf`; the caller
    /// adds its own options (instruction counting, execution log).
    pub fn qemu(&self, elf: &std::path::Path) -> Result<Command, String> {
        let mut command = Command::new(qemu::qemu_binary()?);
        command
            .args(self.machine)
            .args(["-display", "none", "-monitor", "none", "-serial", "none"])
            .args(["-semihosting-config", "enable=on,target=native"])
            .arg("-kernel")
            .arg(elf);
        Ok(command)
    }
}

pub const M4F: Cpu = Cpu {
    name: "Cortex-M4F (mps2-an386)",
    target: "thumbv7em-none-eabihf",
    machine: &["-M", "mps2-an386", "-cpu", "cortex-m4"],
    board_features: "",
    // SysTick on the 25 MHz processor clock: 64 ns x 25 MHz.
    ticks_per_instruction: 1.6,
};

pub const M0: Cpu = Cpu {
    name: "Cortex-M0 (micro:bit)",
    target: "thumbv6m-none-eabi",
    machine: &["-M", "microbit"],
    board_features: ",board-microbit",
    // SysTick on the 16 MHz processor clock: 64 ns x 16 MHz.
    ticks_per_instruction: 1.024,
};

/// Per-state figures of one image.
pub struct Measured {
    /// SysTick ticks of each evaluation.
    pub ticks: Vec<f64>,
    /// Stack high-water mark of each evaluation, bytes.
    pub stack: Vec<u64>,
    /// Upper value (s) and the commands w_p, w_e (1/m) of each state, as the image computed them.
    pub outputs: Vec<[f32; 3]>,
    /// Flash of the image, bytes.
    pub flash: u64,
}

/// Builds the bench image with `features` for `cpu`, runs it in QEMU with `-icount` and reads
/// its per-state lines.
pub fn build_and_run(cpu: Cpu, features: &str) -> Result<Measured, String> {
    let (out, flash) = build_and_print(cpu, features)?;
    let mut m = Measured {
        ticks: Vec::new(),
        stack: Vec::new(),
        outputs: Vec::new(),
        flash,
    };
    for line in out.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        if let ["state", _, ticks, stack, values @ ..] = fields.as_slice() {
            let bad = || format!("bad line {line}");
            m.ticks.push(ticks.parse().map_err(|_| bad())?);
            m.stack.push(stack.parse().map_err(|_| bad())?);
            let mut output = [0.0f32; 3];
            for (o, v) in output.iter_mut().zip(values) {
                *o = f32::from_bits(u32::from_str_radix(v, 16).map_err(|_| bad())?);
            }
            m.outputs.push(output);
        }
    }
    if m.ticks.len() != STATES.len() {
        return Err(format!(
            "bench on {}: {} of {} states reported",
            cpu.name,
            m.ticks.len(),
            STATES.len()
        ));
    }
    Ok(m)
}

/// Builds the bench image with `features` for `cpu` and runs it in QEMU with `-icount`: what it
/// printed, and its flash.
pub(crate) fn build_and_print(cpu: Cpu, features: &str) -> Result<(String, u64), String> {
    let elf = build(cpu, features)?;
    let flash = crate::size::of(&elf)?.flash();
    let mut child = cpu
        .qemu(&elf)?
        .args(["-icount", "shift=6"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| e.to_string())?;
    let deadline = Instant::now() + Duration::from_secs(120);
    let status = loop {
        if let Some(s) = child.try_wait().map_err(|e| e.to_string())? {
            break s;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("bench on {} timed out", cpu.name));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut out = String::new();
    if let Some(mut stdout) = child.stdout.take() {
        std::io::Read::read_to_string(&mut stdout, &mut out).map_err(|e| e.to_string())?;
    }
    if !status.success() {
        return Err(format!("bench on {} exited with {status}", cpu.name));
    }
    Ok((out, flash))
}

/// Builds the bench image with `features` for `cpu`; returns the ELF's path.
pub fn build(cpu: Cpu, features: &str) -> Result<PathBuf, String> {
    let all_features = format!("{features}{}", cpu.board_features);
    crate::qemu::build_image(
        cpu.target,
        &all_features,
        "twocars-bench",
        Stdio::null(),
        &[],
    )
    .map_err(|e| format!("bench build for {} ({all_features}) failed: {e}", cpu.name))
}

/// The session of `twocars::bench::main_loop` served on the host, by a unit with `tables`.
fn host_session<S: Scalar>(
    with_states: bool,
    tables: &'static [twocars::value_tables::ValueTables<'static>],
) -> Result<Outcome, String> {
    let mut bytes = [0u8; SCRIPT_CAPACITY];
    let n = script(with_states, !tables.is_empty(), &mut bytes).ok_or("the script does not fit")?;
    let outcome = serve_script_on::<S>(&mut twocars::serial::Line::new(), &bytes[..n], tables);
    if !outcome.shutdown {
        return Err("the host's session ended without its Shutdown".to_string());
    }
    Ok(outcome)
}

/// The firmware's serial loop on the Cortex-M4F (`bench-loop` image), its replies checked
/// against the host's.
#[derive(Clone, Copy, Debug)]
pub struct LoopMeasured {
    /// Instructions per State frame: deframing, CRC, parsing, the law for both roles, the
    /// Command encoded and written (the session with the states minus the one without, over
    /// its State frames).
    pub per_state: f64,
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
    /// mps2-an386, f32, the unit with the bench's value table (`bench-table`): the session
    /// plays it at the table points.
    M4fTables,
}

/// The bench's value table (`src/bench/table.tcv`), as the `bench-table` image carries it.
fn bench_tables() -> Result<&'static [twocars::value_tables::ValueTables<'static>], String> {
    static TABLE: &[u8] = include_bytes!("../../src/bench/table.tcv");
    let set = twocars::value_tables::ValueTables::parse(TABLE)
        .map_err(|e| format!("src/bench/table.tcv: {e:?}"))?;
    Ok(Box::leak(Box::new([set])))
}

/// Runs the serial loop's bench session on `image`'s CPU; an error where its replies, their
/// digest or its counters differ from the host's (the same unit and backend on the host).
pub fn measure_loop(image: LoopImage) -> Result<LoopMeasured, String> {
    let (cpu, features) = match image {
        LoopImage::M4fFloat => (M4F, "bench-loop"),
        LoopImage::M0Fixed => (M0, "bench-loop,bench-fixed"),
        LoopImage::M4fTables => (M4F, "bench-loop,bench-table"),
    };
    let tables = image == LoopImage::M4fTables;
    let (out, _) = build_and_print(cpu, features)?;
    let mut ticks = [None, None];
    let mut stack = 0;
    let mut replies = 0;
    for line in out.lines() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let ["loop", with, t, s, r, d, a, x] = fields.as_slice() else {
            continue;
        };
        let bad = || format!("bad line {line}");
        let with_states = *with == "1";
        let got = Outcome {
            // The image prints a line only for a session that ended at its Shutdown.
            shutdown: true,
            replies: r.parse().map_err(|_| bad())?,
            digest: u32::from_str_radix(d, 16).map_err(|_| bad())?,
            accepted: a.parse().map_err(|_| bad())?,
            refused: x.parse().map_err(|_| bad())?,
        };
        let want = match image {
            LoopImage::M4fFloat => host_session::<f32>(with_states, &[])?,
            LoopImage::M0Fixed => host_session::<Fixed>(with_states, &[])?,
            LoopImage::M4fTables => host_session::<f32>(with_states, bench_tables()?)?,
        };
        if got != want {
            return Err(format!(
                "serial loop (with states: {with_states}): {} {got:?}, host {want:?}",
                cpu.name
            ));
        }
        ticks[usize::from(with_states)] = Some(t.parse::<f64>().map_err(|_| bad())?);
        if with_states {
            stack = s.parse().map_err(|_| bad())?;
            replies = got.replies;
        }
    }
    let (Some(without), Some(with)) = (ticks[0], ticks[1]) else {
        return Err(format!(
            "the serial loop's image did not report both sessions:\n{out}"
        ));
    };
    let per_instruction = cpu.ticks_per_instruction;
    Ok(LoopMeasured {
        per_state: (with - without)
            / per_instruction
            / twocars::bench::main_loop::state_frames(tables) as f64,
        rest: without / per_instruction,
        stack,
        replies,
    })
}

/// Instructions per evaluation (mean, min, max), the law's stack and flash on one CPU.
struct Row {
    cpu: &'static str,
    numeric: &'static str,
    mean: f64,
    min: f64,
    max: f64,
    stack: u64,
    law_flash: u64,
    image_flash: u64,
}

fn measure(cpu: Cpu, numeric: &'static str, features: &str) -> Result<Row, String> {
    let law = build_and_run(cpu, features)?;
    // The baseline: the same image (numeric backend, set-up, returned type) with the law
    // removed, so that neither the call overhead nor the backend's set-up code (limits, states
    // and guidance built before the timed region) is counted as the law's.
    let empty = build_and_run(cpu, &format!("{features},bench-empty"))?;
    let overhead = empty.ticks.iter().sum::<f64>() / empty.ticks.len() as f64;
    let instructions: Vec<f64> = law
        .ticks
        .iter()
        .map(|t| (t - overhead) / cpu.ticks_per_instruction)
        .collect();
    let mean = instructions.iter().sum::<f64>() / instructions.len() as f64;
    let min = instructions.iter().copied().fold(f64::INFINITY, f64::min);
    let max = instructions.iter().copied().fold(0.0, f64::max);
    let base_stack = empty.stack.iter().copied().max().unwrap_or(0);
    let stack = law
        .stack
        .iter()
        .copied()
        .max()
        .unwrap_or(0)
        .saturating_sub(base_stack);
    Ok(Row {
        cpu: cpu.name,
        numeric,
        mean,
        min,
        max,
        stack,
        law_flash: law.flash.saturating_sub(empty.flash),
        image_flash: law.flash,
    })
}

/// Upper value (s) and commands w_p, w_e (1/m) of one `Guidance::step` on backend `S` per bench
/// state, on the host: what the bench image computes on the target.
pub fn host_outputs<S: Scalar>() -> Vec<Option<[f64; 3]>> {
    let [v_pm, w_pm, v_em, w_em] = LIMITS;
    STATES
        .iter()
        .map(|&(p, e)| {
            let limits = Limits::<S>::new(v_pm, w_pm, v_em, w_em).ok()?;
            let (p, e) = limits.states(p, e).ok()?;
            let mut guidance = Guidance::new(Law::new(limits, Variant::Paper), DT).ok()?;
            let ev = guidance.step(&p, &e);
            let units = ev.units;
            let upper = ev.report.and_then(|r| r.solution.upper);
            Some([
                upper.map_or(f64::INFINITY, |v| units.seconds(v)),
                units.curvature(ev.command.pursuer),
                units.curvature(ev.command.evader),
            ])
        })
        .collect()
}

/// Largest relative error of the predicted value (upper) on the bench states vs the f64 law.
fn value_error<S: Scalar>() -> f64 {
    host_outputs::<f64>()
        .iter()
        .zip(host_outputs::<S>())
        .filter_map(|(a, b)| Some((a.as_ref()?[0], b?[0])))
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (a - b).abs() / a.abs().max(1.0))
        .fold(0.0, f64::max)
}

/// Law evaluations and frame decodes per second on one host core.
fn host_throughput() -> (f64, f64) {
    let [v_pm, w_pm, v_em, w_em] = LIMITS;
    let limits = Limits::<f32>::new(v_pm, w_pm, v_em, w_em).ok();
    let states: Vec<_> = STATES
        .iter()
        .filter_map(|(p, e)| {
            Some((
                VehicleState::new(p[0], p[1], p[2]).ok()?,
                VehicleState::new(e[0], e[1], e[2]).ok()?,
            ))
        })
        .collect();
    let mut evaluations = 0u64;
    let start = Instant::now();
    if let Some(limits) = limits {
        let law = Law::new(limits, Variant::Paper);
        while start.elapsed() < Duration::from_millis(500) {
            for (p, e) in &states {
                std::hint::black_box(law.evaluate(std::hint::black_box(p), e));
                evaluations += 1;
            }
        }
    }
    let law_rate = evaluations as f64 / start.elapsed().as_secs_f64();
    let frame = host_tests::link::state(1, &host_tests::session::paper_state(0, 0));
    let mut decodes = 0u64;
    let mut deframer = twocars::wire::Deframer::<{ twocars::wire::MAX_FRAME }>::new();
    let start = Instant::now();
    while start.elapsed() < Duration::from_millis(500) {
        for &b in &frame {
            if let twocars::wire::Feed::Frame(f) = deframer.push(std::hint::black_box(b)) {
                if let Ok(f) = twocars::wire::Frame::new_checked(f) {
                    std::hint::black_box(twocars::message::StateMsg::parse(f.payload()).ok());
                    decodes += 1;
                }
            }
        }
    }
    (law_rate, decodes as f64 / start.elapsed().as_secs_f64())
}

/// Runs the bench; returns the exit code.
pub fn run() -> i32 {
    let images = [
        (M4F, "f32 (own polynomials + VSQRT)", "bench-firmware"),
        (M4F, "micromath (f32)", "bench-micromath"),
        (M0, "fixed point (Q17.14)", "bench-fixed"),
        (M0, "f32 soft-float (own polynomials)", "bench-firmware"),
        (M4F, "f32, `step` with the per-pair report", "bench-report"),
    ];
    // Each row builds and runs two images (the law and its empty baseline).
    let progress = Progress::new(images.len() as u64, "bench images (law and baseline each)");
    let rows = images.map(|(cpu, numeric, features)| {
        progress.step(&format!("{} {numeric}", cpu.name()));
        let row = measure(cpu, numeric, features);
        progress.inc();
        row
    });
    progress.finish();
    let mut md = String::new();
    let _ = writeln!(md, "# Bench\n");
    let _ = writeln!(
        md,
        "Regenerated by `cargo xtask bench`; do not edit by hand.\n"
    );
    let _ = writeln!(
        md,
        "Law: one `Guidance::decide`, the firmware's path (both roles: 2 x 2 circles, 4 valid \
         tangents, 4 capture times, the matrix game, both sampled commands; the status, the game's \
         solution and the commands returned), and on the last row one `Guidance::step`, which also \
         returns the per-pair report the host tools print, at the paper's limits (v_pm = 2, w_pm = 2, v_em = 1, \
         w_em = 1), dt = 10 ms, over the {} states of `src/bench.rs` (the paper's four cases, a tail \
         chase, no valid tangent, the overshoot entry, near and far states).\n",
        STATES.len()
    );
    let _ = writeln!(
        md,
        "Method: QEMU 7 with `-icount shift=6` (64 ns per instruction) and SysTick on the processor \
         clock: 25 MHz on mps2-an386 (1.6 ticks per instruction), 16 MHz on micro:bit (1.024); one \
         evaluation timed at a time; the call overhead (the same image with the law removed, \
         `bench-empty`) subtracted. Resolution: one tick (0.6 instruction on M4F, 1 on M0). Stack: \
         4 KiB painted below the caller, high-water mark after the call, minus the empty image's. \
         Law flash: image minus the empty image (each row's own: the same numeric backend and \
         set-up, the law removed).\n"
    );
    let _ = writeln!(md, "| CPU | numeric | instructions per evaluation: mean (min - max) | law stack | law flash | bench image flash |");
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    let mut ok = true;
    for row in &rows {
        match row {
            Ok(r) => {
                let _ = writeln!(
                    md,
                    "| {} | {} | {:.0} ({:.0} - {:.0}) | {} B | {} B | {} B |",
                    r.cpu, r.numeric, r.mean, r.min, r.max, r.stack, r.law_flash, r.image_flash
                );
            }
            Err(e) => {
                eprintln!("xtask bench: {e}");
                ok = false;
            }
        }
    }
    let _ = writeln!(md);
    let _ = writeln!(
        md,
        "Accuracy on the bench states: largest relative error of the predicted capture time vs the \
         f64 path: f32 (own polynomials + VSQRT) {:.1e}, micromath {:.1e}, fixed point {:.1e}.\n",
        value_error::<f32>(),
        value_error::<Micro>(),
        value_error::<Fixed>()
    );
    match measure_loop(LoopImage::M4fFloat) {
        Ok(l) => {
            let _ = writeln!(
                md,
                "Main loop (Cortex-M4F, f32; `bench-loop` image: the firmware's serial path, the \
                 UART interrupt's handler and `twocars::serial::service` over the `heapless` \
                 queues, fed the script of `src/bench/main_loop.rs` by a scripted UART one byte \
                 per interrupt: the bench states as State frames under each policy, {} replies, \
                 all equal to the host's): **{:.0} instructions per State frame** (each byte \
                 queued by the handler and dequeued by the loop, deframe, CRC, parse, the law \
                 for both roles, the Command encoded, queued and handed to the transmitter by \
                 the handler; exception entry and return are not instructions: the session's \
                 instructions less those of the same session without its State frames, {:.0}, \
                 over its State frames); **stack \
                 {} B** (the unit, its buffers and the law below the loop's frame, as in the \
                 firmware's `main`; the queues are statics; an interrupt adds its exception frame, 104 B with the FPU \
                 context (108 B when realigned), and its handler's).\n",
                l.replies, l.per_state, l.rest, l.stack
            );
        }
        Err(e) => {
            eprintln!("xtask bench: {e}");
            ok = false;
        }
    }
    match measure_loop(LoopImage::M0Fixed) {
        Ok(l) => {
            let _ = writeln!(
                md,
                "Main loop (Cortex-M0, fixed point; the same `bench-loop` session on the micro:bit \
                 with the Q17.14 law, the wire's f32 values converted with integers only, {} \
                 replies, all equal to the same unit's on the host): **{:.0} instructions per \
                 State frame** (the session without its State frames: {:.0}); **stack {} B**.\n",
                l.replies, l.per_state, l.rest, l.stack
            );
        }
        Err(e) => {
            eprintln!("xtask bench: {e}");
            ok = false;
        }
    }
    match measure_loop(LoopImage::M4fTables) {
        Ok(l) => {
            let _ = writeln!(
                md,
                "Main loop with the value tables (Cortex-M4F, f32; `bench-loop,bench-table`: the \
                 unit carries `src/bench/table.tcv` and one Configure selects it, policy 2; the \
                 {} table points of the bench below as State frames, the pursuer at the origin, \
                 so that both players' turns are read from the table, {} replies, all equal to \
                 the host's): **{:.0} instructions per State frame** (the session without its \
                 State frames: {:.0}); **stack {} B**.\n",
                twocars::bench::main_loop::state_frames(true),
                l.replies,
                l.per_state,
                l.rest,
                l.stack
            );
        }
        Err(e) => {
            eprintln!("xtask bench: {e}");
            ok = false;
        }
    }
    for paragraph in [
        crate::bench_mavlink::measure().map(|m| crate::bench_mavlink::paragraph(&m)),
        crate::bench_table::measure().map(|m| crate::bench_table::paragraph(&m)),
    ] {
        match paragraph {
            Ok(text) => {
                let _ = writeln!(md, "{text}");
            }
            Err(e) => {
                eprintln!("xtask bench: {e}");
                ok = false;
            }
        }
    }
    let firmware = firmware_sizes();
    let _ = writeln!(md, "{firmware}");
    let (law_rate, decode_rate) = host_throughput();
    let _ = writeln!(
        md,
        "Host, one core (this machine; optimised build): {:.2e} law evaluations per second, \
         {:.2e} State frames decoded per second (deframe + CRC + parse).\n",
        law_rate, decode_rate
    );
    let _ = writeln!(
        md,
        "Targets: <= 400 instructions per evaluation on M4F (f32), <= 1,500 on M0 (fixed point), \
         law <= 3 KiB flash, stack <= 512 B, firmware <= 32 KiB flash."
    );
    print!("{md}");
    if let Err(e) = std::fs::write(root().join("docs/bench.md"), &md) {
        eprintln!("xtask bench: docs/bench.md: {e}");
        ok = false;
    }
    i32::from(!ok)
}

fn firmware_sizes() -> String {
    let mut s = String::from(
        "| firmware image | flash | of the board's flash | static RAM |\n|---|---|---|---|\n",
    );
    for board in qemu::Board::ALL {
        match qemu::build_checked(board) {
            Ok((elf, size)) => {
                let name = elf
                    .file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
                let _ = writeln!(
                    s,
                    "| {name} | {} B | {:.1} % of {} KiB | {} B |",
                    size.flash(),
                    100.0 * size.flash() as f64 / board.flash_bytes() as f64,
                    board.flash_bytes() >> 10,
                    size.ram()
                );
            }
            Err(e) => {
                let _ = writeln!(s, "| {board:?} | build failed: {e} | |");
            }
        }
    }
    s
}
