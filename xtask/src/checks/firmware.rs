//! Tests of the firmware in QEMU (part of `cargo xtask test`): the scripted session answered
//! exactly like the host's unit, the closed loop equal to the host simulation, the watchdog, and
//! exit code 0 after Shutdown.

use std::time::Duration;

use twocars::num::fixed::Fixed;
use twocars::protocol::endpoint::{Endpoint, STATUS_STALE_INPUT};
use twocars::protocol::message::{Counters, LineCounts};
use twocars::protocol::message::{ROLE_EVADER, ROLE_PURSUER};
use twocars::{Policy, Scalar, Variant};
use twocars_sim::link::{Reply, ReplyDecoder};
use twocars_sim::scenarios::{paper_cases, Case, PAPER_LIMITS};
use twocars_sim::session::{paper_configure, paper_state, script};
use twocars_sim::sim::{simulate, SimParams};

use super::Tally;
use crate::harness::firmware::closed_loop;
use crate::harness::firmware::emulator::Emulator;
use crate::image::{self, Image};

type Outcome = Result<String, String>;
type QemuTest = fn(&std::path::Path) -> Outcome;

fn host_replies<S: Scalar>(bytes: &[u8], unit: &mut Endpoint<S>) -> Vec<Reply> {
    let mut decoder = ReplyDecoder::default();
    bytes
        .iter()
        .filter_map(|&b| unit.receive(b, 0).copied())
        .flat_map(|r| decoder.feed(r.as_bytes()))
        .filter_map(Result::ok)
        .collect()
}

fn same(a: &Reply, b: &Reply) -> bool {
    match (a, b) {
        (Reply::Command(s, x), Reply::Command(t, y)) => {
            s == t
                && x.status == y.status
                && x.pursuer_rate.to_bits() == y.pursuer_rate.to_bits()
                && x.evader_rate.to_bits() == y.evader_rate.to_bits()
                && (x.row, x.col) == (y.row, y.col)
                && x.predicted.to_bits() == y.predicted.to_bits()
                && x.upper.to_bits() == y.upper.to_bits()
                && x.lower.to_bits() == y.lower.to_bits()
        }
        _ => a == b,
    }
}

fn scripted_session(elf: &std::path::Path) -> Outcome {
    scripted_session_on::<f32>(elf, Image::Qemu)
}

/// `counters` less what the readiness probe counted before the session (`before`, and the
/// probe's own message, counted after its reply), with the board's status flags checked
/// against `board`'s and cleared: the host's unit has neither.
fn since_probe(
    counters: Counters,
    before: Option<Counters>,
    board: Image,
) -> Result<Counters, String> {
    if counters.board != board.status_in_emulator() {
        return Err(format!(
            "board status {}, expected {}",
            counters.board,
            board.status_in_emulator()
        ));
    }
    let Some(b) = before else {
        return Ok(Counters {
            board: 0,
            ..counters
        });
    };
    let less = |x: u32, y: u32| x.wrapping_sub(y);
    let (l, bl) = (counters.line, b.line);
    Ok(Counters {
        accepted: less(counters.accepted, b.accepted + 1),
        stale: less(counters.stale, b.stale),
        errors: core::array::from_fn(|i| less(counters.errors[i], b.errors[i])),
        line: LineCounts {
            overrun: less(l.overrun, bl.overrun),
            framing: less(l.framing, bl.framing),
            noise: less(l.noise, bl.noise),
            parity: less(l.parity, bl.parity),
            rx_full: less(l.rx_full, bl.rx_full),
            tx_full: less(l.tx_full, bl.tx_full),
        },
        board: 0,
        coasted: less(counters.coasted, b.coasted),
        fixes_refused: less(counters.fixes_refused, b.fixes_refused),
    })
}

/// The scripted session on `board`'s image, each reply equal to the host unit's on backend `S`
/// (counters taken from the readiness probe's, where the image was probed).
fn scripted_session_on<S: Scalar>(elf: &std::path::Path, board: Image) -> Outcome {
    let mut q = Emulator::start(elf, board, false)?;
    let mut unit = Endpoint::<S>::new();
    for step in script() {
        q.send(&step.bytes)?;
        let got = match q.reply().map_err(|e| format!("{}: {e}", step.name))? {
            Reply::Counters(s, c) => Reply::Counters(
                s,
                since_probe(c, q.before_session(), board)
                    .map_err(|e| format!("{}: {e}", step.name))?,
            ),
            other => other,
        };
        let want = host_replies(&step.bytes, &mut unit);
        match want.as_slice() {
            [w] if same(w, &got) => {}
            _ => {
                return Err(format!(
                    "{}: firmware {got:?}, host unit {want:?}",
                    step.name
                ))
            }
        }
    }
    let mut sequence = 1000;
    let exits = q.exits_on_shutdown();
    let code = closed_loop::shutdown(q, &mut sequence)?;
    if code != 0 {
        return Err(format!("exit code {code} after Shutdown"));
    }
    Ok(format!(
        "{} steps answered as the host unit does; {}",
        script().len(),
        if exits {
            "exit code 0"
        } else {
            "Shutdown acknowledged"
        }
    ))
}

/// A paper case at the paper's limits, dt = 10 ms, 30 s, capture to 1 cm.
fn paper_case_params(case: &Case) -> SimParams {
    SimParams {
        limits: PAPER_LIMITS,
        pursuer: case.pursuer,
        evader: case.evader,
        dt: 0.01,
        t_max: 30.0,
        eps: 0.01,
    }
}

fn closed_loop(elf: &std::path::Path) -> Outcome {
    closed_loop_on(elf, Image::Qemu)
}

/// The paper's cases under both policies on `board`'s f32 image, each capture within a control
/// period of the host simulation's.
fn closed_loop_on(elf: &std::path::Path, board: Image) -> Outcome {
    let mut q = Emulator::start(elf, board, false)?;
    let mut sequence = 0;
    let mut report = Vec::new();
    // Both policies: Configure's policy byte selects the firmware's, the host runs the same.
    for policy in [Policy::Paper, Policy::Flight] {
        for case in paper_cases() {
            let params = paper_case_params(&case);
            let fw = closed_loop::run_case(
                &mut q,
                &mut sequence,
                &params,
                ROLE_PURSUER | ROLE_EVADER,
                (Variant::Paper, policy),
            )?;
            let host = simulate::<f32>(&params, Variant::Paper, policy, false);
            let diff = fw.result.t_capture - host.t_capture;
            // Stated tolerance: one control period (the same f32 code runs on both sides).
            if fw.result.status != host.status || diff.abs() > params.dt || fw.errors_received > 0 {
                return Err(format!(
                    "{} {policy:?}: firmware {:?} vs host {:?}",
                    case.name, fw.result, host
                ));
            }
            report.push(format!("{} {policy:?} {:+.1e} s", case.name, diff));
        }
    }
    closed_loop::shutdown(q, &mut sequence)?;
    Ok(format!(
        "capture time firmware - host: {}",
        report.join(", ")
    ))
}

fn watchdog(elf: &std::path::Path) -> Outcome {
    watchdog_on(elf, Image::Qemu)
}

/// Half a second of silence after a State on `board`'s image: the safe command, latched until
/// Reset; the watchdog counted once.
fn watchdog_on(elf: &std::path::Path, board: Image) -> Outcome {
    let mut q = Emulator::start(elf, board, false)?;
    q.send(&twocars_sim::link::configure(1, &paper_configure()))?;
    q.reply()?;
    q.send(&twocars_sim::link::state(2, &paper_state(0, 0)))?;
    q.reply()?;
    // Silence past the 0.5 s watchdog: the firmware sends the safe command by itself.
    std::thread::sleep(Duration::from_millis(700));
    match q.reply()? {
        Reply::Command(_, c)
            if c.status == STATUS_STALE_INPUT && c.pursuer_rate == 0.0 && c.evader_rate == 0.0 => {}
        other => {
            return Err(format!(
                "expected the stale-input safe command, got {other:?}"
            ))
        }
    }
    // Latched: a fresh State still gets the safe command; a Reset clears it.
    q.send(&twocars_sim::link::state(3, &paper_state(0, 800)))?;
    match q.reply()? {
        Reply::Command(3, c) if c.status == STATUS_STALE_INPUT => {}
        other => return Err(format!("expected the latched safe command, got {other:?}")),
    }
    q.send(&twocars_sim::link::reset(4))?;
    match q.reply()? {
        Reply::ResetAck(4) => {}
        other => return Err(format!("expected the Reset acknowledgement, got {other:?}")),
    }
    q.send(&twocars_sim::link::state(5, &paper_state(0, 810)))?;
    match q.reply()? {
        Reply::Command(5, c) if c.status == 0 && c.pursuer_rate == 4.0 => {}
        other => {
            return Err(format!(
                "expected the law's command after Reset, got {other:?}"
            ))
        }
    }
    let mut sequence = 5;
    let counters = closed_loop::counters(&mut q, &mut sequence)?;
    if counters.stale != 1 {
        return Err(format!("stale counter {}", counters.stale));
    }
    closed_loop::shutdown(q, &mut sequence)?;
    Ok(
        "safe command with status stale_input after 0.5 s of silence, latched until Reset"
            .to_string(),
    )
}

/// 400 States written back to back without waiting, each after a burst of line noise (1 to 24
/// random bytes, zeros included) and a delimiter: every State answered with its Command, in
/// order; the noise refused with Errors that the counters match; no reset.
fn noisy_stream(elf: &std::path::Path) -> Outcome {
    noisy_stream_on(elf, Image::Qemu)
}

/// [`noisy_stream`] on `board`'s image.
fn noisy_stream_on(elf: &std::path::Path, board: Image) -> Outcome {
    const STATES: u16 = 400;
    let mut q = Emulator::start(elf, board, false)?;
    let (accepted_before, refused_before) = q.counted_before();
    q.send(&twocars_sim::link::configure(1, &paper_configure()))?;
    match q.reply()? {
        Reply::ConfigureAck(1, Some(0)) => {}
        other => return Err(format!("expected ConfigureAck, got {other:?}")),
    }
    let mut rng = twocars_sim::rng::Rng::new(27);
    let (mut stream, mut noise_bytes) = (Vec::new(), 0);
    for k in 0..STATES {
        let noise = 1 + rng.next_u64() % 24;
        noise_bytes += noise;
        stream.extend((0..noise).map(|_| rng.next_u64() as u8));
        stream.push(0);
        let t_ms = 10 * u32::from(k);
        stream.extend(twocars_sim::link::state(
            100 + k,
            &paper_state(usize::from(k), t_ms),
        ));
    }
    q.send(&stream)?;
    let (mut answered, mut errors) = (Vec::new(), 0u32);
    while answered.len() < usize::from(STATES) {
        match q.reply()? {
            Reply::Command(s, c) if c.status == 0 => answered.push(s),
            Reply::Error(None, _) => errors += 1,
            other => return Err(format!("unexpected reply {other:?}")),
        }
    }
    if !answered.iter().copied().eq(100..100 + STATES) {
        return Err(format!("Commands out of order or missing: {answered:?}"));
    }
    let mut sequence = 1000;
    let counters = closed_loop::counters(&mut q, &mut sequence)?;
    let refused: u32 = counters.errors.iter().sum();
    // Accepted: the Configure and the States (the ReadCounters counts after its reply).
    let board_status = board.status_in_emulator();
    if refused != refused_before + errors
        || counters.accepted != accepted_before + 1 + u32::from(STATES)
        || counters.board != board_status
    {
        return Err(format!(
            "counters {counters:?}: {errors} Errors received, {} messages sent",
            STATES + 2
        ));
    }
    closed_loop::shutdown(q, &mut sequence)?;
    Ok(format!(
        "{STATES} States behind {noise_bytes} bytes of noise: {STATES} Commands in order, \
         {errors} Errors for the noise, counters agree; board status {}",
        counters.board
    ))
}

/// The fixed-point law on a Cortex-M0 (QEMU micro:bit, the bench image): every bench state's
/// value and commands equal to the host's fixed-point law bit for bit (integer arithmetic), and
/// the paper's four values (the first four bench states) within 1e-3 s.
fn fixed_point_on_cortex_m0() -> Outcome {
    let m0 =
        crate::harness::bench::image::build_and_run(crate::harness::bench::image::M0, "law_fixed")?;
    let host = crate::harness::bench::law::host_outputs::<twocars::num::fixed::Fixed>();
    if m0.outputs.len() != host.len() {
        return Err(format!(
            "{} of {} states reported",
            m0.outputs.len(),
            host.len()
        ));
    }
    for (i, (got, want)) in m0.outputs.iter().zip(&host).enumerate() {
        let want = want.ok_or(format!("state {i}: the host could not evaluate it"))?;
        if got.map(f32::to_bits) != want.map(|v| (v as f32).to_bits()) {
            return Err(format!("state {i}: Cortex-M0 {got:?}, host {want:?}"));
        }
    }
    let mut values = Vec::new();
    for (case, got) in paper_cases().iter().zip(&m0.outputs) {
        let value = f64::from(got[0]);
        if (value - case.expected_value).abs() > 1e-3 {
            return Err(format!(
                "{}: {value:.4} s on the M0, paper {:.4} s",
                case.name, case.expected_value
            ));
        }
        values.push(format!("{} {value:.4} s", case.name));
    }
    Ok(format!(
        "{} states equal to the host bit for bit; {}",
        host.len(),
        values.join(", ")
    ))
}

/// The firmware's serial loop on the Cortex-M4F (the bench's `serial` image, QEMU
/// mps2-an386): the bench session's replies (their count and digest) and the unit's counters
/// equal the host's.
fn serial_loop_on_cortex_m4f() -> Outcome {
    let l = crate::harness::bench::serial::measure_loop(
        crate::harness::bench::serial::LoopImage::M4fFloat,
    )?;
    Ok(format!(
        "{} replies equal to the host's; {:.0} instructions per State frame, stack {} B",
        l.replies, l.per_state, l.stack
    ))
}

/// A fixed-point image (micro:bit, RP2040) in closed loop on the paper's four cases under both
/// policies: every run identical to the same unit's on the host (`HostUnit<Fixed>` fed the same
/// frames), bit for bit: capture time, switches and sign flips.
fn fixed_point_closed_loop(elf: &std::path::Path, board: Image) -> Outcome {
    let mut q = Emulator::start(elf, board, false)?;
    let (mut sequence, mut twin_sequence) = (0, 0);
    let mut twin = closed_loop::HostUnit::<Fixed>::new();
    let mut times = Vec::new();
    for policy in [Policy::Paper, Policy::Flight] {
        for case in paper_cases() {
            let params = paper_case_params(&case);
            let how = (Variant::Paper, policy);
            let both = ROLE_PURSUER | ROLE_EVADER;
            let fw = closed_loop::run_case(&mut q, &mut sequence, &params, both, how)?;
            let host = closed_loop::run_case(&mut twin, &mut twin_sequence, &params, both, how)?;
            let (f, h) = (&fw.result, &host.result);
            if f.status != h.status
                || f.t_capture.to_bits() != h.t_capture.to_bits()
                || (f.switches, f.sign_flips) != (h.switches, h.sign_flips)
                || fw.errors_received > 0
            {
                return Err(format!(
                    "{} {policy:?}: firmware {f:?} vs the host's unit {h:?}",
                    case.name
                ));
            }
            times.push(format!("{} {policy:?} {:.4} s", case.name, f.t_capture));
        }
    }
    closed_loop::shutdown(q, &mut sequence)?;
    Ok(format!("identical runs: {}", times.join(", ")))
}

/// A test of one board's image: the ELF and the board.
type BoardTest = fn(&std::path::Path, Image) -> Outcome;

/// One board's flight image in its emulator, as `cargo xtask build` builds it, and the tests
/// run on it; `failed_build` names the record of a build (or emulator install) that failed.
struct ImageTests {
    heading: &'static str,
    board: Image,
    failed_build: &'static str,
    tests: &'static [(&'static str, BoardTest)],
}

/// The micro:bit (fixed point); the STM32F405, whose crystal never starts in netduinoplus2
/// (it runs on the internal oscillator); the Raspberry Pi Pico in rp2040js.
const IMAGE_TESTS: [ImageTests; 3] = [
    ImageTests {
        heading: "firmware in QEMU (micro:bit, Cortex-M0, fixed point)",
        board: Image::Microbit,
        failed_build: "qemu::microbit_image_builds",
        tests: &[
            (
                "qemu::microbit_scripted_session_matches_the_host_fixed_point_unit",
                scripted_session_on::<Fixed>,
            ),
            (
                "qemu::microbit_closed_loop_equals_the_same_unit_on_the_host_bit_for_bit",
                fixed_point_closed_loop,
            ),
        ],
    },
    ImageTests {
        heading: "firmware in QEMU (netduinoplus2, STM32F405, the flight image)",
        board: Image::Stm32f405,
        failed_build: "qemu::stm32f405_image_builds",
        tests: &[
            (
                "qemu::stm32f405_scripted_session_matches_the_host_unit",
                scripted_session_on::<f32>,
            ),
            (
                "qemu::stm32f405_closed_loop_matches_the_host_simulation",
                closed_loop_on,
            ),
            (
                "qemu::stm32f405_states_through_line_noise_are_all_answered_in_order",
                noisy_stream_on,
            ),
        ],
    },
    ImageTests {
        heading: "firmware in rp2040js (RP2040, Cortex-M0+, fixed point, the flight image)",
        board: Image::Rp2040,
        failed_build: "rp2040js::rp2040_image_runs",
        tests: &[
            (
                "rp2040js::rp2040_scripted_session_matches_the_host_fixed_point_unit",
                scripted_session_on::<Fixed>,
            ),
            (
                "rp2040js::rp2040_closed_loop_equals_the_same_unit_on_the_host_bit_for_bit",
                fixed_point_closed_loop,
            ),
            (
                "rp2040js::rp2040_watchdog_latches_the_safe_command_until_reset",
                watchdog_on,
            ),
            (
                "rp2040js::rp2040_states_through_line_noise_are_all_answered_in_order",
                noisy_stream_on,
            ),
        ],
    },
];

/// Builds each board's image (rp2040js installed first where it runs there) and runs its tests.
fn run_images(record: &mut impl FnMut(&str, Outcome)) {
    for image in &IMAGE_TESTS {
        println!("== xtask test: {}", image.heading);
        let ready = match image.board.machine() {
            Some(image::Machine::Rp2040js) => {
                crate::harness::firmware::rp2040js::installed().map(|_| ())
            }
            _ => Ok(()),
        };
        let elf = match ready.and_then(|()| image::build_checked(image.board, None)) {
            Ok((elf, _)) => elf,
            Err(e) => {
                record(image.failed_build, Err(e));
                continue;
            }
        };
        for (name, test) in image.tests {
            record(name, test(&elf, image.board));
        }
    }
}

/// The serial images' tests in their emulators: QEMU's mps2-an386, the other boards', the
/// value tables' image and the serial loop's and the fixed-point law's bench sessions.
pub fn serial_images(tally: &mut Tally) {
    println!("== xtask test: firmware in QEMU (mps2-an386)");
    let elf = match crate::util::setup::qemu_binary()
        .and_then(|_| image::build_checked(Image::Qemu, None))
    {
        Ok((elf, _)) => elf,
        Err(e) => {
            tally.record("qemu::image_builds_and_qemu_is_found", Err(e));
            return;
        }
    };
    let tests: [(&str, QemuTest); 4] = [
        (
            "qemu::scripted_session_matches_the_host_unit_byte_for_byte",
            scripted_session,
        ),
        ("qemu::closed_loop_matches_the_host_simulation", closed_loop),
        (
            "qemu::watchdog_latches_the_safe_command_until_reset",
            watchdog,
        ),
        (
            "qemu::states_back_to_back_through_line_noise_are_all_answered_in_order",
            noisy_stream,
        ),
    ];
    for (name, test) in tests {
        tally.record(name, test(&elf));
    }
    let mut record = |name: &str, outcome: Outcome| tally.record(name, outcome);
    run_images(&mut record);
    crate::checks::tables::run(&mut record);
    println!("== xtask test: the serial loop's bench session in QEMU (mps2-an386)");
    record(
        "qemu::serial_loop_bench_session_on_cortex_m4f_equals_the_host",
        serial_loop_on_cortex_m4f(),
    );
    println!("== xtask test: fixed-point law in QEMU (micro:bit, Cortex-M0)");
    record(
        "qemu::fixed_point_law_on_cortex_m0_equals_the_host_and_the_paper",
        fixed_point_on_cortex_m0(),
    );
}

/// The MAVLink images in QEMU, pymavlink playing the autopilot and the target: the scripted
/// session, the paper's cases on two boards, the field's chases, and the signed link.
pub fn mavlink_images(tally: &mut Tally) {
    println!("== xtask test: the MAVLink images in QEMU, pymavlink the autopilot and the target");
    tally.record(
        "qemu::mavlink_scripted_session_passes_every_check",
        crate::harness::firmware::mavlink::scripted_session(Image::QemuMavlink)
            .map(|()| "every check passed".to_string()),
    );
    // The STM32F405 image closes the loop too. Its scripted session's timing checks do not
    // hold in netduinoplus2: QEMU clocks SysTick at the model's own rate whatever the clock
    // controller says, so the image's internal-oscillator millisecond runs 10.5 times fast.
    for (image, name) in [
        (Image::QemuMavlink, "mavlink"),
        (Image::Stm32f405Mavlink, "stm32f405_mavlink"),
    ] {
        tally.record(
            &format!("qemu::{name}_closed_loop_captures_the_paper_cases_on_time"),
            crate::harness::firmware::mavlink::run_cases(image, None).and_then(|on_time| {
                if on_time {
                    Ok("four captures within 5 control periods".to_string())
                } else {
                    Err("a capture missed its reference by more than 5 periods".to_string())
                }
            }),
        );
    }
    tally.record(
        "qemu::mavlink_late_sparse_noisy_target_is_captured_without_chatter",
        crate::harness::firmware::mavlink_field::run_field(Image::QemuMavlink, None).and_then(
            |ok| {
                if ok {
                    Ok("four captures, median sign flips within 5".to_string())
                } else {
                    Err("a chase was not captured, or the setpoint chattered".to_string())
                }
            },
        ),
    );
    tally.record(
        "qemu::mavlink_signed_closed_loop_captures_and_refuses_unsigned_and_forged_frames",
        signed_closed_loop(),
    );
}

/// The MAVLink image built with a signing key, pymavlink signing with it: the paper's cases
/// captured on time; a PARAM_SET unsigned, wrongly keyed, replayed, with its timestamp gone back
/// and with its signature cut short each refused and counted; the unit's frames well signed by
/// pymavlink's check. The key is a fixed test key.
fn signed_closed_loop() -> Outcome {
    let key = crate::image::signing::SigningKey::for_tests()?;
    match crate::harness::firmware::mavlink::run_cases(Image::QemuMavlink, Some(&key))? {
        true => Ok(
            "signed both ways: four captures within 5 control periods; five forged \
                    PARAM_SETs unanswered, each counted once; pymavlink took every frame"
                .to_string(),
        ),
        false => Err("a capture missed its reference, or a forged PARAM_SET was taken".to_string()),
    }
}
