//! `cargo xtask run`: the main job. The firmware runs in its board's emulator (QEMU, or
//! rp2040js for the RP2040), its UART on a loopback TCP link to the host simulator, which integrates both vehicles exactly and sends a
//! State every control period; per case it prints the law's matrix at t = 0, the capture time in
//! closed loop with the firmware, the host-only simulation of the same case, frames and counters.

use host_tests::scenarios::EPS;
use host_tests::scenarios::{paper_cases, Case, PAPER_LIMITS};
use host_tests::sim::{SimParams, SimResult, SimStatus};
use twocars::protocol::message::{ROLE_EVADER, ROLE_PURSUER};
use twocars::value_tables::ValueTables;
use twocars::{evaluate_observation, Observation, Policy, Scalar};

use crate::firmware::build::{self, Image};
use crate::firmware::closed_loop;
use crate::firmware::emulator::Emulator;
use crate::firmware::signing::SigningKey;
use crate::host::options::{with_numeric, LawArgs, Options};

/// Largest |firmware - host| capture-time difference accepted, in control periods.
const AGREEMENT_PERIODS: f64 = 3.0;

/// Options of `run`.
#[derive(Debug, Clone)]
struct RunOptions {
    cases: Vec<Case>,
    limits: [f64; 4],
    dt: f64,
    t_max: f64,
    roles: u8,
    host_only: bool,
}

/// Which players the firmware plays (the host law plays the other).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Roles {
    /// Both players.
    Both,
    /// The pursuer only.
    Pursuer,
    /// The evader only.
    Evader,
}

/// `cargo xtask run`'s options.
#[derive(Debug, Clone, clap::Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub law: LawArgs,
    /// A paper case (paper1..paper4) or all; repeatable; default all.
    #[arg(long, value_parser = ["paper1", "paper2", "paper3", "paper4", "all"])]
    case: Vec<String>,
    /// Control period, seconds.
    #[arg(long, default_value_t = 0.01)]
    dt: f64,
    /// Longest run, seconds.
    #[arg(long, default_value_t = 30.0)]
    t_max: f64,
    /// The players the firmware plays; the host's law plays the other.
    #[arg(long, value_enum, default_value = "both")]
    roles: Roles,
    /// Limits v_pm,w_pm,v_em,w_em (m/s, 1/m, m/s, 1/m); default the paper's 2,2,1,1.
    #[arg(long, value_parser = crate::workspace::numbers::<4>)]
    limits: Option<[f64; 4]>,
    /// A custom start: the pursuer's x,y,theta (m, m, rad), with --evader.
    #[arg(long, value_parser = crate::workspace::numbers::<3>, requires = "evader")]
    pursuer: Option<[f64; 3]>,
    /// A custom start: the evader's x,y,theta (m, m, rad), with --pursuer.
    #[arg(long, value_parser = crate::workspace::numbers::<3>, requires = "pursuer")]
    evader: Option<[f64; 3]>,
    /// The host simulation only, no emulator.
    #[arg(long)]
    pub host_only: bool,
    /// The emulated board: an f32 image (mps2-an386, STM32F405), or a fixed-point one (micro:bit,
    /// RP2040; the host then simulates fixed point too, and runs the same unit in this process
    /// to compare bit for bit).
    #[arg(long, value_enum, default_value = "qemu")]
    board: RunBoard,
    /// The firmware's link: our COBS protocol, or MAVLink 2 with pymavlink playing the
    /// autopilot and the target (the paper's cases at ten times their scale; docs/mavlink.md).
    #[arg(long, value_enum, default_value = "cobs")]
    link: RunLink,
    /// With `--link mavlink` or `ardupilot`: build the MAVLink image with this signing key (a
    /// file of 32 bytes or 64 hexadecimal digits), and sign the other
    /// side with it (pymavlink; ArduPilot, given the key with SETUP_SIGNING).
    #[arg(long)]
    signing_key: Option<std::path::PathBuf>,
    /// With `--link ardupilot`, or `px4 --rover-evader`: the `ardurover` SITL binary
    /// (default: TWOCARS_ARDUROVER, then ../shared/ardupilot/ardurover).
    #[arg(long)]
    ardurover: Option<std::path::PathBuf>,
    /// With `--link mavlink`: the target's fixes 200 ms late, 5 a second, with GPS noise of
    /// 0.2 r_p, through the unit's estimator; with `--link ardupilot`: 300 ms late, 5 a
    /// second, 1 m and 5 degrees, wind and GPS noise on the rover (docs/field.md).
    #[arg(long)]
    field: bool,
    /// With `--link ardupilot` or `px4` (rovers): the evader a second ArduPilot Rover SITL
    /// driven by the suite's evaders, its own GLOBAL_POSITION_INT the unit's target
    /// (docs/ardupilot.md, docs/px4.md).
    #[arg(long)]
    rover_evader: bool,
    /// With `--link ardupilot` or `px4`: the unit the `twocars-companion` binary on the host
    /// (over TCP to the router) in place of the QEMU image (docs/companion.md).
    #[arg(long)]
    companion: bool,
    /// With `--link ardupilot` or `px4`: the pursuer a rover or a plane (ArduPlane in GUIDED
    /// under roll setpoints; PX4's SIH airplane in OFFBOARD under the unit's energy hold).
    #[arg(long, value_enum, default_value = "rover")]
    vehicle: RunVehicle,
    /// With `--vehicle plane` (`--link ardupilot` or `px4`): the evader an ArduPlane SITL
    /// (slower, banking less) driven by the suite's evaders, its own GLOBAL_POSITION_INT the
    /// unit's target (docs/ardupilot.md, docs/px4.md).
    #[arg(long)]
    plane_evader: bool,
    /// With `--link ardupilot --vehicle plane`, or `px4 --plane-evader`: the `arduplane` SITL
    /// binary (default: TWOCARS_ARDUPLANE, then ../shared/ardupilot/arduplane).
    #[arg(long)]
    arduplane: Option<std::path::PathBuf>,
    /// With `--vehicle plane`: SITL's speed-up over the wall clock.
    #[arg(long, default_value_t = crate::ardupilot::plane::SPEEDUP)]
    speedup: u32,
    /// With `--link px4`: the `px4` SITL binary, its `etc/` beside `bin/` (default:
    /// ../shared/px4/bin/px4).
    #[arg(long)]
    px4: Option<std::path::PathBuf>,
}

/// The links `run` can fly the firmware over.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RunLink {
    /// The COBS protocol (docs/protocol.md).
    Cobs,
    /// MAVLink 2 (the `twocars-qemu-mavlink` image).
    Mavlink,
    /// MAVLink 2 with ArduPilot Rover SITL flying the pursuer (docs/ardupilot.md).
    Ardupilot,
    /// MAVLink 2 with PX4 SITL (SIH Ackermann rover) flying the pursuer (docs/px4.md).
    Px4,
}

/// The pursuer's vehicle under an autopilot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RunVehicle {
    /// A ground vehicle.
    Rover,
    /// A fixed-wing aircraft.
    Plane,
}

/// The boards `run` can emulate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RunBoard {
    /// QEMU mps2-an386 (Cortex-M4F, f32 law).
    Qemu,
    /// QEMU microbit (nRF51822, Cortex-M0, fixed-point law).
    Microbit,
    /// QEMU mps2-an386 with the value tables in flash: the policy defaults to the
    /// tables' (Configure's policy byte 2), and the host simulation plays the same tables.
    QemuTables,
    /// The STM32F405 flight image in QEMU's netduinoplus2 (Cortex-M4F, f32; USART1).
    Stm32f405,
    /// The Raspberry Pi Pico flight image in rp2040js (RP2040, Cortex-M0+, fixed-point law;
    /// UART0), compared bit for bit with the same unit on the host, as the micro:bit is.
    Rp2040,
}

/// A start below the theorem's threshold at the paper's limits, where the tables play: the
/// evader 1.1 m behind and to the left of the pursuer, turning across its path.
const NEAR_CASE: Case = Case {
    name: "near",
    pursuer: [0.0, 0.0, 0.0],
    evader: [-0.85, 0.75, -0.9],
    expected_value: f64::NAN,
};

fn parse(args: &RunArgs) -> Result<RunOptions, String> {
    let tables = args.board == RunBoard::QemuTables;
    let mut o = RunOptions {
        cases: Vec::new(),
        limits: args.limits.unwrap_or(PAPER_LIMITS),
        dt: args.dt,
        t_max: args.t_max,
        roles: match args.roles {
            Roles::Both => ROLE_PURSUER | ROLE_EVADER,
            Roles::Pursuer => ROLE_PURSUER,
            Roles::Evader => ROLE_EVADER,
        },
        host_only: args.host_only,
    };
    for name in &args.case {
        o.cases.extend(
            paper_cases()
                .into_iter()
                .filter(|c| name == "all" || c.name == name.as_str()),
        );
    }
    if let (Some(p), Some(e)) = (args.pursuer, args.evader) {
        o.cases.push(Case {
            name: "custom",
            pursuer: p,
            evader: e,
            expected_value: f64::NAN,
        });
    }
    if o.cases.is_empty() {
        o.cases.extend(paper_cases());
        if tables {
            o.cases.push(NEAR_CASE);
        }
    }
    if !(o.dt.is_finite() && o.dt > 0.0 && o.t_max.is_finite() && o.t_max > 0.0) {
        return Err("--dt and --t-max must be positive".to_string());
    }
    Ok(o)
}

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
    firmware: &host_tests::sim::SimResult,
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

/// Runs the main job; returns the exit code.
pub fn run(args: &RunArgs) -> i32 {
    if args.link == RunLink::Px4 && args.vehicle == RunVehicle::Plane {
        return crate::px4::plane::run(&crate::px4::plane::Options {
            px4: args.px4.clone(),
            short: false,
            companion: args.companion,
            plane_evader: args.plane_evader,
            arduplane: args.arduplane.clone(),
        });
    }
    if args.link == RunLink::Px4 {
        return crate::px4::run(&crate::px4::Options {
            px4: args.px4.clone(),
            short: false,
            companion: args.companion,
            rover_evader: args.rover_evader,
            ardurover: args.ardurover.clone(),
        });
    }
    let Ok(key) = SigningKey::given(args.signing_key.as_deref(), "xtask run") else {
        return 2;
    };
    if args.link == RunLink::Ardupilot {
        if args.vehicle == RunVehicle::Plane {
            return crate::ardupilot::plane::run(&crate::ardupilot::plane::Options {
                arduplane: args.arduplane.clone(),
                short: false,
                companion: args.companion,
                speedup: args.speedup,
                plane_evader: args.plane_evader,
                key,
            });
        }
        let options = crate::ardupilot::Options {
            ardurover: args.ardurover.clone(),
            short: false,
            field: args.field,
            simulated: !args.rover_evader,
            rover_evader: args.rover_evader,
            companion: args.companion,
            key,
        };
        return crate::ardupilot::run(&options);
    }
    if args.link == RunLink::Mavlink && args.field {
        return match crate::firmware::mavlink_field::run_field(Image::QemuMavlink, key.as_ref()) {
            Ok(true) => 0,
            Ok(false) => 1,
            Err(e) => {
                eprintln!("xtask run --link mavlink --field: {e}");
                1
            }
        };
    }
    if args.link == RunLink::Mavlink {
        return match args.board {
            RunBoard::Qemu => crate::firmware::mavlink::run(Image::QemuMavlink, key.as_ref()),
            RunBoard::Stm32f405 => {
                crate::firmware::mavlink::run(Image::Stm32f405Mavlink, key.as_ref())
            }
            other => {
                eprintln!("xtask run: no MAVLink image for {other:?}");
                2
            }
        };
    }
    let (board, options) = board_and_options(args);
    let options = &options;
    let (o, tables) = match parse(args).and_then(|o| {
        let tables = tables_for(args, options, &o)?;
        Ok((o, tables))
    }) {
        Ok(set_up) => set_up,
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
        match build::build_checked(board, None)
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
        ok &= with_numeric!(options.numeric, S => show_matrix::<S>(&o, case, options));
        let host = host_case(&o, case, options, tables);
        let Some(q) = session.as_mut() else { continue };
        match firmware_case(q, &mut sequence, (&o, case, options), board, &host) {
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

/// The board `args` asks for, and the law's options there: the policy its image plays by
/// default, and the numeric backend of its law, which the host simulates too.
fn board_and_options(args: &RunArgs) -> (Image, Options) {
    let tables_board = args.board == RunBoard::QemuTables;
    let mut options = args.law.options(if tables_board {
        Policy::Table
    } else {
        Policy::Flight
    });
    let board = match args.board {
        RunBoard::Qemu => Image::Qemu,
        RunBoard::Microbit => {
            options.numeric = crate::host::options::Numeric::Fixed;
            Image::Microbit
        }
        RunBoard::QemuTables => {
            // The tables are read in f32.
            options.numeric = crate::host::options::Numeric::F32;
            Image::QemuTables
        }
        RunBoard::Stm32f405 => Image::Stm32f405,
        RunBoard::Rp2040 => {
            options.numeric = crate::host::options::Numeric::Fixed;
            Image::Rp2040
        }
    };
    (board, options)
}

/// The value-table set the image plays at `o`'s limits (the files it was built with), where
/// it plays one.
fn tables_for(
    args: &RunArgs,
    options: &Options,
    o: &RunOptions,
) -> Result<Option<&'static ValueTables<'static>>, String> {
    if args.board == RunBoard::QemuTables && options.policy == Policy::Table {
        crate::firmware::tables::table_set(o.limits, options.variant, o.dt).map(Some)
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
            host_tests::sim::simulate_with_turns::<f32>(
                &params(o, case),
                options.variant,
                options.policy,
                None,
                false,
                [&|_, _| None, &|_, _| None],
                host_tests::sim::Setup {
                    tables: Some(set),
                    ..Default::default()
                },
            )
        }
        None => crate::host::sim::run_one(&params(o, case), options, None, false),
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
