//! The main job over our serial protocol: the firmware runs in its board's emulator (QEMU, or
//! rp2040js for the RP2040), its UART on a loopback TCP link to the host simulator, which
//! integrates both vehicles exactly and sends a State every control period; per case it prints
//! the law's matrix at t = 0, the capture time in closed loop with the firmware, the host-only
//! simulation of the same case, frames and counters.

use twocars::law::{evaluate_observation, Observation};
use twocars::value_tables::ValueTables;
use twocars::{Policy, Scalar};
use twocars_sim::scenarios::Case;
use twocars_sim::scenarios::EPS;
use twocars_sim::sim::{SimParams, SimResult, SimStatus};

use crate::harness::firmware::closed_loop;
use crate::harness::firmware::emulator::Emulator;
use crate::harness::host::{with_numeric, Options};
use crate::image::{self, Image};

/// Largest |firmware - host| capture-time difference accepted, in control periods.
const AGREEMENT_PERIODS: f64 = 3.0;

/// What `run` flies over our serial protocol: the cases, the limits (m/s, 1/m), the control
/// period and longest run (s), the roles the firmware plays (Configure's bits), and whether
/// the host simulates alone.
#[derive(Debug, Clone)]
pub struct RunOptions {
    pub cases: Vec<Case>,
    pub limits: [f64; 4],
    pub dt: f64,
    pub t_max: f64,
    pub roles: u8,
    pub host_only: bool,
}

/// A start below the theorem's threshold at the paper's limits, where the tables play: the
/// evader 1.1 m behind and to the left of the pursuer, turning across its path.
pub const NEAR_CASE: Case = Case {
    name: "near",
    pursuer: [0.0, 0.0, 0.0],
    evader: [-0.85, 0.75, -0.9],
    expected_value: f64::NAN,
};

fn observation(o: &RunOptions, case: &Case) -> Observation {
    Observation {
        limits: o.limits.map(|v| v as f32),
        pursuer: case.pursuer.map(|v| v as f32),
        evader: case.evader.map(|v| v as f32),
    }
}

/// Prints the law's matrix at t = 0; false if a paper value is off by more than 1e-3 s.
fn show_matrix<S: Scalar>(o: &RunOptions, case: &Case, options: &Options) -> bool {
    let evaluation = evaluate_observation::<S>(&observation(o, case), options.variant);
    println!();
    println!(
        "{}: p0 = {:?}, e0 = {:?}: status {}",
        case.name,
        case.pursuer,
        case.evader,
        evaluation.status.name()
    );
    let Some(report) = evaluation.report else {
        return case.expected_value.is_nan();
    };
    let units = evaluation.units;
    let f = |v: Option<S>| v.map_or("inf".to_string(), |v| format!("{:9.4}", units.seconds(v)));
    let m = report.matrix().entries;
    println!("             evader A   evader C");
    println!("  pursuer A {}  {}", f(m[0][0]), f(m[0][1]));
    println!("  pursuer C {}  {}", f(m[1][0]), f(m[1][1]));
    let s = report.solution;
    println!(
        "  pursuer plays {}, evader plays {}; upper {} s, lower {} s, saddle {}{}",
        s.row.letter(),
        s.col.letter(),
        f(s.upper).trim(),
        f(s.lower).trim(),
        s.saddle(),
        report
            .matrix()
            .mixed_value()
            .map_or(String::new(), |v| format!(
                ", mixed value {:.4} s",
                units.seconds(v)
            )),
    );
    let predicted = s.upper.map_or(f64::INFINITY, |v| units.seconds(v));
    if case.expected_value.is_nan() {
        println!("  predicted capture time {predicted:.4} s");
        true
    } else {
        println!(
            "  predicted capture time {predicted:.4} s (independent f64: {:.4} s)",
            case.expected_value
        );
        (predicted - case.expected_value).abs() <= 1e-3
    }
}

fn params(o: &RunOptions, case: &Case) -> SimParams {
    SimParams {
        limits: o.limits,
        pursuer: case.pursuer,
        evader: case.evader,
        dt: o.dt,
        t_max: o.t_max,
        eps: EPS,
    }
}

fn closing(o: &RunOptions, t: f64) -> f64 {
    t + EPS / (o.limits[0] - o.limits[2])
}

/// A fixed-point image's twin: the same fixed-point unit in this process, fed the same frames;
/// prints the difference of the capture times (0 when the M0 computes what the host does, bit
/// for bit) and whether the two runs are identical.
fn twin_agrees(
    o: &RunOptions,
    case: &Case,
    options: &Options,
    firmware: &twocars_sim::sim::SimResult,
) -> bool {
    let mut twin = closed_loop::HostUnit::<twocars::num::fixed::Fixed>::new();
    let mut sequence = 0u16;
    match closed_loop::run_case(
        &mut twin,
        &mut sequence,
        &params(o, case),
        o.roles,
        (options.variant, options.policy),
    ) {
        Ok(t) => {
            let r = &t.result;
            let same = r.status == firmware.status
                && r.t_capture.to_bits() == firmware.t_capture.to_bits()
                && r.switches == firmware.switches
                && r.sign_flips == firmware.sign_flips;
            println!(
                "  the same unit on the host (fixed point): {}, captured at {:.4} s; firmware - host: {} s ({})",
                r.status.name(),
                r.t_capture,
                firmware.t_capture - r.t_capture,
                if same { "identical runs" } else { "RUNS DIFFER" }
            );
            same
        }
        Err(e) => {
            eprintln!("xtask run: the host twin: {e}");
            false
        }
    }
}

/// Prints the tables' V(x0) for `case`: the time to capture at the tables' radius (one r_p)
/// under optimal play by both sides; none beyond the threshold or inside the disc.
fn print_table_value(o: &RunOptions, case: &Case, set: &ValueTables<'_>) {
    let [v_pm, w_pm, ..] = o.limits;
    let (x, y, phi) = hji::policy::relative(w_pm, case.pursuer, case.evader);
    match set.value(x as f32, y as f32, phi as f32) {
        Some(v) => println!(
            "  the tables' V(x0): {:.4} s to capture within {} m (one r_p) under optimal play by both sides",
            f64::from(v) / (w_pm * v_pm),
            1.0 / w_pm
        ),
        None => println!("  the tables do not play here (beyond the threshold or in the capture disc): the paper's law"),
    }
}

/// Flies `o`'s cases on `board`'s image over our serial protocol, beside the host's
/// simulation of each under `options`; the exit code.
pub fn fly(board: Image, options: &Options, o: &RunOptions) -> i32 {
    let tables = match tables_for(board, options, o) {
        Ok(tables) => tables,
        Err(e) => {
            eprintln!("xtask run: {e}");
            return 2;
        }
    };
    let [v_pm, w_pm, v_em, w_em] = o.limits;
    println!(
        "limits: v_pm = {v_pm} m/s, w_pm = {w_pm} 1/m, v_em = {v_em} m/s, w_em = {w_em} 1/m; variant {:?}, policy {:?}, numeric {:?}",
        options.variant, options.policy, options.numeric
    );
    let mut session = None;
    if !o.host_only {
        match image::build_checked(board, None)
            .and_then(|(elf, _)| Emulator::start(&elf, board, board.logs_with_defmt()))
        {
            Ok(q) => session = Some(q),
            Err(e) => {
                eprintln!("xtask run: {e}");
                return 1;
            }
        }
    }
    let mut ok = true;
    let mut sequence = 0u16;
    for case in &o.cases {
        ok &= with_numeric!(options.numeric, S => show_matrix::<S>(o, case, options));
        let host = host_case(o, case, options, tables);
        let Some(q) = session.as_mut() else { continue };
        match firmware_case(q, &mut sequence, (o, case, options), board, &host) {
            Ok(agrees) => ok &= agrees,
            Err(e) => {
                eprintln!("xtask run: {}: {e}", case.name);
                return 1;
            }
        }
    }
    if let Some(q) = session {
        match finish(q, &mut sequence) {
            Ok(exited_cleanly) => ok &= exited_cleanly,
            Err(e) => {
                eprintln!("xtask run: {e}");
                return 1;
            }
        }
    }
    i32::from(!ok)
}

/// The value-table set the image plays at `o`'s limits (the files it was built with), where
/// it plays one.
fn tables_for(
    board: Image,
    options: &Options,
    o: &RunOptions,
) -> Result<Option<&'static ValueTables<'static>>, String> {
    if board == Image::QemuTables && options.policy == Policy::Table {
        crate::harness::firmware::tables::table_set(o.limits, options.variant, o.dt).map(Some)
    } else {
        Ok(None)
    }
}

/// The host's simulation of `case` (with the image's tables, where it plays them), printed.
fn host_case(
    o: &RunOptions,
    case: &Case,
    options: &Options,
    tables: Option<&'static ValueTables<'static>>,
) -> SimResult {
    let host = match tables {
        Some(set) => {
            print_table_value(o, case, set);
            twocars_sim::sim::simulate_with::<f32>(
                &params(o, case),
                options.variant,
                options.policy,
                false,
                twocars_sim::sim::Setup {
                    tables: Some(set),
                    ..Default::default()
                },
            )
        }
        None => crate::harness::host::run_one(&params(o, case), options, None, false),
    };
    println!(
        "  host simulation (dt = {} s): {}, captured to {EPS} m at {:.4} s (+ eps / (v_pm - v_em) = {:.4} s); {} switches, {} sign flips",
        o.dt,
        host.status.name(),
        host.t_capture,
        closing(o, host.t_capture),
        host.switches,
        host.sign_flips
    );
    host
}

/// `case` flown in closed loop with the firmware, printed; whether it agrees with the host's
/// simulation `host` (and on the micro:bit, with the same unit run on the host bit for bit).
fn firmware_case(
    q: &mut Emulator,
    sequence: &mut u16,
    (o, case, options): (&RunOptions, &Case, &Options),
    board: Image,
    host: &SimResult,
) -> Result<bool, String> {
    let fw = closed_loop::run_case(
        q,
        sequence,
        &params(o, case),
        o.roles,
        (options.variant, options.policy),
    )?;
    let r = &fw.result;
    let diff = r.t_capture - host.t_capture;
    let emulator = board.machine().map_or_else(String::new, |m| m.name());
    println!(
        "  firmware in {emulator}: {}, captured at {:.4} s (+ eps / (v_pm - v_em) = {:.4} s), firmware's prediction {:.4} s; \
         vs host: {:+.6} s ({:+.2} control periods); {} States sent, {} Commands and {} Errors received; {} switches, {} sign flips",
        r.status.name(),
        r.t_capture,
        closing(o, r.t_capture),
        fw.predicted,
        diff,
        diff / o.dt,
        fw.states_sent,
        fw.commands_received,
        fw.errors_received,
        r.switches,
        r.sign_flips
    );
    let mut agree = r.status == host.status
        && (r.status != SimStatus::Captured || diff.abs() <= AGREEMENT_PERIODS * o.dt);
    if matches!(board, Image::Microbit | Image::Rp2040) {
        agree &= twin_agrees(o, case, options, r);
    }
    Ok(agree)
}

/// Reads the firmware's counters, prints them, shuts it down; whether it exited with 0.
fn finish(mut q: Emulator, sequence: &mut u16) -> Result<bool, String> {
    let c = closed_loop::counters(&mut q, sequence)?;
    println!(
        "\nfirmware counters: {} messages accepted, {} refused {:?}, {} watchdog expiries, board status {} (1: fallback clock); {} bytes sent, {} frames received",
        c.accepted,
        c.errors.iter().sum::<u32>(),
        c.errors,
        c.stale,
        c.board,
        q.bytes_sent,
        q.frames_received
    );
    let exits = q.exits_on_shutdown();
    let code = closed_loop::shutdown(q, sequence)?;
    if exits {
        println!("firmware exited with code {code}");
    } else {
        println!("firmware acknowledged Shutdown (a flight image serves on; its emulator stopped)");
    }
    Ok(code == 0)
}
