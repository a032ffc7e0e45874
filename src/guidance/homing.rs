//! The flight policy's pursuer below the theorem's threshold ([`crate::Policy::Flight`]): the
//! paper's law while its own prediction holds, homing on the evader where the law's game no
//! longer describes the chase.
//!
//! Below 2 r_e + 2 pi r_e v_pm / v_em the paper gives no law. Its 2x2 game still steers well
//! while its upper value falls by dt each period, but it breaks in three ways measured against
//! the adversary suite (docs/closed-loop.md): a crossing pair loses its valid tangent when the
//! players' circles overlap, so a row's maximum becomes infinite and min-max turns the pursuer
//! away for a full loop; an arc wraps by 2 pi and an entry jumps by a turn's time; and an evader
//! that circles never leaves its circle along the predicted tangent. The pursuer then homes on
//! the evader's present state and its turn rate seen over the last period (a state cannot tell
//! which way an evader turns; two states can), which needs no prediction of its choices:
//!
//! - within four periods' travel (a heading error there is a miss distance): the arc through
//!   the point where it meets the evader going on as it goes, on the arc of its observed turn
//!   (`terminal`), in the tail-chase zone no more than one period ahead;
//! - in the tail-chase zone, pure pursuit: the evader ahead of the pursuer's beam, running away from it, and
//!   the line of sight turning at most half the pursuer's full rate,
//!   v_em |sin beta| / d <= (1/2) v_pm w_pm, beta being the angle between the evader's heading
//!   and the line of sight. There pure pursuit closes at v_pm - v_em cos beta >= v_pm - v_em and
//!   the pursuer can turn with the line of sight, against any evader (a circling evader
//!   included: behind it on its circle the line of sight turns at v_em / (2 r_e));
//! - and once the law has lost its prediction (its upper value rose beyond the tie floor, or it
//!   has none), until the players are beyond the threshold again: first a lead turn, the
//!   pursuer turning (at most what a period needs, on the side it began: the nearer, or, on
//!   the first near-field period with the point within 0.3 rad of straight behind, the law's)
//!   until its nose is
//!   within 0.2 rad (`LEAD_ALIGNED`) of the point where it meets the evader going on along its
//!   observed arc (the collision triangle's point, `lead`), while the players are more than
//!   3 r_p (`LEAD_RADII`) apart: a Dubins car reaches a point soonest by turning fully and then
//!   running straight, where proportional navigation alone would curve slowly onto the
//!   collision course and give away most of a turn against an evader that plays well;
//!   then augmented proportional navigation (the evader's observed turn fed forward) while
//!   the evader is ahead and the distance closes (`navigation`), else pure pursuit;
//!   where the evader is inside the pursuer's turning circle on its side by more than the
//!   capture radius (turning cannot bring it ahead, nor within reach) the pursuer runs
//!   straight to open the distance. An evader can ride that circle's
//!   edge behind the beam, where pure pursuit alternates between turning toward it and running
//!   straight (a sliding mode on the boundary); after a full turn's time 2 pi / (v_pm w_pm) of
//!   pure pursuit with the evader inside the circle, the pursuer breaks away: a full turn to the
//!   other side until the evader is ahead of its beam.
//!
//! On the first period below the threshold the law's prediction is trusted where its chosen
//! pair is not Algorithm 2's overshoot and it has a saddle, or promises no more than homing
//! would take (the turn onto the line of sight at the full rate, then the distance closed at
//! v_pm - v_em): a law that promises more than that is far from the game's value there. With a
//! capture radius ([`crate::Guidance::with_capture_radius`]; 0, point capture, by default) the
//! pursuer also leaves the law, on any period, where homing to the radius is sooner than the
//! law's promise (`HomingTerms::outrun`): the law plays for the evader's position.
//!
//! On estimated states whose uncertainty passes a quarter of the capture radius
//! ([`crate::Guidance::decide_estimated`]) the pursuer flies none of the above but lead
//! pursuit (`lead_pursuit`): toward the collision point of the estimated evader running
//! straight on, at most 0.2 of its full turn ahead. Each fix moves an estimate by its
//! correction, which the tests above read as a manoeuvre (a jump of the observed turn, a rise
//! of the law's value, an evader inside the turning circle); the collision point needs the
//! estimated position and heading alone.
//!
//! Units: metres, seconds, radians anticlockwise from +x; curvature in 1/m.

use crate::law::geometry::{Limits, TurningCircle, VehicleLimits, VehicleState};
use crate::law::{bearing, steer, GameReport};
use crate::num::Scalar;

/// The line-of-sight rate the tail-chase zone allows, as a fraction of the pursuer's full turn
/// rate v_pm w_pm: the margin that leaves the pursuer turn left to close the bearing.
const TAIL_CHASE_RATE_FRACTION: f32 = 0.5;

/// What the near field compares and scales by, fixed by the limits and dt (computed once by
/// [`crate::Guidance::new`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct HomingTerms<S> {
    /// The theorem's distance threshold, metres ([`crate::Limits::theorem_threshold`]).
    pub threshold: S,
    /// Four periods' travel of the pursuer, 4 v_pm dt, metres: closer, a heading error is a
    /// miss distance.
    pub close: S,
    /// The tail-chase zone's largest line-of-sight rate, rad/s: half of v_pm w_pm.
    tail_chase_rate: S,
    /// v_em, m/s.
    evader_speed: S,
    /// v_pm, m/s.
    pursuer_speed: S,
    /// N / v_pm, s/m: proportional navigation's curvature per rad/s of line-of-sight rate.
    navigation_gain: S,
    /// v_pm^2 - v_em^2, m^2/s^2: the collision triangle's quadratic coefficient.
    closing_squares: S,
    /// The control period dt, seconds: the tail chase's terminal lead.
    period: S,
    /// The sampled law's tie floor, seconds: a rise of the upper value within it is a tie.
    tie_floor: S,
    /// The pursuer's 1 / (v_pm dt), per radian: the curvature that turns a radian in a period.
    per_radian: S,
    /// The evader's full turn over one period, v_em w_em dt, radians: the bound of its
    /// observed turn.
    evader_turn: S,
    /// (N / 2) v_em / v_pm^2, s/m: augmented navigation's curvature per rad/s of the evader's
    /// turn rate, per unit of its velocity's share across the line of sight.
    augment_gain: S,
    /// A full turn of the pursuer, 2 pi / (v_pm w_pm), seconds: how long pure pursuit may
    /// hold the evader inside its turning circle before it breaks away.
    turn_time: S,
    /// v_pm w_pm, rad/s: the pursuer's full turn rate.
    turn_rate: S,
    /// v_pm - v_em, m/s: the slowest closing of pure pursuit once on course.
    closing_speed: S,
    /// The lead pursuit's longest lead, [`LEAD_PURSUIT_TURNS`] of the pursuer's full turn,
    /// seconds.
    lead_cap: S,
    /// The capture radius, metres (0 unless the caller gives one,
    /// [`crate::Guidance::with_capture_radius`]): an evader within it of the pursuer's
    /// turning circle is in reach of a turn.
    pub capture: S,
}

impl<S: Scalar> HomingTerms<S> {
    /// The estimates' uncertainty (metres) past which the near field flies [`lead_pursuit`]:
    /// [`LEAD_PURSUIT_SHARE`] of the capture radius, or without one of four periods' travel.
    pub fn lead_pursuit_floor(&self) -> S {
        let reach = if self.capture > S::zero() {
            self.capture
        } else {
            self.close
        };
        S::from_f32(LEAD_PURSUIT_SHARE) * reach
    }

    /// What homing would take from here, seconds: the turn onto the line of sight `to_go`
    /// (radians) at the full rate, then `gap` (metres) closed at v_pm - v_em.
    fn time_by_homing(&self, to_go: S, gap: S) -> S {
        to_go.abs() / self.turn_rate + gap / self.closing_speed
    }

    /// Whether, with a capture radius, homing reaches it sooner than the law promises: the
    /// law plays for the evader's position (point capture), and its upper value less the
    /// radius's share, capture / (v_pm - v_em), is then compared with [`Self::time_by_homing`]
    /// to the radius.
    /// Never without a capture radius: there the law's path is the quick one more often than
    /// this estimate says (measured on seeded starts against the law's evader).
    fn outrun(&self, report: &GameReport<S>, to_go: S, distance: S) -> bool {
        match report.solution.upper {
            Some(upper) if self.capture > S::zero() => {
                let gap = (distance - self.capture).max(S::zero());
                upper - self.capture / self.closing_speed > self.time_by_homing(to_go, gap)
            }
            _ => false,
        }
    }

    /// The terms of `limits` with control period `dt` (the law's units), the sampled law's
    /// `tie_floor` (seconds) and the pursuer's `per_radian`, 1 / (v_pm dt).
    pub fn new(limits: &Limits<S>, dt: S, tie_floor: S, per_radian: S) -> Self {
        let p = &limits.pursuer;
        HomingTerms {
            threshold: limits.theorem_threshold(),
            close: S::from_f32(4.0) * p.v_max() * dt,
            tail_chase_rate: S::from_f32(TAIL_CHASE_RATE_FRACTION) * p.max_turn_rate(),
            evader_speed: limits.evader.v_max(),
            pursuer_speed: p.v_max(),
            navigation_gain: S::from_f32(NAVIGATION_GAIN) / p.v_max(),
            closing_squares: p.v_max() * p.v_max() - limits.evader.v_max() * limits.evader.v_max(),
            period: dt,
            tie_floor,
            per_radian,
            evader_turn: limits.evader.max_turn_rate() * dt,
            augment_gain: S::from_f32(NAVIGATION_GAIN / 2.0) * limits.evader.v_max()
                / (p.v_max() * p.v_max()),
            turn_time: S::from_f32(2.0) * S::pi() / p.max_turn_rate(),
            turn_rate: p.max_turn_rate(),
            closing_speed: p.v_max() - limits.evader.v_max(),
            lead_cap: S::from_f32(2.0 * LEAD_PURSUIT_TURNS) * S::pi() / p.max_turn_rate(),
            capture: S::zero(),
        }
    }
}

/// One near-field period as the homing laws see it.
#[derive(Clone, Copy)]
pub(crate) struct Situation<'a, S> {
    /// This period's game.
    pub report: &'a GameReport<S>,
    /// The pursuer's state (metres, radians).
    pub pursuer: &'a VehicleState<S>,
    /// The evader's state.
    pub evader: &'a VehicleState<S>,
    /// Their distance, metres.
    pub distance: S,
    /// The pursuer's limits.
    pub limits: &'a VehicleLimits<S>,
    /// The law's sampled curvature for the pursuer, 1/m.
    pub law: S,
}

/// What homing remembers: the law's last upper value (seconds), whether the pursuer
/// has left the law for pursuit, the evader's last heading (radians), the time of pure
/// pursuit since navigation or the terminal arc last steered (seconds), and the curvature of a
/// break-away turn (1/m) while it lasts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct HomingMemory<S> {
    last_upper: Option<S>,
    pursuing: bool,
    last_evader_heading: Option<S>,
    time_homing: Option<S>,
    breaking: Option<S>,
    lead: LeadTurn,
}

/// The lead turn's progress (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
enum LeadTurn {
    /// Not yet aligned with the lead point; the side of the turn once begun (anticlockwise
    /// if `true`).
    Pending(Option<bool>),
    /// The nose came within [`LEAD_ALIGNED`] of the lead point: navigation holds the course.
    Done,
}

impl<S: Scalar> HomingMemory<S> {
    /// Nothing remembered: the law is followed.
    pub const FRESH: Self = HomingMemory {
        last_upper: None,
        pursuing: false,
        last_evader_heading: None,
        time_homing: None,
        breaking: None,
        lead: LeadTurn::Pending(None),
    };

    /// The pursuer's curvature (1/m) below the threshold: the law's sampled command or
    /// homing (module docs).
    pub fn pursuer_command(&mut self, now: &Situation<'_, S>, terms: &HomingTerms<S>) -> S {
        let Situation {
            report,
            pursuer,
            evader,
            distance,
            limits,
            law,
        } = *now;
        let (dt, tie_floor, per_radian) = (terms.period, terms.tie_floor, terms.per_radian);
        let to_go = bearing(pursuer, evader.x, evader.y);
        // The law's turn is the lead turn's tie-break only where the pursuer has not followed
        // it yet: later the law's circles have been played and the point behind is the
        // evader's doing.
        let untried_law = if self.last_evader_heading.is_none() {
            law
        } else {
            S::zero()
        };
        if self.lost(report, distance, terms, dt, tie_floor, to_go)
            || terms.outrun(report, to_go, distance)
        {
            self.pursuing = true;
        }
        let close = distance < terms.close;
        let turn = self.evader_turn_rate(evader, terms);
        let sight = Sight::new(pursuer, evader, distance, turn);
        // Pursuit, once begun, holds until the players are beyond the threshold again: a
        // pursuer that went back to the law at the zone's edge would chatter between the two.
        let tail = sight.tail_chase(terms);
        self.pursuing = self.pursuing || close || tail;
        if !self.pursuing {
            return law;
        }
        // Within four periods' travel: the collision triangle's arc; in the tail-chase zone
        // aimed at most one period ahead.
        if close {
            self.end_pure_pursuit();
            return sight.terminal(limits, terms, tail);
        }
        if !tail {
            if let Some(w) = self.lead_turn(&sight, pursuer, limits, terms, per_radian, untried_law)
            {
                self.end_pure_pursuit();
                return w;
            }
            if let Some(w) = sight.navigation(limits, terms) {
                self.end_pure_pursuit();
                return w;
            }
        }
        // Pure pursuit; where the evader is inside the turning circle on its side, straight on
        // to open the distance, and a break-away turn once pure pursuit has held for a full
        // turn's time (module docs). The time saturates there (fixed point's range).
        // A bearing below the arc resolution is on course, as the law reads a tangent's arc.
        let on_course = to_go.abs() <= S::from_f32(S::ARC_RESOLUTION);
        let homed = (self.time_homing.unwrap_or(S::zero()) + dt).min(terms.turn_time);
        self.time_homing = Some(homed);
        if sight.ahead > S::zero() {
            self.breaking = None;
        }
        let inside = inside_turn(pursuer, evader, limits, to_go, terms.capture);
        if inside && homed >= terms.turn_time && self.breaking.is_none() {
            // Away from the evader: anticlockwise when it is on the right.
            let away = if to_go < S::zero() {
                S::one()
            } else {
                S::zero() - S::one()
            };
            self.breaking = Some(full_turn(away, limits));
            self.time_homing = None;
        }
        if let Some(w) = self.breaking {
            w
        } else if on_course || inside {
            S::zero()
        } else {
            steer(to_go, limits, Some(per_radian))
        }
    }

    /// The lead turn's curvature (1/m) while it lasts (module docs): toward the collision
    /// triangle's point at most what one period needs (`per_radian`, 1 / (v_pm dt)), on the
    /// side the turn began ([`first_side`], `law` the law's curvature on the first near-field
    /// period, else 0), so that a point
    /// straight behind does not flip it every period;
    /// `None` once the nose has come within [`LEAD_ALIGNED`] of the point, or within
    /// [`LEAD_RADII`] r_p of the evader (a turn there passes it).
    fn lead_turn(
        &mut self,
        sight: &Sight<S>,
        pursuer: &VehicleState<S>,
        limits: &VehicleLimits<S>,
        terms: &HomingTerms<S>,
        per_radian: S,
        law: S,
    ) -> Option<S> {
        let LeadTurn::Pending(side) = self.lead else {
            return None;
        };
        let (ax, ay) = sight.lead(terms);
        let to_aim = bearing(pursuer, pursuer.x + ax, pursuer.y + ay);
        if to_aim.abs() <= S::from_f32(LEAD_ALIGNED) {
            self.lead = LeadTurn::Done;
            return None;
        }
        if sight.distance * limits.w_max() <= S::from_f32(LEAD_RADII) {
            return None;
        }
        let left = to_aim >= S::zero();
        let side = side.unwrap_or_else(|| first_side(to_aim, law));
        self.lead = LeadTurn::Pending(Some(side));
        Some(if side == left {
            steer(to_aim, limits, Some(per_radian))
        } else {
            full_turn(if side { S::one() } else { S::zero() - S::one() }, limits)
        })
    }

    /// Navigation or the terminal arc steers: pure pursuit's timer and break-away end.
    fn end_pure_pursuit(&mut self) {
        self.time_homing = None;
        self.breaking = None;
    }

    /// The evader's turn rate (rad/s, anticlockwise positive) observed over the last period:
    /// its heading's change within +-v_em w_em dt, over dt; 0 on the first near-field period.
    /// A state feedback cannot tell which way a circling evader turns; over two periods the
    /// pursuer sees it. Records the heading.
    fn evader_turn_rate(&mut self, evader: &VehicleState<S>, terms: &HomingTerms<S>) -> S {
        let turn = match self.last_evader_heading {
            Some(last) => (evader.theta - last)
                .wrap_signed()
                .max(S::zero() - terms.evader_turn)
                .min(terms.evader_turn),
            None => S::zero(),
        };
        self.last_evader_heading = Some(evader.theta);
        turn / terms.period
    }

    /// Whether the law has lost its own prediction: on the first near-field period its game is
    /// not trusted ([`crate::GameReport::trusted`]), or has no saddle and promises more than
    /// homing would take (`to_go` the bearing to the evader, radians); later, its upper value rose instead of
    /// falling by dt (beyond the tie floor), or it has no finite value while the players are
    /// more than four periods' travel apart. Records the upper value.
    fn lost(
        &mut self,
        report: &GameReport<S>,
        distance: S,
        terms: &HomingTerms<S>,
        dt: S,
        tie_floor: S,
        to_go: S,
    ) -> bool {
        let upper = report.solution.upper;
        let lost = match (self.last_upper, upper) {
            (_, None) => distance >= terms.close,
            (None, Some(now)) => {
                let saddle = report.solution.saddle_within(tie_floor);
                !(report.trusted() && (saddle || now <= terms.time_by_homing(to_go, distance)))
            }
            (Some(last), Some(now)) => now > last - dt + tie_floor,
        };
        self.last_upper = upper;
        lost
    }
}

/// The line of sight and both headings, computed once per near-field period: the sines and
/// cosines are shared by the zone test and the homing laws.
struct Sight<S> {
    /// Evader minus pursuer, metres.
    rx: S,
    ry: S,
    /// |r|, metres.
    distance: S,
    /// The pursuer's heading, (sin, cos).
    pursuer: (S, S),
    /// The evader's heading, (sin, cos).
    evader: (S, S),
    /// r along the pursuer's heading, metres: > 0 where the evader is ahead of its beam.
    ahead: S,
    /// The evader's observed turn rate, rad/s.
    turn: S,
}

impl<S: Scalar> Sight<S> {
    fn new(pursuer: &VehicleState<S>, evader: &VehicleState<S>, distance: S, turn: S) -> Self {
        let (rx, ry) = (evader.x - pursuer.x, evader.y - pursuer.y);
        let (sin_p, cos_p) = pursuer.theta.sin_cos();
        Sight {
            rx,
            ry,
            distance,
            pursuer: (sin_p, cos_p),
            evader: evader.theta.sin_cos(),
            ahead: rx * cos_p + ry * sin_p,
            turn,
        }
    }

    /// Whether the players are in the tail-chase zone (module docs): the evader ahead of the
    /// pursuer's beam and running away from it, with the line of sight turning at most
    /// `terms.tail_chase_rate`, v_em |sin beta| / d (rad/s), compared as
    /// v_em |cross| <= rate d^2 with cross = d sin beta.
    fn tail_chase(&self, terms: &HomingTerms<S>) -> bool {
        let (sin, cos) = self.evader;
        let away = self.rx * cos + self.ry * sin;
        let cross = (self.rx * sin - self.ry * cos).abs();
        away > S::zero()
            && self.ahead > S::zero()
            && terms.evader_speed * cross <= terms.tail_chase_rate * self.distance * self.distance
    }

    /// The terminal command within four periods' travel (1/m): the arc, tangent to the
    /// pursuer's heading, through where the evader will be at the collision time T of the
    /// straight-line triangle |r + u T| = v_pm T (u the evader's velocity), placed on the arc
    /// of its observed turn ([`Self::evader_after`]); in the tail-chase zone (`tail`) at most
    /// one period ahead (T <= dt). Pure pursuit aims where the evader is; over a period the pursuer runs several
    /// capture radii, so aiming there misses by the evader's own travel across the line of
    /// sight (a circling evader was passed 1 to 3 cm off, lap after lap, against a 1 cm capture
    /// radius). In the tail chase the straight-line prediction is trusted for one period only:
    /// a slow tail chase has a collision time of many periods, over which a circling evader
    /// leaves the predicted line. The arc through a point at bearing b and distance L has
    /// curvature 2 sin b / L, with L the aim point's own distance: with the lead capped at a
    /// period L exceeds v_pm T, and dividing by v_pm T twice made the gain up to 14 times too
    /// high (full turns each way against a weaving evader, 0.34 s late); a point behind the
    /// pursuer gets a full turn toward it. Written so that no term exceeds
    /// |r| / (1 - v_em / v_pm) (the fixed-point backend's range):
    /// T = d (c + sqrt(c^2 + v_pm^2 - v_em^2)) / (v_pm^2 - v_em^2) with c = (r . u) / d, and
    /// sin b = (h x aim) / L.
    fn terminal(&self, limits: &VehicleLimits<S>, terms: &HomingTerms<S>, tail: bool) -> S {
        if self.distance <= S::zero() {
            return S::zero();
        }
        let time = self.collision_time(terms);
        let time = if tail { time.min(terms.period) } else { time };
        let (ax, ay) = self.evader_after(time, terms);
        let (sin_p, cos_p) = self.pursuer;
        let cross = cos_p * ay - sin_p * ax;
        // |aim| <= d + v_em T: its components over that bound square without overflow.
        let bound = self.distance + terms.evader_speed * time;
        let (ux, uy) = (ax / bound, ay / bound);
        let reach = bound * (ux * ux + uy * uy).sqrt();
        if cos_p * ax + sin_p * ay <= S::zero() || reach <= S::zero() {
            return full_turn(cross, limits);
        }
        // 2 sin b / |aim| within +-w_max, compared before dividing.
        let two_sin = S::from_f32(2.0) * cross / reach;
        within_turn(two_sin, reach, limits)
    }

    /// The collision time T of the straight-line triangle |r + u T| = v_pm T (u the evader's
    /// velocity), seconds, for a distance > 0 (see [`Self::terminal`] for its range).
    fn collision_time(&self, terms: &HomingTerms<S>) -> S {
        let (sin_e, cos_e) = self.evader;
        let c = terms.evader_speed * (self.rx * cos_e + self.ry * sin_e) / self.distance;
        let a = terms.closing_squares;
        self.distance * (c + (c * c + a).sqrt()) / a
    }

    /// The lead turn's aim relative to the pursuer (metres): where the evader will be at the
    /// collision time, on the arc of its observed turn.
    fn lead(&self, terms: &HomingTerms<S>) -> (S, S) {
        self.evader_after(self.collision_time(terms), terms)
    }

    /// Where the evader will be after `time` seconds relative to the pursuer now (metres): on
    /// the arc of its observed turn rate at v_em, no more than half a turn of it. The chord of
    /// an arc turned by phi has length v_em T sin(phi / 2) / (phi / 2) and heading
    /// theta_e + phi / 2.
    fn evader_after(&self, time: S, terms: &HomingTerms<S>) -> (S, S) {
        let half_turn = S::pi() / S::from_f32(2.0);
        let half = (self.turn * time / S::from_f32(2.0))
            .max(S::zero() - half_turn)
            .min(half_turn);
        let (sin_h, cos_h) = half.sin_cos();
        let run = terms.evader_speed * time;
        let chord = if half.abs() > S::from_f32(S::ARC_RESOLUTION) {
            run * (sin_h / half)
        } else {
            run
        };
        let (sin_e, cos_e) = self.evader;
        (
            self.rx + chord * (cos_e * cos_h - sin_e * sin_h),
            self.ry + chord * (sin_e * cos_h + cos_e * sin_h),
        )
    }

    /// Augmented proportional navigation (1/m): curvature N lambda_dot / v_pm, lambda_dot being
    /// the line of sight's rate (rad/s) with the evader at v_em on its heading, plus
    /// (N / 2) a_e / v_pm^2 for the evader's observed acceleration a_e across the line of
    /// sight, within +-w_max; `None`
    /// unless the evader is ahead of the pursuer's beam and the distance closing. Pure
    /// pursuit's turn rate grows without bound in the last metre of a crossing chase when
    /// v_pm < 2 v_em (the pursuer misses by centimetres and comes round again, for ever against
    /// a circling evader); navigation holds the line of sight still and leads the evader.
    fn navigation(&self, limits: &VehicleLimits<S>, terms: &HomingTerms<S>) -> Option<S> {
        let ((sin_p, cos_p), (sin_e, cos_e)) = (self.pursuer, self.evader);
        let (vx, vy) = (
            terms.evader_speed * cos_e - terms.pursuer_speed * cos_p,
            terms.evader_speed * sin_e - terms.pursuer_speed * sin_p,
        );
        let closing = self.rx * vx + self.ry * vy < S::zero();
        if self.ahead <= S::zero() || !closing || self.distance <= S::zero() {
            return None;
        }
        // N lambda_dot / v_pm = (N / v_pm) ((r x v) / d) / d: the first quotient is at most
        // N |v| / v_pm <= 2 N; compared with w_max d before the second division.
        let turn = terms.navigation_gain * ((self.rx * vy - self.ry * vx) / self.distance);
        // Augmented: plus (N / 2) a_e / v_pm^2 with a_e the evader's observed acceleration
        // across the line of sight, omega_e v_em (r . e_hat) / d (times d, as `turn`).
        let across = (self.rx * cos_e + self.ry * sin_e) * self.turn;
        let turn = turn + terms.augment_gain * across;
        Some(within_turn(turn, self.distance, limits))
    }
}

/// The near field's pursuer on uncertain estimates (module docs): toward the estimated
/// evader's collision point, where it meets the evader running straight on at v_em, led at
/// most [`LEAD_PURSUIT_TURNS`] of a full turn; the sampled command, at most what a period
/// needs (`per_radian`, 1 / (v_pm dt)).
pub(crate) fn lead_pursuit<S: Scalar>(
    now: &Situation<'_, S>,
    terms: &HomingTerms<S>,
    per_radian: S,
) -> S {
    if now.distance <= S::zero() {
        return S::zero();
    }
    let sight = Sight::new(now.pursuer, now.evader, now.distance, S::zero());
    let time = sight.collision_time(terms).min(terms.lead_cap);
    let (ax, ay) = sight.evader_after(time, terms);
    let pursuer = now.pursuer;
    let to_aim = bearing(pursuer, pursuer.x + ax, pursuer.y + ay);
    steer(to_aim, now.limits, Some(per_radian))
}

/// The lead pursuit's longest lead, in the pursuer's full turns 2 pi / (v_pm w_pm): measured
/// on the field's sweep at 5 fixes per full turn, 0.1 and 0.4 met fewer cells than 0.2.
const LEAD_PURSUIT_TURNS: f32 = 0.2;

/// The share of the capture radius (or, without one, of four periods' travel) that the
/// estimates' uncertainty must pass for the near field to fly [`lead_pursuit`].
const LEAD_PURSUIT_SHARE: f32 = 0.25;

/// A full turn (1/m) to the side of `side`'s sign (anticlockwise for zero).
fn full_turn<S: Scalar>(side: S, limits: &VehicleLimits<S>) -> S {
    if side < S::zero() {
        S::zero() - limits.w_max()
    } else {
        limits.w_max()
    }
}

/// `numerator / length` (1/m) where it is within +-w_max, else the full turn on its side;
/// compared before dividing, so that a short `length` (> 0) does not overflow the quotient.
fn within_turn<S: Scalar>(numerator: S, length: S, limits: &VehicleLimits<S>) -> S {
    if numerator.abs() >= limits.w_max() * length {
        full_turn(numerator, limits)
    } else {
        numerator / length
    }
}

/// Proportional navigation's gain N: the pursuer turns N times as fast as the line of sight.
/// 3, the textbook value: it nulls the line of sight's rate against a non-turning evader, and
/// against one turning with lateral acceleration a_e it asks for about N / (N - 2) a_e = 3 a_e,
/// which the pursuer has wherever v_pm^2 w_pm >= 3 v_em^2 w_em.
const NAVIGATION_GAIN: f32 = 3.0;

/// How close to the lead point the pursuer's nose must come to end the lead turn, radians:
/// five periods' full turn at 10 ms and the paper's limits; navigation takes the rest.
const LEAD_ALIGNED: f32 = 0.2;

/// How near straight behind the lead point must be for the law's side to start the lead turn,
/// radians: there the two sides differ by less than 0.6 rad of turn (0.15 s at the paper's
/// pursuer), less than the evader's turn moves the point while the pursuer turns.
const LEAD_BEHIND: f32 = 0.3;

/// The side of a lead turn that begins with the lead point at bearing `to_aim` (radians),
/// anticlockwise if `true`: the nearer one, but with the point within [`LEAD_BEHIND`] of
/// straight behind, the side of the law's turn `law` (curvature, 1/m), whose circles weigh
/// the evader's best turn, when it turns (0: no preference).
fn first_side<S: Scalar>(to_aim: S, law: S) -> bool {
    if to_aim.abs() > S::pi() - S::from_f32(LEAD_BEHIND) && law != S::zero() {
        law > S::zero()
    } else {
        to_aim >= S::zero()
    }
}

/// The distance, in pursuer radii r_p, within which there is no lead turn: closer, a full turn
/// toward the lead point orbits an evader that circles inside it (meshing circles were passed
/// a few centimetres off once a lap), and navigation and the terminal arc steer.
const LEAD_RADII: f32 = 3.0;

/// Whether the evader is inside the pursuer's turning circle on the side of its bearing
/// `to_go` (radians) by more than the capture radius `capture` (metres): turning cannot bring
/// it ahead, nor within reach.
fn inside_turn<S: Scalar>(
    pursuer: &VehicleState<S>,
    evader: &VehicleState<S>,
    limits: &VehicleLimits<S>,
    to_go: S,
    capture: S,
) -> bool {
    let [a, c] = TurningCircle::both(pursuer, limits);
    let side = if to_go >= S::zero() { a } else { c };
    let reach = side.radius - capture;
    reach > S::zero() && side.centre().distance_squared(evader.position()) < reach * reach
}
