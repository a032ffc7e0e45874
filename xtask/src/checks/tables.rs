//! The value tables in flash, tested in QEMU (part of `cargo xtask test`): the
//! `qemu-tables` image carries a set per pair of ratios ([`crate::image::tables::sets::FLASH_SETS`]); its
//! Configure selects the set of the limits' ratios and says so; and below the theorem's
//! threshold it captures every evader of the adversary suite, and the tables' own evader, as
//! the same unit on the host does, within the bar over V(x0) ([`BAR`]).

use hji::policy::relative;
use twocars::protocol::message::{Configure, ROLE_EVADER, ROLE_PURSUER};
use twocars::value_tables::ValueTables;
use twocars_sim::adversary::EvaderKind;
use twocars_sim::link::{self, Reply};
use twocars_sim::rng::Rng;
use twocars_sim::session::paper_configure;
use twocars_sim::sim::{theorem_threshold, SimParams, SimStatus};

use crate::harness::firmware::tables::{image_sets, table_set};
use twocars::{Policy, Variant};

use crate::harness::firmware::closed_loop::{self, HostUnit};
use crate::harness::firmware::emulator::Emulator;
use crate::image::{self, Image};

/// Control period, s.
const DT: f64 = 0.01;

/// Seeded starts per evader and pair of ratios.
const STARTS: usize = 2;

/// The bar on (capture - V(x0) - 5 dt) / V(x0): at the 90th percentile, and at worst.
const BAR: (f64, f64) = (0.05, 0.10);

/// The Configure's policy byte in effect for `limits` asked with `policy`.
fn ack(
    q: &mut Emulator,
    sequence: u16,
    limits: [f32; 4],
    policy: u8,
) -> Result<Option<u8>, String> {
    let configure = Configure {
        limits,
        policy,
        ..paper_configure()
    };
    q.send(&link::configure(sequence, &configure))?;
    match q.reply()? {
        Reply::ConfigureAck(s, p) if s == sequence => Ok(p),
        other => Err(format!(
            "expected the ConfigureAck {sequence}, got {other:?}"
        )),
    }
}

/// Policy byte 2 selects the set of either pair of ratios (ack 2); limits of other ratios fall
/// back to the flight policy (ack 1).
fn configure_selects_each_set(elf: &std::path::Path) -> Result<String, String> {
    let mut q = Emulator::start(elf, Image::QemuTables, false)?;
    let mut got = Vec::new();
    let other = [2.0, 2.0, 1.2, 1.0];
    let cases = crate::image::tables::sets::FLASH_SETS
        .iter()
        .map(|set| (set.limits.map(|v| v as f32), 2))
        .chain([(other, 1)]);
    for (k, (limits, want)) in cases.enumerate() {
        let policy = ack(&mut q, k as u16 + 1, limits, 2)?;
        if policy != Some(want) {
            return Err(format!(
                "limits {limits:?}: ack {policy:?}, expected {want}"
            ));
        }
        got.push(format!("{limits:?} -> {want}"));
    }
    let mut sequence = 100;
    closed_loop::shutdown(q, &mut sequence)?;
    Ok(format!("policy 2 asked: {}", got.join(", ")))
}

/// `STARTS` seeded starts below the threshold of `limits` (m, rad; the pursuer at the origin)
/// where the tables play, with V(x0) (s) read from `set`.
fn starts(limits: [f64; 4], set: &ValueTables<'_>, seed: u64) -> Vec<(SimParams, f64)> {
    let [v_pm, w_pm, ..] = limits;
    let threshold = theorem_threshold(limits);
    let pi = std::f64::consts::PI;
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    while out.len() < STARTS {
        let d0 = rng.uniform(0.05, 1.0) * threshold;
        let bearing = rng.uniform(-pi, pi);
        let pursuer = [0.0, 0.0, rng.uniform(-pi, pi)];
        let evader = [d0 * bearing.cos(), d0 * bearing.sin(), rng.uniform(-pi, pi)];
        let (x, y, phi) = relative(w_pm, pursuer, evader);
        if let Some(v) = set.value(x as f32, y as f32, phi as f32) {
            let v0 = f64::from(v) / (w_pm * v_pm);
            let params = SimParams {
                limits,
                pursuer,
                evader,
                dt: DT,
                t_max: 3.0 * v0 + 30.0,
                // The tables' capture radius: one r_p.
                eps: 1.0 / w_pm,
            };
            out.push((params, v0));
        }
    }
    out
}

/// Below the threshold of each pair of ratios, the firmware's pursuer (policy 2) against every
/// evader of the suite and against its own tables' evader: every run captured, at the capture
/// time the same unit on the host reaches on the same frames (within a period), and over
/// V(x0) within the bar.
fn suite_below_the_threshold(elf: &std::path::Path) -> Result<String, String> {
    let sets = image_sets()?;
    let mut q = Emulator::start(elf, Image::QemuTables, false)?;
    let mut twin = HostUnit::<f32>::with_tables(sets);
    let (mut sequence, mut twin_sequence) = (0, 0);
    let mut over = Vec::new();
    let mut largest_diff = 0.0_f64;
    let evaders = EvaderKind::ALL.map(Some).into_iter().chain([None]);
    for (limits, set) in crate::image::tables::sets::FLASH_SETS
        .iter()
        .map(|s| &s.limits)
        .zip(sets)
    {
        for (k, evader) in evaders.clone().enumerate() {
            // The tables' own evader: the firmware plays both players.
            let roles = match evader {
                Some(_) => ROLE_PURSUER,
                None => ROLE_PURSUER | ROLE_EVADER,
            };
            for (run, (params, v0)) in starts(*limits, set, 30 + k as u64).iter().enumerate() {
                let opponent = evader.map(|kind| (kind, run as u64 + 1));
                let how = (Variant::Paper, Policy::Table);
                let fw =
                    closed_loop::run_against(&mut q, &mut sequence, params, roles, how, opponent)?;
                let host = closed_loop::run_against(
                    &mut twin,
                    &mut twin_sequence,
                    params,
                    roles,
                    how,
                    opponent,
                )?;
                let name = evader.map_or("the tables' evader", EvaderKind::name);
                let diff = (fw.result.t_capture - host.result.t_capture).abs();
                if fw.result.status != SimStatus::Captured
                    || host.result.status != fw.result.status
                    || diff > DT
                    || fw.errors_received > 0
                {
                    return Err(format!(
                        "limits {limits:?}, {name}, start {:?} {:?}: firmware {:?}, host {:?}",
                        params.pursuer, params.evader, fw.result, host.result
                    ));
                }
                largest_diff = largest_diff.max(diff);
                over.push(((fw.result.t_capture - v0 - 5.0 * DT) / v0, name, *limits));
            }
        }
    }
    closed_loop::shutdown(q, &mut sequence)?;
    over.sort_by(|a, b| a.0.total_cmp(&b.0));
    let p90 = over[(over.len() - 1) * 9 / 10].0;
    let (worst, name, limits) = over[over.len() - 1];
    let summary = format!(
        "{} runs captured, firmware - host at most {largest_diff:.1e} s; over V(x0) p90 {:+.1} %, worst {:+.1} % ({name}, limits {limits:?})",
        over.len(),
        100.0 * p90,
        100.0 * worst
    );
    if p90 > BAR.0 || worst > BAR.1 {
        return Err(format!("over the bar: {summary}"));
    }
    Ok(summary)
}

/// `cargo xtask run --board qemu --tables` plays the set of the limits' ratios on the host, and
/// refuses, saying which ratios the image carries, limits of other ratios.
fn run_picks_the_set_of_the_limits_ratios() -> Result<String, String> {
    let ratios = |limits: [f64; 4]| {
        let [v_pm, w_pm, v_em, w_em] = limits.map(|v| v as f32);
        (v_em / v_pm, (v_em / v_pm) * (w_em / w_pm))
    };
    for set in &crate::image::tables::sets::FLASH_SETS {
        let picked = table_set(set.limits, Variant::Paper, DT)?;
        let table = picked.finest_table().ok_or("a set without tables")?;
        let (speed_ratio, evader_turn) = ratios(set.limits);
        if (table.speed_ratio - speed_ratio).abs() > 1e-6
            || (table.evader_turn - evader_turn).abs() > 1e-6
        {
            return Err(format!(
                "{:?}: picked the set of {} and {}",
                set.limits, table.speed_ratio, table.evader_turn
            ));
        }
    }
    match table_set([2.0, 2.0, 1.2, 1.0], Variant::Paper, DT) {
        Ok(_) => Err("2, 2, 1.2, 1.0: a set was picked; none has its ratios".to_string()),
        Err(e) if e.contains("[2.0, 2.0, 1.0, 1.0]") && e.contains("[2.0, 2.0, 1.2, 1.2]") => Ok(
            format!("each set's limits pick it; 2, 2, 1.2, 1.0: \"{e}\""),
        ),
        Err(e) => Err(format!("the refusal does not name the carried ratios: {e}")),
    }
}

/// Runs the tables image's tests with `record`.
pub fn run(record: &mut impl FnMut(&str, Result<String, String>)) {
    println!("== xtask test: the value tables in flash, in QEMU (mps2-an386)");
    let elf = match image::build_checked(Image::QemuTables, None) {
        Ok((elf, _)) => elf,
        Err(e) => {
            record("qemu::tables_image_builds", Err(e));
            return;
        }
    };
    record(
        "qemu::tables_image_configure_selects_the_set_of_the_limits_ratios",
        configure_selects_each_set(&elf),
    );
    record(
        "qemu::tables_image_captures_the_suite_below_the_threshold_as_its_host_twin",
        suite_below_the_threshold(&elf),
    );
    record(
        "qemu::run_on_the_tables_image_picks_the_set_of_the_limits_ratios",
        run_picks_the_set_of_the_limits_ratios(),
    );
}
