//! The game's value tables as a policy, on the host: from a start inside the theorem's
//! threshold, where the paper's law is not proven optimal, one chase with the pursuer playing
//! the tables (`Policy::Table`) and one with the flight policy, the evader the law's in both.
//! The tables' value is the capture time when both play the game's best; the law's evader does
//! not, so each chase ends before it.
//! The tables (`examples/tables/paper-near-field.bin`, 83 kB) are two nested 41 x 41 x 24 grids,
//! +-30 and +-4 turning radii, of the paper's limits, solved by the workspace's `hji` crate
//! (`cargo xtask hj --set FILE --levels 41:30:24,41:4:24`); a firmware carries finer ones in
//! flash (feature `tables-in-flash`).
//!
//! ```sh
//! cargo run --example table_policy --features value-tables
//! ```

use twocars::value_tables::ValueTables;
use twocars::{Guidance, Law, Limits, Policy, Variant};

/// The tables, as a firmware keeps them in flash.
static TABLES: &[u8] = include_bytes!("tables/paper-near-field.bin");
/// The paper's limits: v_pm, w_pm, v_em, w_em (m/s, 1/m); the pursuer's radius r_p = 0.5 m.
const LIMITS: [f32; 4] = [2.0, 2.0, 1.0, 1.0];
/// Control period, s.
const DT: f32 = 0.01;
/// Capture radius, m: one r_p, the radius the tables are solved for.
const CAPTURE: f32 = 0.5;

/// (x, y, theta) after `DT` at speed `v` (m/s) and curvature `w` (1/m).
fn advance([x, y, theta]: [f32; 3], v: f32, w: f32) -> [f32; 3] {
    if w == 0.0 {
        return [x + v * DT * theta.cos(), y + v * DT * theta.sin(), theta];
    }
    let turned = theta + v * w * DT;
    let x1 = x + (turned.sin() - theta.sin()) / w;
    let y1 = y + (theta.cos() - turned.cos()) / w;
    [x1, y1, turned]
}

/// The start: the pursuer at the origin heading north (x east, y north, theta anticlockwise
/// from x), the evader 1 m behind it and 1.5 m to its left, heading west.
const START: ([f32; 3], [f32; 3]) = (
    [0.0, 0.0, core::f32::consts::FRAC_PI_2],
    [-1.5, -1.0, core::f32::consts::PI],
);

/// The evader in the pursuer's frame, in units of `r_p` (ahead, left) and its heading relative
/// to the pursuer's: where the tables are read.
fn relative([xp, yp, tp]: [f32; 3], [xe, ye, te]: [f32; 3], r_p: f32) -> (f32, f32, f32) {
    let (dx, dy, (s, c)) = (xe - xp, ye - yp, tp.sin_cos());
    let phi = (te - tp + core::f32::consts::PI).rem_euclid(core::f32::consts::TAU);
    (
        (dx * c + dy * s) / r_p,
        (dy * c - dx * s) / r_p,
        phi - core::f32::consts::PI,
    )
}

/// The time `pursuer` takes to come within [`CAPTURE`] of the evader from [`START`], the
/// evader steered by `evader`; `None` within 30 s.
fn chase(
    limits: &Limits<f32>,
    pursuer: &mut Guidance<f32>,
    evader: &mut Guidance<f32>,
) -> Option<f32> {
    let (mut p, mut e) = START;
    for k in 0..3_000 {
        if (p[0] - e[0]).hypot(p[1] - e[1]) <= CAPTURE {
            return Some(k as f32 * DT);
        }
        let (sp, se) = limits.states(p, e).ok()?;
        let w_p = pursuer.decide(&sp, &se).command.pursuer;
        let w_e = evader.decide(&sp, &se).command.evader;
        p = advance(p, LIMITS[0], w_p);
        e = advance(e, LIMITS[2], w_e);
    }
    None
}

fn main() -> Result<(), twocars::Error> {
    // `with_tables` keeps a reference for the guidance's life: a firmware's tables are a
    // static in flash; here the parsed header is leaked once.
    let tables = ValueTables::parse(TABLES).map_err(|_| twocars::Error::TablesMismatch)?;
    let tables: &'static ValueTables<'static> = Box::leak(Box::new(tables));
    let [v_pm, w_pm, v_em, w_em] = LIMITS;
    let limits = Limits::<f32>::new(v_pm, w_pm, v_em, w_em)?;
    let guidance = |policy| -> Result<Guidance<f32>, twocars::Error> {
        Guidance::new(Law::new(limits, Variant::Paper), DT, policy)?
            .with_capture_radius(CAPTURE)?
            .with_tables(tables)
    };
    let r_p = 1.0 / w_pm;
    let (x, y, phi) = relative(START.0, START.1, r_p);
    if let Some(v) = tables.value(x, y, phi) {
        // V is in units of r_p / v_pm.
        println!("the tables' value at the start: {:.2} s", v * r_p / v_pm);
    }
    for (name, policy) in [("the tables", Policy::Table), ("flight", Policy::Flight)] {
        match chase(
            &limits,
            &mut guidance(policy)?,
            &mut guidance(Policy::Paper)?,
        ) {
            Some(t) => println!("{name}: captured within {CAPTURE} m at {t:.2} s"),
            None => println!("{name}: not captured within 30 s"),
        }
    }
    Ok(())
}
