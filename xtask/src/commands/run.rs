//! `cargo xtask run`: its options, and the one call each link and vehicle makes: our serial
//! protocol in an emulator ([`crate::harness::firmware::run`]), MAVLink against pymavlink
//! ([`crate::harness::firmware::mavlink`]), or an autopilot's SITL ([`crate::harness::ardupilot`],
//! [`crate::harness::px4`]).

use twocars::protocol::message::{ROLE_EVADER, ROLE_PURSUER};
use twocars::Policy;
use twocars_sim::scenarios::{paper_cases, Case, PAPER_LIMITS};

use crate::harness::firmware::run::{RunOptions, NEAR_CASE};
use crate::harness::host::{LawArgs, Options};
use crate::image::signing::SigningKey;
use crate::image::Image;

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
    #[arg(long, value_parser = crate::util::workspace::numbers::<4>)]
    limits: Option<[f64; 4]>,
    /// A custom start: the pursuer's x,y,theta (m, m, rad), with --evader.
    #[arg(long, value_parser = crate::util::workspace::numbers::<3>, requires = "evader")]
    pursuer: Option<[f64; 3]>,
    /// A custom start: the evader's x,y,theta (m, m, rad), with --pursuer.
    #[arg(long, value_parser = crate::util::workspace::numbers::<3>, requires = "pursuer")]
    evader: Option<[f64; 3]>,
    /// The host simulation only, no emulator.
    #[arg(long)]
    pub host_only: bool,
    /// The emulated board: an f32 image (mps2-an386, STM32F405), or a fixed-point one (micro:bit,
    /// RP2040; the host then simulates fixed point too, and runs the same unit in this process
    /// to compare bit for bit).
    #[arg(long, value_enum, default_value = "qemu")]
    board: RunBoard,
    /// The firmware's link: our serial protocol (COBS frames), or MAVLink 2 with pymavlink
    /// playing the autopilot and the target (the paper's cases at ten times their scale;
    /// docs/mavlink.md).
    #[arg(long, value_enum, default_value = "serial")]
    link: RunLink,
    /// MAVLink 2 with this autopilot's SITL flying the pursuer (docs/ardupilot.md,
    /// docs/px4.md).
    #[arg(long, value_enum, conflicts_with = "link")]
    autopilot: Option<RunAutopilot>,
    /// With `--board qemu`: the image with the value tables in flash; the policy defaults to
    /// the tables' (Configure's policy byte 2), and the host simulation plays the same tables.
    #[arg(long)]
    tables: bool,
    /// With `--link mavlink` or `--autopilot ardupilot`: build the MAVLink image with this signing key (a
    /// file of 32 bytes or 64 hexadecimal digits), and sign the other
    /// side with it (pymavlink; ArduPilot, given the key with SETUP_SIGNING).
    #[arg(long)]
    signing_key: Option<std::path::PathBuf>,
    /// With `--autopilot ardupilot`, or `--autopilot px4 --rover-evader`: the `ardurover` SITL binary
    /// (default: TWOCARS_ARDUROVER, then ../shared/ardupilot/ardurover).
    #[arg(long)]
    ardurover: Option<std::path::PathBuf>,
    /// With `--link mavlink`: the target's fixes 200 ms late, 5 a second, with GPS noise of
    /// 0.2 r_p, through the unit's estimator; with `--autopilot ardupilot`: 300 ms late, 5 a
    /// second, 1 m and 5 degrees, wind and GPS noise on the rover (docs/field.md); with
    /// `--vehicle plane` 2 a second, and with `--plane-evader` both aircraft in wind.
    #[arg(long)]
    field: bool,
    /// With `--autopilot ardupilot` or `px4` (rovers): the evader a second ArduPilot Rover SITL
    /// driven by the suite's evaders, its own GLOBAL_POSITION_INT the unit's target
    /// (docs/ardupilot.md, docs/px4.md).
    #[arg(long)]
    rover_evader: bool,
    /// With `--autopilot ardupilot`: three rovers, each with its own companion unit in a team,
    /// against a fourth rover flown by the team's evaders, the target's fixes through the
    /// rovers' radio (docs/team.md).
    #[arg(long, conflicts_with_all = ["rover_evader", "signing_key", "field"])]
    team: bool,
    /// With `--autopilot ardupilot` or `px4`: the unit the `twocars-companion` binary on the host
    /// (over TCP to the router) in place of the QEMU image (docs/companion.md).
    #[arg(long)]
    companion: bool,
    /// With `--autopilot ardupilot` or `px4`: the pursuer a rover or a plane (ArduPlane in GUIDED
    /// under roll setpoints; PX4's SIH airplane in OFFBOARD under the unit's energy hold).
    #[arg(long, value_enum, default_value = "rover")]
    vehicle: RunVehicle,
    /// With `--vehicle plane` (`--autopilot ardupilot` or `px4`): the evader an ArduPlane SITL
    /// (slower, banking less) driven by the suite's evaders, its own GLOBAL_POSITION_INT the
    /// unit's target (docs/ardupilot.md, docs/px4.md).
    #[arg(long)]
    plane_evader: bool,
    /// With `--autopilot ardupilot --vehicle plane`, or `--autopilot px4 --plane-evader`: the `arduplane` SITL
    /// binary (default: TWOCARS_ARDUPLANE, then ../shared/ardupilot/arduplane).
    #[arg(long)]
    arduplane: Option<std::path::PathBuf>,
    /// With `--vehicle plane`: SITL's speed-up over the wall clock.
    #[arg(long, default_value_t = crate::harness::ardupilot::plane::SPEEDUP)]
    speedup: u32,
    /// With `--autopilot px4`: the `px4` SITL binary, its `etc/` beside `bin/` (default:
    /// ../shared/px4/bin/px4).
    #[arg(long)]
    px4: Option<std::path::PathBuf>,
}

/// The links `run` can fly the firmware over.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RunLink {
    /// Our serial protocol (docs/protocol.md); `cobs` is an alias.
    #[value(alias = "cobs")]
    Serial,
    /// MAVLink 2 (the `twocars-qemu-mavlink` image).
    Mavlink,
    /// `--autopilot ardupilot`'s former spelling, kept for one release.
    #[value(hide = true)]
    Ardupilot,
    /// `--autopilot px4`'s former spelling, kept for one release.
    #[value(hide = true)]
    Px4,
}

/// The autopilots whose SITL `run` flies the pursuer with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RunAutopilot {
    /// ArduPilot: Rover, or ArduPlane with `--vehicle plane` (docs/ardupilot.md).
    Ardupilot,
    /// PX4 with its SIH simulator: the Ackermann rover, or the airplane with `--vehicle
    /// plane` (docs/px4.md).
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
    /// `--board qemu --tables`' former spelling, kept for one release.
    #[value(hide = true)]
    QemuTables,
    /// The STM32F405 flight image in QEMU's netduinoplus2 (Cortex-M4F, f32; USART1).
    Stm32f405,
    /// The Raspberry Pi Pico flight image in rp2040js (RP2040, Cortex-M0+, fixed-point law;
    /// UART0), compared bit for bit with the same unit on the host, as the micro:bit is.
    Rp2040,
}

/// Runs the main job; returns the exit code.
pub fn run(args: &RunArgs) -> i32 {
    if args.tables && !matches!(args.board, RunBoard::Qemu | RunBoard::QemuTables) {
        eprintln!(
            "xtask run: --tables: the image that plays value tables is QEMU's (--board qemu)"
        );
        return 2;
    }
    if args.team && args.autopilot() != Some(RunAutopilot::Ardupilot) {
        eprintln!("xtask run: --team flies ArduPilot Rover SITL: give --autopilot ardupilot");
        return 2;
    }
    if args.autopilot() == Some(RunAutopilot::Px4) {
        return px4(args);
    }
    let Ok(key) = SigningKey::given(args.signing_key.as_deref(), "xtask run") else {
        return 2;
    };
    if args.autopilot() == Some(RunAutopilot::Ardupilot) {
        return ardupilot(args, key);
    }
    match args.link {
        RunLink::Mavlink => mavlink(args, key.as_ref()),
        _ => {
            let (board, options) = board_and_options(args);
            match parse(args) {
                Ok(o) => crate::harness::firmware::run::fly(board, &options, &o),
                Err(e) => {
                    eprintln!("xtask run: {e}");
                    2
                }
            }
        }
    }
}

/// `--autopilot px4`: the rover or the airplane. The PX4 build here has no message signing
/// (docs/px4.md, "Signing"): a key is refused, not dropped.
fn px4(args: &RunArgs) -> i32 {
    if args.signing_key.is_some() {
        eprintln!(
            "xtask run: --signing-key with --autopilot px4: this PX4 build cannot sign (no MAV_SIGN_CFG; docs/px4.md)"
        );
        return 2;
    }
    if args.vehicle == RunVehicle::Plane {
        return crate::harness::px4::plane::run(&crate::harness::px4::plane::Options {
            px4: args.px4.clone(),
            short: false,
            companion: args.companion,
            plane_evader: args.plane_evader,
            arduplane: args.arduplane.clone(),
        });
    }
    crate::harness::px4::run(&crate::harness::px4::Options {
        px4: args.px4.clone(),
        short: false,
        companion: args.companion,
        rover_evader: args.rover_evader,
        ardurover: args.ardurover.clone(),
    })
}

/// `--autopilot ardupilot`: the rover or the plane, signed with `key` where given.
fn ardupilot(args: &RunArgs, key: Option<SigningKey>) -> i32 {
    if args.team {
        return crate::harness::ardupilot::team::run(&crate::harness::ardupilot::team::Options {
            ardurover: args.ardurover.clone(),
            short: false,
        });
    }
    if args.vehicle == RunVehicle::Plane {
        return crate::harness::ardupilot::plane::run(&crate::harness::ardupilot::plane::Options {
            arduplane: args.arduplane.clone(),
            short: false,
            companion: args.companion,
            speedup: args.speedup,
            plane_evader: args.plane_evader,
            field: args.field,
            key,
        });
    }
    crate::harness::ardupilot::run(&crate::harness::ardupilot::Options {
        ardurover: args.ardurover.clone(),
        short: false,
        field: args.field,
        simulated: !args.rover_evader,
        rover_evader: args.rover_evader,
        companion: args.companion,
        key,
    })
}

/// `--link mavlink`: the paper's cases, or the field's chases, against pymavlink.
fn mavlink(args: &RunArgs, key: Option<&SigningKey>) -> i32 {
    if args.field {
        return match crate::harness::firmware::mavlink_field::run_field(Image::QemuMavlink, key) {
            Ok(true) => 0,
            Ok(false) => 1,
            Err(e) => {
                eprintln!("xtask run --link mavlink --field: {e}");
                1
            }
        };
    }
    match args.board() {
        RunBoard::Qemu => crate::harness::firmware::mavlink::run(Image::QemuMavlink, key),
        RunBoard::Stm32f405 => crate::harness::firmware::mavlink::run(Image::Stm32f405Mavlink, key),
        other => {
            eprintln!("xtask run: no MAVLink image for {other:?}");
            2
        }
    }
}

fn parse(args: &RunArgs) -> Result<RunOptions, String> {
    let tables = args.board() == RunBoard::QemuTables;
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

impl RunArgs {
    /// The Rust target of the image this run builds (a MAVLink link's image is the same
    /// core's).
    pub fn target(&self) -> &'static str {
        board_and_options(self).0.target()
    }

    /// The autopilot flying the pursuer, if one does (`--autopilot`, or `--link`'s former
    /// spelling).
    fn autopilot(&self) -> Option<RunAutopilot> {
        self.autopilot.or(match self.link {
            RunLink::Ardupilot => Some(RunAutopilot::Ardupilot),
            RunLink::Px4 => Some(RunAutopilot::Px4),
            RunLink::Serial | RunLink::Mavlink => None,
        })
    }

    /// The board, `--tables` read: QEMU's tables image where asked for.
    fn board(&self) -> RunBoard {
        match (self.board, self.tables) {
            (RunBoard::Qemu, true) => RunBoard::QemuTables,
            (board, _) => board,
        }
    }
}

/// The board `args` asks for, and the law's options there: the policy its image plays by
/// default, and the numeric backend of its law, which the host simulates too.
fn board_and_options(args: &RunArgs) -> (Image, Options) {
    let tables_board = args.board() == RunBoard::QemuTables;
    let mut options = args.law.options(if tables_board {
        Policy::Table
    } else {
        Policy::Flight
    });
    let board = match args.board() {
        RunBoard::Qemu => Image::Qemu,
        RunBoard::Microbit => {
            options.numeric = crate::harness::host::Numeric::Fixed;
            Image::Microbit
        }
        RunBoard::QemuTables => {
            // The tables are read in f32.
            options.numeric = crate::harness::host::Numeric::F32;
            Image::QemuTables
        }
        RunBoard::Stm32f405 => Image::Stm32f405,
        RunBoard::Rp2040 => {
            options.numeric = crate::harness::host::Numeric::Fixed;
            Image::Rp2040
        }
    };
    (board, options)
}
