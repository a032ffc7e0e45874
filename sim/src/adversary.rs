//! The adversary suite: opponents that do not play the paper's law, seeded, for the closed loop
//! ([`crate::sim::simulate_against`]). Evaders run from our pursuer; the mirror, pursuers that
//! do not play the law, chase our evader.
//!
//! Every adversary sees the true states each control period and answers a curvature (1/m) and a
//! speed (m/s) within its limits, held for the period like the law's sampled command.

use crate::kinematics::advance;
use crate::rng::Rng;
use twocars::{Guidance, Law, Limits, Scalar, Status, Variant, VehicleState};

/// An evader of the suite.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EvaderKind {
    /// The paper's law with the sampled command's tie memory (what `sim` runs).
    Law,
    /// The paper's law with no memory: ties go to A every period.
    LawMemoryless,
    /// Straight ahead at full speed.
    Straight,
    /// A circle at full speed: anticlockwise (`left`) or clockwise, at the full or half curvature.
    Circle {
        /// Anticlockwise.
        left: bool,
        /// Half the maximum curvature.
        half: bool,
    },
    /// Piecewise-constant curvature, uniform in [-w_em, w_em], each held 0.2 to 2 s.
    Random,
    /// Full turns, +-w_em, switching side at random times 0.1 to 3 s apart.
    BangBang,
    /// Each period the curvature in {-w_em, 0, +w_em} that, held for `periods` periods against
    /// the law-playing pursuer, leaves the law's upper value largest.
    Greedy {
        /// Lookahead, control periods.
        periods: u32,
    },
    /// The law's turns at a speed anywhere in [0, v_em], piecewise constant (0.2 to 2 s).
    Slowing,
    /// Full turns, +-w_em, switching side every 3 s, the first side at random (not in
    /// [`EvaderKind::ALL`]: the field's sweep adds it, [`EvaderKind::FIELD`]).
    Zigzag,
}

/// A pursuer of the mirror suite (against our evader).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PursuerKind {
    /// The paper's law (with the tie memory).
    Law,
    /// Straight ahead at full speed.
    Straight,
    /// Pure pursuit: turns toward the evader's present position, at most one period's need.
    PurePursuit,
    /// A full-rate anticlockwise circle.
    Circle,
    /// Each period the curvature in {-w_pm, 0, +w_pm} that, held for one period against the
    /// law-playing evader, leaves the law's upper value smallest.
    Greedy,
}

/// The player an adversary replaces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Opponent {
    /// An evader against our pursuer.
    Evader(EvaderKind),
    /// A pursuer against our evader.
    Pursuer(PursuerKind),
}

impl EvaderKind {
    /// Every evader of the suite.
    pub const ALL: [EvaderKind; 12] = [
        EvaderKind::Law,
        EvaderKind::LawMemoryless,
        EvaderKind::Straight,
        EvaderKind::Circle {
            left: true,
            half: false,
        },
        EvaderKind::Circle {
            left: false,
            half: false,
        },
        EvaderKind::Circle {
            left: true,
            half: true,
        },
        EvaderKind::Circle {
            left: false,
            half: true,
        },
        EvaderKind::Random,
        EvaderKind::BangBang,
        EvaderKind::Greedy { periods: 1 },
        EvaderKind::Greedy { periods: 10 },
        EvaderKind::Slowing,
    ];

    /// The evaders of the field's sweep: the suite and [`EvaderKind::Zigzag`].
    pub const FIELD: [EvaderKind; 13] = {
        let mut field = [EvaderKind::Zigzag; 13];
        let mut i = 0;
        while i < Self::ALL.len() {
            field[i] = Self::ALL[i];
            i += 1;
        }
        field
    };

    /// The name `cargo xtask report --evader` takes.
    pub fn name(self) -> &'static str {
        match self {
            EvaderKind::Law => "law",
            EvaderKind::LawMemoryless => "law-memoryless",
            EvaderKind::Straight => "straight",
            EvaderKind::Circle {
                left: true,
                half: false,
            } => "circle-left",
            EvaderKind::Circle {
                left: false,
                half: false,
            } => "circle-right",
            EvaderKind::Circle {
                left: true,
                half: true,
            } => "circle-left-half",
            EvaderKind::Circle {
                left: false,
                half: true,
            } => "circle-right-half",
            EvaderKind::Random => "random",
            EvaderKind::BangBang => "bang-bang",
            EvaderKind::Greedy { periods: 1 } => "greedy",
            EvaderKind::Greedy { .. } => "greedy-10",
            EvaderKind::Slowing => "slowing",
            EvaderKind::Zigzag => "zigzag",
        }
    }

    /// The evader of that name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::FIELD.into_iter().find(|e| e.name() == name)
    }
}

impl PursuerKind {
    /// Every pursuer of the mirror suite.
    pub const ALL: [PursuerKind; 5] = [
        PursuerKind::Law,
        PursuerKind::Straight,
        PursuerKind::PurePursuit,
        PursuerKind::Circle,
        PursuerKind::Greedy,
    ];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            PursuerKind::Law => "law",
            PursuerKind::Straight => "straight",
            PursuerKind::PurePursuit => "pure-pursuit",
            PursuerKind::Circle => "circle",
            PursuerKind::Greedy => "greedy",
        }
    }
}

/// How long the zigzag evader turns to one side, seconds.
pub const ZIGZAG_SECONDS: f64 = 3.0;

/// A piecewise-constant choice: curvature and speed as fractions of the maxima, until `until`.
#[derive(Clone, Copy, Debug)]
struct Hold {
    until: f64,
    curvature: f64,
    speed: f64,
}

/// One adversary in one run: its kind, its seeded generator and what it needs of the law.
pub struct Adversary {
    opponent: Opponent,
    rng: Rng,
    hold: Hold,
    /// v_pm, w_pm, v_em, w_em.
    limits: [f64; 4],
    dt: f64,
    eps: f64,
    /// The paper's law in f64 with the run's period (the law-playing and greedy adversaries).
    guidance: Guidance<f64>,
    scene: Limits<f64>,
}

impl Adversary {
    /// The adversary `opponent` for limits (v_pm, w_pm, v_em, w_em), period `dt` and capture
    /// distance `eps`; `seed` drives its random choices. `None` where the limits or dt are
    /// invalid for the law.
    pub fn new(opponent: Opponent, limits: [f64; 4], dt: f64, eps: f64, seed: u64) -> Option<Self> {
        let [v_pm, w_pm, v_em, w_em] = limits.map(|v| v as f32);
        let scene = Limits::<f64>::new(v_pm, w_pm, v_em, w_em).ok()?;
        let guidance = Guidance::new(
            Law::new(scene, Variant::Paper),
            dt as f32,
            twocars::Policy::Paper,
        )
        .ok()?;
        Some(Adversary {
            opponent,
            rng: Rng::new(seed),
            hold: Hold {
                until: f64::NEG_INFINITY,
                curvature: 0.0,
                speed: 1.0,
            },
            limits,
            dt,
            eps,
            guidance,
            scene,
        })
    }

    /// Which player this adversary is.
    pub fn opponent(&self) -> Opponent {
        self.opponent
    }

    /// This period's curvature (1/m) and speed (m/s) of the adversary's player, at time `t` (s),
    /// from both states (x, y, theta in one frame).
    pub fn command(&mut self, t: f64, pursuer: [f64; 3], evader: [f64; 3]) -> (f64, f64) {
        let [v_pm, w_pm, v_em, w_em] = self.limits;
        match self.opponent {
            Opponent::Evader(kind) => {
                let w = match kind {
                    EvaderKind::Law => self.law(pursuer, evader, true).1,
                    EvaderKind::LawMemoryless => self.law(pursuer, evader, false).1,
                    EvaderKind::Straight => 0.0,
                    EvaderKind::Circle { left, half } => {
                        let w = if half { 0.5 * w_em } else { w_em };
                        if left {
                            w
                        } else {
                            -w
                        }
                    }
                    EvaderKind::Random => {
                        self.renew(t, 0.2, 2.0, |rng| (rng.uniform(-1.0, 1.0), 1.0));
                        self.hold.curvature * w_em
                    }
                    EvaderKind::BangBang => {
                        self.switch_sides(t, |rng| rng.uniform(0.1, 3.0)) * w_em
                    }
                    EvaderKind::Zigzag => self.switch_sides(t, |_| ZIGZAG_SECONDS) * w_em,
                    EvaderKind::Greedy { periods } => self.greedy(pursuer, evader, periods, false),
                    EvaderKind::Slowing => {
                        self.renew(t, 0.2, 2.0, |rng| (0.0, rng.uniform(0.0, 1.0)));
                        let w = self.law(pursuer, evader, true).1;
                        return (w, self.hold.speed * v_em);
                    }
                };
                (w, v_em)
            }
            Opponent::Pursuer(kind) => {
                let w = match kind {
                    PursuerKind::Law => self.law(pursuer, evader, true).0,
                    PursuerKind::Straight => 0.0,
                    PursuerKind::Circle => w_pm,
                    PursuerKind::PurePursuit => {
                        let bearing = crate::kinematics::wrap_pi(
                            (evader[1] - pursuer[1]).atan2(evader[0] - pursuer[0]) - pursuer[2],
                        );
                        bearing.signum() * w_pm.min(bearing.abs() / (v_pm * self.dt))
                    }
                    PursuerKind::Greedy => self.greedy(pursuer, evader, 1, true),
                };
                (w, v_pm)
            }
        }
    }

    /// Full turns that switch side whenever the hold ends, each held for what `hold_for`
    /// draws (s); the first side at random. The curvature as a fraction of w_max.
    fn switch_sides(&mut self, t: f64, hold_for: impl FnOnce(&mut Rng) -> f64) -> f64 {
        if t >= self.hold.until {
            let side = if self.hold.until == f64::NEG_INFINITY {
                if self.rng.uniform(0.0, 1.0) < 0.5 {
                    1.0
                } else {
                    -1.0
                }
            } else {
                -self.hold.curvature
            };
            self.hold = Hold {
                until: t + hold_for(&mut self.rng),
                curvature: side,
                speed: 1.0,
            };
        }
        self.hold.curvature
    }

    /// Draws a new hold (curvature and speed fractions) lasting `lo` to `hi` seconds once the
    /// last one has ended.
    fn renew(&mut self, t: f64, lo: f64, hi: f64, draw: impl FnOnce(&mut Rng) -> (f64, f64)) {
        if t >= self.hold.until {
            let (curvature, speed) = draw(&mut self.rng);
            self.hold = Hold {
                until: t + self.rng.uniform(lo, hi),
                curvature,
                speed,
            };
        }
    }

    /// The law's sampled command (pursuer, evader curvatures, 1/m), with or without the tie
    /// memory; straight ahead where the states leave the law's envelope.
    fn law(&mut self, pursuer: [f64; 3], evader: [f64; 3], memory: bool) -> (f64, f64) {
        if !memory {
            self.guidance.reset();
        }
        match self.states(pursuer, evader) {
            Some((p, e)) => {
                let command = self.guidance.decide(&p, &e).command;
                (command.pursuer, command.evader)
            }
            None => (0.0, 0.0),
        }
    }

    fn states(
        &self,
        pursuer: [f64; 3],
        evader: [f64; 3],
    ) -> Option<(VehicleState<f64>, VehicleState<f64>)> {
        let narrow = |s: [f64; 3]| s.map(|v| v as f32);
        self.scene.states(narrow(pursuer), narrow(evader)).ok()
    }

    /// The law's upper value (s) at a state; infinity where it has none, minus infinity where
    /// the players are within eps.
    fn upper(&self, pursuer: [f64; 3], evader: [f64; 3]) -> f64 {
        if (pursuer[0] - evader[0]).hypot(pursuer[1] - evader[1]) <= self.eps {
            return f64::NEG_INFINITY;
        }
        let Some((p, e)) = self.states(pursuer, evader) else {
            return f64::INFINITY;
        };
        let evaluation = Law::new(self.scene, Variant::Paper).evaluate(&p, &e);
        match evaluation.status {
            Status::Captured => f64::NEG_INFINITY,
            _ => evaluation
                .report
                .and_then(|r| r.solution.upper)
                .map_or(f64::INFINITY, |v| v.to_f64()),
        }
    }

    /// The greedy player's curvature: of {-w_max, 0, +w_max} held for `periods` periods while
    /// the other player follows the law's sampled command, the one whose end state's upper
    /// value is largest (evader) or smallest (`pursuing`). The first option wins ties.
    fn greedy(&mut self, pursuer: [f64; 3], evader: [f64; 3], periods: u32, pursuing: bool) -> f64 {
        let [v_pm, w_pm, v_em, w_em] = self.limits;
        let w_max = if pursuing { w_pm } else { w_em };
        let mut best = (0.0, f64::NAN);
        for w in [0.0, w_max, -w_max] {
            let mut scratch = self.guidance;
            scratch.reset();
            let (mut p, mut e) = (pursuer, evader);
            let mut score = f64::NAN;
            for _ in 0..periods {
                let other = match self.states(p, e) {
                    Some((ps, es)) => scratch.decide(&ps, &es).command,
                    None => twocars::Command::straight(),
                };
                let (w_p, w_e) = if pursuing {
                    (w, other.evader)
                } else {
                    (other.pursuer, w)
                };
                p = advance(p, v_pm, w_p, self.dt);
                e = advance(e, v_em, w_e, self.dt);
                if (p[0] - e[0]).hypot(p[1] - e[1]) <= self.eps {
                    score = f64::NEG_INFINITY;
                    break;
                }
            }
            if score.is_nan() {
                score = self.upper(p, e);
            }
            let better = if pursuing {
                score < best.1
            } else {
                score > best.1
            };
            if best.1.is_nan() || better {
                best = (w, score);
            }
        }
        best.0
    }
}
