//! An independent f64 derivation of the law, written from the paper's figures rather than from
//! the core's closed form: enumerate all common tangents of a circle pair, keep the directed one
//! that passes Algorithm 1's test (tangent at +-pi/2 from both radii), measure the arcs from the
//! vehicle's radius vector to the tangent point's, then Algorithm 2 and Table 1.
//!
//! It shares no code with `twocars` and is only for tests and reports.

use std::f64::consts::TAU;

/// One vehicle's limits and state: m/s, 1/m, metres, radians.
#[derive(Clone, Copy, Debug)]
pub struct RefVehicle {
    /// Maximum speed, m/s.
    pub v: f64,
    /// Maximum curvature, 1/m.
    pub w: f64,
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// Heading, radians.
    pub theta: f64,
}

/// The reference's answer for one pair.
#[derive(Clone, Copy, Debug)]
pub struct RefEntry {
    /// Time to capture (paper variant), seconds.
    pub value: f64,
    /// Tangent points on the pursuer's and evader's circles.
    pub tp: (f64, f64),
    /// See `tp`.
    pub te: (f64, f64),
    /// Heading angles to go, radians.
    pub alpha_p: f64,
    /// See `alpha_p`.
    pub alpha_e: f64,
    /// Tangent length, metres.
    pub length: f64,
}

/// The reference's matrix game: entries `[pursuer][evader]` in (A, C) order, `None` = infinity.
#[derive(Clone, Copy, Debug)]
pub struct RefGame {
    /// Table 1.
    pub m: [[Option<RefEntry>; 2]; 2],
    /// min over rows of max over columns (infinity as f64::INFINITY).
    pub upper: f64,
    /// max over columns of min over rows.
    pub lower: f64,
}

fn centre(v: &RefVehicle, sigma: f64) -> (f64, f64) {
    let r = 1.0 / v.w;
    (
        v.x - sigma * r * v.theta.sin(),
        v.y + sigma * r * v.theta.cos(),
    )
}

/// Each pair's L^2 = |D|^2 - k^2 (square metres) and |D| (metres), `[pursuer circle][evader
/// circle]` in (A, C) order: D joins the circles' centres, k = sigma_e r_e - sigma_p r_p. A
/// pair's directed tangent exists where L^2 >= 0 (and |D| > 0).
pub fn pair_terms(p: &RefVehicle, e: &RefVehicle) -> [[(f64, f64); 2]; 2] {
    let sigma = [1.0, -1.0];
    sigma.map(|sp| {
        sigma.map(|se| {
            let (op, oe) = (centre(p, sp), centre(e, se));
            let d = (oe.0 - op.0).hypot(oe.1 - op.1);
            let k = se / e.w - sp / p.w;
            (d * d - k * k, d)
        })
    })
}

fn valid_tangent(
    op: (f64, f64),
    rp: f64,
    sp: f64,
    oe: (f64, f64),
    re: f64,
    se: f64,
) -> Option<((f64, f64), (f64, f64))> {
    let d = (oe.0 - op.0, oe.1 - op.1);
    let d2 = d.0 * d.0 + d.1 * d.1;
    let perp = (-d.1, d.0);
    for e1 in [1.0, -1.0] {
        for e2 in [1.0, -1.0] {
            let q = e2 * re - e1 * rp;
            let disc = d2 - q * q;
            if disc < 0.0 || d2 == 0.0 {
                continue;
            }
            for s in [1.0, -1.0] {
                let h = s * disc.sqrt();
                let n = ((q * d.0 + h * perp.0) / d2, (q * d.1 + h * perp.1) / d2);
                let t1 = (op.0 - e1 * rp * n.0, op.1 - e1 * rp * n.1);
                let t2 = (oe.0 - e2 * re * n.0, oe.1 - e2 * re * n.1);
                let len = ((t2.0 - t1.0).powi(2) + (t2.1 - t1.1).powi(2)).sqrt();
                if len < 1e-12 {
                    continue;
                }
                let u = ((t2.0 - t1.0) / len, (t2.1 - t1.1) / len);
                // Algorithm 1: the tangent is the radius turned by +pi/2 (A) or -pi/2 (C).
                let ok = |o: (f64, f64), t: (f64, f64), r: f64, sigma: f64| {
                    let radial = ((t.0 - o.0) / r, (t.1 - o.1) / r);
                    let want = (-sigma * radial.1, sigma * radial.0);
                    want.0 * u.0 + want.1 * u.1 > 1.0 - 1e-9
                };
                if ok(op, t1, rp, sp) && ok(oe, t2, re, se) {
                    return Some((t1, t2));
                }
            }
        }
    }
    None
}

fn arc(o: (f64, f64), from: (f64, f64), to: (f64, f64), sigma: f64) -> f64 {
    let a0 = (from.1 - o.1).atan2(from.0 - o.0);
    let a1 = (to.1 - o.1).atan2(to.0 - o.0);
    (sigma * (a1 - a0)).rem_euclid(TAU)
}

/// Evaluates Table 1 for the paper's variant of Algorithm 2.
pub fn game(p: &RefVehicle, e: &RefVehicle) -> RefGame {
    let (rp, re) = (1.0 / p.w, 1.0 / e.w);
    let entry = |sp: f64, se: f64| -> Option<RefEntry> {
        let op = centre(p, sp);
        let oe = centre(e, se);
        let (tp, te) = valid_tangent(op, rp, sp, oe, re, se)?;
        let alpha_p = arc(op, (p.x, p.y), tp, sp);
        let alpha_e = arc(oe, (e.x, e.y), te, se);
        let length = ((te.0 - tp.0).powi(2) + (te.1 - tp.1).powi(2)).sqrt();
        let t_p = rp * alpha_p / p.v;
        let t_e = re * alpha_e / e.v;
        let value = if t_p > t_e {
            t_p + (length + e.v * (t_p - t_e)) / (p.v - e.v)
        } else {
            t_e + (length - p.v * (t_e - t_p)) / (p.v - e.v)
        };
        Some(RefEntry {
            value,
            tp,
            te,
            alpha_p,
            alpha_e,
            length,
        })
    };
    let m = [
        [entry(1.0, 1.0), entry(1.0, -1.0)],
        [entry(-1.0, 1.0), entry(-1.0, -1.0)],
    ];
    let v = |i: usize, j: usize| m[i][j].map_or(f64::INFINITY, |x| x.value);
    let upper = v(0, 0).max(v(0, 1)).min(v(1, 0).max(v(1, 1)));
    let lower = v(0, 0).min(v(1, 0)).max(v(0, 1).min(v(1, 1)));
    RefGame { m, upper, lower }
}
