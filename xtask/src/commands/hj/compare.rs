//! `cargo xtask hj --compare`: our solver beside hj_reachability (WENO5 in space, TVD-RK3 in
//! time, JAX on the CPU), the peer its field reaches for first, on the same game and grid. The
//! peer runs in `xtask/hj_peer.py` from a virtual environment of pinned versions; it reads our
//! values from a file and prints both solvers' figures: time and peak memory, the tail chase
//! against its exact value, the agreement where V is smooth, the width of V's jumps on rays
//! across its barriers, and how far V falls below r - eps, which an evader that stands still
//! forces. Both solutions stay in `target/hj-compare/` (f64, phi slowest and x
//! fastest, as `hji` lays them out; the peer's infinite where it does not capture).

use std::path::PathBuf;
use std::process::Command;

use hji::{Game, Grid, Sweeps};

use crate::image::tables::solve::{solve_grid, Boundary};

/// The peer's versions, pinned: hj_reachability and the JAX it was measured with.
const PEER: [&str; 3] = ["hj_reachability==0.7.0", "jax==0.10.2", "jaxlib==0.10.2"];

/// The peer's horizon, r_p / v_pm: times to capture beyond it are not compared.
const HORIZON: f64 = 20.0;

/// What the peer printed, in the order of its table.
#[derive(serde::Deserialize)]
struct Compared {
    grid: String,
    jax: String,
    ours: Side,
    peer: Side,
    smooth_nodes: usize,
    smooth_median: Option<f64>,
    smooth_p90: Option<f64>,
    reached_both: usize,
    reached_only_ours: usize,
    reached_only_peer: usize,
    rays: usize,
    width_p50: [Option<f64>; 2],
    width_p90: [Option<f64>; 2],
}

/// One solver's cost, tail chase, and how far its V falls below r - eps (least, and the share
/// of nodes more than a thousandth below).
#[derive(serde::Deserialize)]
struct Side {
    seconds: f64,
    peak_mb: f64,
    tail_chase: Vec<f64>,
    below_stop: (f64, f64),
}

/// Solves `game` on `grid` with ours and with the peer and prints the comparison; the exit
/// code.
pub fn command(game: Game, grid: Grid, sweeps: Sweeps) -> i32 {
    match compare(game, grid, sweeps) {
        Ok(c) => {
            print(&c);
            0
        }
        Err(e) => {
            eprintln!("xtask hj --compare: {e}");
            1
        }
    }
}

fn compare(game: Game, grid: Grid, sweeps: Sweeps) -> Result<Compared, String> {
    let python = crate::util::setup::venv("hj-peer-venv", &PEER, "import hj_reachability, jax")?;
    let (ours, seconds) = solve_grid(game, grid, sweeps, Boundary::Never);
    let peak_mb = peak_resident_mb()?;
    let dir = crate::util::workspace::target_dir().join("hj-compare");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let file = dir.join(format!("ours-{}x{}.f64", grid.n, grid.headings));
    let bytes: Vec<u8> = ours.values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(&file, bytes).map_err(|e| format!("{}: {e}", file.display()))?;
    eprintln!("xtask: hj_reachability on the same grid (minutes; JAX on the CPU)");
    let output = Command::new(python)
        .arg(peer_script())
        .args(["--nodes", &grid.n.to_string()])
        .args(["--headings", &grid.headings.to_string()])
        .args(["--half", &grid.half.to_string()])
        .args(["--eps", &game.eps.to_string()])
        .args(["--speed-ratio", &game.speed_ratio.to_string()])
        .args(["--evader-turn", &game.evader_turn.to_string()])
        .args(["--horizon", &HORIZON.to_string()])
        .args(["--ours-seconds", &seconds.to_string()])
        .args(["--ours-peak-mb", &peak_mb.to_string()])
        .arg("--ours")
        .arg(&file)
        .arg("--peer-out")
        .arg(dir.join(format!("peer-{}x{}.f64", grid.n, grid.headings)))
        .env("JAX_PLATFORMS", "cpu")
        .output()
        .map_err(|e| format!("the peer did not start: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "the peer failed: {}",
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    serde_json::from_slice(&output.stdout).map_err(|e| format!("the peer's answer: {e}"))
}

fn peer_script() -> PathBuf {
    crate::util::workspace::root().join("xtask/hj_peer.py")
}

/// This process's peak resident memory (VmHWM), MB: an upper bound of the solve's, since
/// xtask holds little else.
fn peak_resident_mb() -> Result<f64, String> {
    let status = std::fs::read_to_string("/proc/self/status").map_err(|e| e.to_string())?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map(|kb| kb / 1024.0)
        .ok_or_else(|| "no VmHWM in /proc/self/status".to_string())
}

fn print(c: &Compared) {
    let cells = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
    let tail = |s: &Side| {
        s.tail_chase
            .iter()
            .map(|e| format!("{e:+.4}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    println!(
        "# {}: ours beside hj_reachability 0.7.0 (JAX {}, CPU, {} threads)\n",
        c.grid,
        c.jax,
        rayon::current_num_threads()
    );
    println!("| solver | time (s) | peak memory (MB) | tail chase at d = 1, 2, 3, 4 r_p (r_p / v_pm) | V's jumps, 10-90 % rise p50 / p90 (cells) |");
    println!("|---|---|---|---|---|");
    for (name, side, i) in [("ours", &c.ours, 0), ("hj_reachability", &c.peer, 1)] {
        println!(
            "| {name} | {:.1} | {:.0} | {} | {} / {} |",
            side.seconds,
            side.peak_mb,
            tail(side),
            cells(c.width_p50[i]),
            cells(c.width_p90[i]),
        );
    }
    println!(
        "\nWhere V is smooth in both ({} nodes: every change to a neighbour within two cells below 1 r_p / v_pm): |ours - peer| median {} and p90 {} r_p / v_pm.",
        c.smooth_nodes,
        c.smooth_median.map_or("-".to_string(), |v| format!("{v:.4}")),
        c.smooth_p90.map_or("-".to_string(), |v| format!("{v:.4}")),
    );
    println!(
        "V - (r - eps), at least 0 since the evader may stand still: least {:+.4} (ours) and {:+.4} (peer); nodes below -0.001: {:.2} % and {:.2} %.",
        c.ours.below_stop.0,
        c.peer.below_stop.0,
        100.0 * c.ours.below_stop.1,
        100.0 * c.peer.below_stop.1,
    );
    println!(
        "Captured within {HORIZON} r_p / v_pm: {} nodes by both, {} by ours alone, {} by the peer alone; {} rays across V's barriers (their ends at least 2 r_p / v_pm apart in both).",
        c.reached_both, c.reached_only_ours, c.reached_only_peer, c.rays
    );
}
