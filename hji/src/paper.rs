//! The paper's upper value in the Hamilton-Jacobi-Isaacs solver's reduced units (r_p = 1,
//! v_pm = 1), and the comparison the theorem asks for: beyond its threshold, wherever the
//! paper's law has a saddle, the game's value V is the paper's upper value.

use crate::Game;

/// The paper's law for a game of the solver, in its units.
#[derive(Clone, Copy)]
pub struct PaperValue {
    law: twocars::Law<f64>,
    /// The theorem's threshold distance, r_p.
    pub threshold: f64,
    /// The capture radius's closing time eps / (1 - a): the law's capture is a point's.
    eps_closing: f64,
}

impl PaperValue {
    /// The paper's law for `game`; `None` for limits the law refuses.
    pub fn of(game: Game) -> Option<Self> {
        let a = game.speed_ratio;
        // r_e = a / (the evader's turn rate per unit time), in r_p.
        let r_e = a / game.evader_turn;
        let limits = twocars::Limits::<f64>::new(1.0, 1.0, a as f32, (1.0 / r_e) as f32).ok()?;
        Some(PaperValue {
            law: twocars::Law::new(limits, twocars::Variant::Paper),
            threshold: game.threshold(),
            eps_closing: game.eps / (1.0 - a),
        })
    }

    /// The upper value (r_p / v_pm) of the evader at `(x, y, phi)` in the pursuer's frame, less
    /// the capture radius's closing time, where the players are beyond the threshold and the
    /// law has a saddle.
    pub fn beyond_threshold(&self, x: f64, y: f64, phi: f64) -> Option<f64> {
        if x.hypot(y) < self.threshold {
            return None;
        }
        let (p, e) = (self.law.limits)
            .states([0.0; 3], [x as f32, y as f32, phi as f32])
            .ok()?;
        let s = self.law.evaluate(&p, &e).report?.solution;
        let (upper, lower) = (s.upper?, s.lower?);
        ((upper - lower).abs() <= 1e-9 * upper).then_some(upper - self.eps_closing)
    }

    /// Over `states` (x, y in r_p, phi in radians): for each beyond the threshold where the law
    /// has a saddle, V from `value` (`None`: the table has none) less the paper's value, with
    /// that value; and how many had no V.
    pub fn gaps(
        &self,
        states: impl IntoIterator<Item = (f64, f64, f64)>,
        value: impl Fn(f64, f64, f64) -> Option<f64>,
    ) -> (Vec<(f64, f64)>, usize) {
        let (mut gaps, mut refused) = (Vec::new(), 0);
        for (x, y, phi) in states {
            let Some(paper) = self.beyond_threshold(x, y, phi) else {
                continue;
            };
            match value(x, y, phi) {
                Some(v) => gaps.push((v - paper, paper)),
                None => refused += 1,
            }
        }
        (gaps, refused)
    }
}
