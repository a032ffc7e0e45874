//! Vehicles, their minimum-radius turning circles and the valid directed common tangent of a
//! pursuer/evader circle pair (the paper's Preliminaries and Algorithm 1).
//!
//! Frames: metres, radians anticlockwise from +x. Curvature `w` in 1/m (theta_dot = v w).

use crate::error::Error;
use crate::num::convert::Reciprocal;
use crate::num::{ieee, Scalar};

/// Turning direction of a minimum-radius circle. As a number (`as usize`), its index in Table 1's
/// order: A = 0, C = 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Direction {
    /// The A circle: w = +w_max, sigma = +1.
    Anticlockwise = 0,
    /// The C circle: w = -w_max, sigma = -1.
    Clockwise = 1,
}

impl Direction {
    /// Both directions in the paper's Table 1 order (A first).
    pub const BOTH: [Direction; 2] = [Direction::Anticlockwise, Direction::Clockwise];

    /// sigma: +1 for anticlockwise, -1 for clockwise.
    pub fn sigma<S: Scalar>(self) -> S {
        match self {
            Direction::Anticlockwise => S::one(),
            Direction::Clockwise => -S::one(),
        }
    }

    /// `value` with this direction's sign: `value` for A, `-value` for C (sigma value without a
    /// multiplication).
    pub fn signed<S: Scalar>(self, value: S) -> S {
        match self {
            Direction::Anticlockwise => value,
            Direction::Clockwise => -value,
        }
    }

    /// Heading angle (radians, in [0, 2 pi)) a vehicle with heading `theta` turns through in this
    /// direction to reach heading `psi`: (sigma (psi - theta)) mod 2 pi, for `theta` and `psi`
    /// both in [-pi, pi] ([`Scalar::wrap_signed`]), whose difference wraps with one addition. The
    /// vehicle is on the tangent (angle 0) when the angle is below the backend's resolution
    /// `S::ARC_RESOLUTION`, or above `largest` (2 pi less a tolerance): a hair past the tangent.
    pub fn arc_to<S: Scalar>(self, theta: S, psi: S, largest: S) -> S {
        let turn = self.signed(psi - theta);
        let alpha = if turn < S::zero() {
            turn + S::tau()
        } else {
            turn
        };
        if alpha.between(S::from_f32(S::ARC_RESOLUTION), largest) {
            alpha
        } else {
            S::zero()
        }
    }

    /// The paper's letter: `A` or `C`.
    pub fn letter(self) -> char {
        match self {
            Direction::Anticlockwise => 'A',
            Direction::Clockwise => 'C',
        }
    }
}

/// A point in the plane, metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point<S> {
    /// x, metres.
    pub x: S,
    /// y, metres.
    pub y: S,
}

impl<S: Scalar> Point<S> {
    /// Euclidean distance to `other`, metres.
    pub fn distance(self, other: Point<S>) -> S {
        self.distance_squared(other).sqrt()
    }

    /// Square of the distance to `other`, square metres (no square root).
    pub fn distance_squared(self, other: Point<S>) -> S {
        let dx = other.x - self.x;
        let dy = other.y - self.y;
        dx * dx + dy * dy
    }
}

/// Speed and curvature limits of one vehicle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VehicleLimits<S> {
    v_max: S,
    w_max: S,
    radius: S,
    seconds_per_radian: S,
}

impl<S: Scalar> VehicleLimits<S> {
    /// Maximum speed, m/s.
    pub fn v_max(&self) -> S {
        self.v_max
    }
    /// Maximum curvature, 1/m.
    pub fn w_max(&self) -> S {
        self.w_max
    }
    /// Minimum turning radius 1 / w_max, metres.
    pub fn radius(&self) -> S {
        self.radius
    }
    /// Maximum turn rate v_max w_max, rad/s.
    pub fn max_turn_rate(&self) -> S {
        self.v_max * self.w_max
    }
    /// Time to turn through one radian at full speed on the minimum-radius circle,
    /// r / v_max, seconds (precomputed: a division on a core without a divider is a library call).
    pub fn seconds_per_radian(&self) -> S {
        self.seconds_per_radian
    }
}

/// Distance at or below which the positions coincide (status `captured`), as a fraction of the
/// pursuer's turning radius.
pub const CAPTURE_RADIUS_FRACTION: f32 = 1.0e-6;

/// Largest speed (m/s) and curvature (1/m) the law accepts, the largest turning radius (m) and
/// the smallest speed (m/s): beyond them products and quotients of the law leave every backend's
/// range (a subnormal evader speed made a capture time inf - inf = NaN; found by fuzzing).
pub const MAX_SPEED: f32 = 1.0e4;
/// See [`MAX_SPEED`].
pub const MIN_SPEED: f32 = 1.0e-3;
/// See [`MAX_SPEED`].
pub const MAX_CURVATURE: f32 = 1.0e4;
/// See [`MAX_SPEED`].
pub const MAX_RADIUS: f32 = 1.0e4;

/// The size of the law's units. SI backends (f32, f64) compute in metres and seconds; a
/// normalised backend ([`Scalar::NORMALISED`], fixed point) in units of the pursuer's turning
/// radius r_p and of r_p / v_pm seconds, so one number range covers every vehicle scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Units {
    /// One law length unit, metres.
    pub metres: f32,
    /// One law speed unit, m/s.
    pub metres_per_second: f32,
}

impl Units {
    /// Metres and seconds.
    pub const SI: Units = Units {
        metres: 1.0,
        metres_per_second: 1.0,
    };

    /// A law time, in seconds.
    pub fn seconds<S: Scalar>(&self, t: S) -> f64 {
        t.to_f64() * f64::from(self.metres) / f64::from(self.metres_per_second)
    }

    /// A law curvature, in 1/m.
    pub fn curvature<S: Scalar>(&self, w: S) -> f64 {
        w.to_f64() / f64::from(self.metres)
    }

    /// A law length, in metres.
    pub fn length<S: Scalar>(&self, l: S) -> f64 {
        l.to_f64() * f64::from(self.metres)
    }

    /// A duration in seconds, in law time units.
    pub fn time_from_seconds(&self, seconds: f32) -> f32 {
        seconds * self.metres_per_second / self.metres
    }

    /// The units backend `S` computes in for a pursuer of speed `v_pm` (m/s) and curvature
    /// `w_pm` (1/m), both finite and positive.
    pub fn of<S: Scalar>(v_pm: f32, w_pm: f32) -> Units {
        if S::NORMALISED {
            Units {
                metres: length_unit(w_pm),
                metres_per_second: v_pm,
            }
        } else {
            Units::SI
        }
    }
}

/// Whether a state in metres and radians is inside the f32 envelope (finite, |x|, |y| <=
/// 1e6 m, |theta| <= 1e4 rad), read on the bits: no float operation on a core without an FPU.
///
/// # Errors
/// `NonFiniteInput` for NaN or infinity, `OutOfRange` outside the envelope.
pub(crate) fn f32_envelope(state: [f32; 3]) -> Result<(), Error> {
    let bits = state.map(f32::to_bits);
    if !bits.iter().all(|&b| ieee::is_finite_bits(b)) {
        return Err(Error::NonFiniteInput);
    }
    let [x, y, theta] = bits.map(ieee::magnitude_bits);
    let coordinate = <f32 as Scalar>::MAX_COORDINATE.to_bits();
    if x > coordinate || y > coordinate || theta > <f32 as Scalar>::MAX_HEADING.to_bits() {
        return Err(Error::OutOfRange);
    }
    Ok(())
}

/// Limits of both players, validated once against the paper's Assumption 1
/// (v_pm > v_em > 0 and w_pm > w_em > 0), so the law never sees impossible limits. Stored in
/// the law's units ([`Units`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits<S> {
    /// The pursuer's limits.
    pub pursuer: VehicleLimits<S>,
    /// The evader's limits.
    pub evader: VehicleLimits<S>,
    /// The law's units for these limits on this backend.
    pub units: Units,
    /// 1 / (v_pm - v_em), s/m: the time the pursuer needs to close one metre on a common line.
    seconds_per_metre_closed: S,
    /// 1 / `units.metres`, for the integer conversion of wire positions on a normalised backend.
    per_metre: Reciprocal,
}

/// The checks of [`Limits::new`], in the contract's order: non-finite, then the game's
/// assumptions, then the envelope.
#[inline(always)]
fn validate<S: Scalar>(v_pm: f32, w_pm: f32, v_em: f32, w_em: f32) -> Result<(), Error> {
    if [v_pm, w_pm, v_em, w_em].iter().any(|v| !v.is_finite()) {
        return Err(Error::NonFiniteInput);
    }
    if !(v_pm > v_em && v_em > 0.0 && w_pm > w_em && w_em > 0.0) {
        return Err(Error::InvalidLimits);
    }
    if v_pm > MAX_SPEED || v_em < MIN_SPEED || w_pm > MAX_CURVATURE || 1.0 / w_em > MAX_RADIUS {
        return Err(Error::OutOfRange);
    }
    let speed_ratio = v_em / v_pm;
    if w_pm / w_em > S::MAX_RADIUS_RATIO
        || speed_ratio < S::MIN_SPEED_RATIO
        || speed_ratio > S::MAX_SPEED_RATIO
    {
        return Err(Error::OutOfRange);
    }
    Ok(())
}

impl<S: Scalar> VehicleLimits<S> {
    /// A vehicle of speed `v` (m/s) and curvature `w` (1/m) in the backend's `units`. The
    /// curvature is rounded toward zero, so that +-w_max commands stay within the true limit.
    /// On a normalised backend the radius and the turn time per radian are formed in f32 and
    /// rounded once: formed from the rounded curvature and speed they carried those roundings
    /// (fixed point: up to 1e-3 of r_e where w_em is w_pm / 16, and t_e with it).
    #[inline(always)]
    fn in_units(v: f32, w: f32, units: Units) -> Self {
        let w_max = S::from_f32_toward_zero(w * units.metres);
        let v_max = S::from_f32(v / units.metres_per_second);
        let (radius, seconds_per_radian) = if S::NORMALISED {
            let radius = 1.0 / (w * units.metres);
            (
                S::from_f32(radius),
                S::from_f32(radius / (v / units.metres_per_second)),
            )
        } else {
            let radius = S::one() / w_max;
            (radius, radius / v_max)
        };
        VehicleLimits {
            v_max,
            w_max,
            radius,
            seconds_per_radian,
        }
    }
}

impl<S: Scalar> Limits<S> {
    /// Validates limits given in m/s and 1/m.
    ///
    /// # Errors
    /// `NonFiniteInput` for NaN or infinity, `InvalidLimits` unless v_pm > v_em > 0 and
    /// w_pm > w_em > 0, `OutOfRange` for speeds above [`MAX_SPEED`] or below [`MIN_SPEED`],
    /// curvatures above [`MAX_CURVATURE`], radii above [`MAX_RADIUS`], or ratios outside the
    /// backend's envelope (`S::MAX_RADIUS_RATIO`, `S::MIN_SPEED_RATIO`, `S::MAX_SPEED_RATIO`).
    pub fn new(v_pm: f32, w_pm: f32, v_em: f32, w_em: f32) -> Result<Self, Error> {
        validate::<S>(v_pm, w_pm, v_em, w_em)?;
        let units = Units::of::<S>(v_pm, w_pm);
        let pursuer = if S::NORMALISED {
            // The units themselves: exactly one, so that the law skips its products by them
            // ([`Limits::pursuer_radius_times`], [`Limits::pursuer_turn_time`],
            // [`Limits::pursuer_run`]).
            let one = S::one();
            VehicleLimits {
                v_max: one,
                w_max: one,
                radius: one,
                seconds_per_radian: one,
            }
        } else {
            VehicleLimits::in_units(v_pm, w_pm, units)
        };
        let evader = VehicleLimits::in_units(v_em, w_em, units);
        let seconds_per_metre_closed = if S::NORMALISED {
            S::from_f32(1.0 / (1.0 - v_em / v_pm))
        } else {
            S::one() / (pursuer.v_max - evader.v_max)
        };
        let derived = [
            pursuer.seconds_per_radian,
            evader.seconds_per_radian,
            seconds_per_metre_closed,
        ];
        if !derived.iter().all(|v| v.is_valid()) {
            return Err(Error::OutOfRange);
        }
        Ok(Limits {
            pursuer,
            evader,
            units,
            seconds_per_metre_closed,
            per_metre: if S::NORMALISED {
                Reciprocal::of(units.metres)
            } else {
                Reciprocal::ONE
            },
        })
    }

    /// Both vehicles' states in the law's frame, from positions in metres and headings in
    /// radians anticlockwise from +x. SI backends take them as they are; a normalised backend
    /// takes positions relative to the pursuer in units of r_p, and headings reduced to
    /// [-pi, pi].
    ///
    /// # Errors
    /// `NonFiniteInput` for NaN or infinity; `OutOfRange` outside the f32 envelope
    /// (|x|, |y| <= 1e6 m, |theta| <= 1e4 rad) or the backend's (`S::MAX_COORDINATE` in the
    /// law's frame), or on a normalised backend where the players are apart by more than the
    /// capture radius but closer than the backend resolves (fixed point: both offsets below half
    /// a raw unit, 2^-15 r_p).
    #[inline(always)]
    pub fn states(
        &self,
        pursuer: [f32; 3],
        evader: [f32; 3],
    ) -> Result<(VehicleState<S>, VehicleState<S>), Error> {
        let [x_p, y_p, theta_p] = pursuer;
        let [x_e, y_e, theta_e] = evader;
        if !S::NORMALISED {
            return Ok((
                VehicleState::in_law_frame(x_p, y_p, theta_p)?,
                VehicleState::in_law_frame(x_e, y_e, theta_e)?,
            ));
        }
        // The metres envelope first, so that the differences below stay finite.
        f32_envelope(pursuer)?;
        f32_envelope(evader)?;
        let (dx, dy) = S::relative_position(
            (x_p, x_e),
            (y_p, y_e),
            self.units.metres,
            &self.per_metre,
            CAPTURE_RADIUS_FRACTION,
        )?;
        let c = S::from_f32(S::MAX_COORDINATE);
        if dx.abs() > c || dy.abs() > c {
            return Err(Error::OutOfRange);
        }
        let at = |x, y, theta| VehicleState { x, y, theta };
        Ok((
            at(S::zero(), S::zero(), S::reduced_heading(theta_p)),
            at(dx, dy, S::reduced_heading(theta_e)),
        ))
    }

    /// Both vehicles' states in the law's frame from states in the law's units that share an
    /// origin of their own ([`crate::estimate`]'s frame): SI backends take them as they are; a
    /// normalised backend takes the evader's offset from the pursuer, its headings reduced.
    ///
    /// # Errors
    /// `NonFiniteInput` for NaN or an invalid value; `OutOfRange` outside the backend's
    /// envelope (`S::MAX_COORDINATE` in the law's frame, `S::MAX_HEADING`).
    pub fn states_in_units(
        &self,
        pursuer: [S; 3],
        evader: [S; 3],
    ) -> Result<(VehicleState<S>, VehicleState<S>), Error> {
        let [x_p, y_p, theta_p] = pursuer;
        let [x_e, y_e, theta_e] = evader;
        if ![x_p, y_p, theta_p, x_e, y_e, theta_e]
            .iter()
            .all(|v| v.is_number())
        {
            return Err(Error::NonFiniteInput);
        }
        let at = |x, y, theta| VehicleState { x, y, theta };
        let c = S::from_f32(S::MAX_COORDINATE);
        if S::NORMALISED {
            // Both headings are reduced in that frame; the offset is what the backend holds.
            let (x, y) = (x_e - x_p, y_e - y_p);
            if x.abs() > c || y.abs() > c {
                return Err(Error::OutOfRange);
            }
            return Ok((at(S::zero(), S::zero(), theta_p), at(x, y, theta_e)));
        }
        let heading = S::from_f32(S::MAX_HEADING);
        let inside = [x_p, y_p, x_e, y_e].iter().all(|v| v.abs() <= c)
            && theta_p.abs() <= heading
            && theta_e.abs() <= heading;
        if !inside {
            return Err(Error::OutOfRange);
        }
        Ok((at(x_p, y_p, theta_p), at(x_e, y_e, theta_e)))
    }

    /// r_p x, metres for x in radians (or r_p times any factor): x itself on a normalised backend,
    /// whose unit of length is r_p (a product is a dozen instructions on a Cortex-M0).
    #[inline(always)]
    pub fn pursuer_radius_times(&self, x: S) -> S {
        if S::NORMALISED {
            x
        } else {
            self.pursuer.radius * x
        }
    }

    /// t_p = r_p alpha / v_pm, seconds: the time the pursuer turns through `arc` radians at full
    /// speed; `arc` itself on a normalised backend, whose unit of time is r_p / v_pm.
    #[inline(always)]
    pub fn pursuer_turn_time(&self, arc: S) -> S {
        if S::NORMALISED {
            arc
        } else {
            self.pursuer.seconds_per_radian * arc
        }
    }

    /// v_pm t, metres: how far the pursuer runs in `t` seconds; `t` itself on a normalised
    /// backend, whose unit of speed is v_pm.
    #[inline(always)]
    pub fn pursuer_run(&self, t: S) -> S {
        if S::NORMALISED {
            t
        } else {
            self.pursuer.v_max * t
        }
    }

    /// 1 / (v_pm - v_em), s/m: the time the pursuer needs to close one metre on a common line.
    pub fn seconds_per_metre_closed(&self) -> S {
        self.seconds_per_metre_closed
    }

    /// The theorem's distance threshold ([`theorem_threshold`]) of these limits, metres.
    pub fn theorem_threshold(&self) -> S {
        theorem_threshold(self.evader.radius, self.pursuer.v_max, self.evader.v_max)
    }
}

/// The theorem's distance threshold 2 r_e + 2 pi r_e v_pm / v_em, in the units of the evader's
/// turning radius `r_e`: at or above it the saddle-point strategies are circle-then-straight
/// (Theorems 2 and 3). The one formula the crate, its tables, its solver and its tools use.
pub fn theorem_threshold<S: Scalar>(r_e: S, v_pm: S, v_em: S) -> S {
    r_e + r_e + S::tau() * r_e * v_pm / v_em
}

/// The normalised backends' unit of length, metres: 1 / w_pm rounded up to an f32, so that one
/// unit of curvature, the pursuer's w_max there, is within the true w_pm.
fn length_unit(w_pm: f32) -> f32 {
    let metres = 1.0 / w_pm;
    if f64::from(metres) * f64::from(w_pm) < 1.0 {
        // The next f32 up (metres is positive and finite).
        f32::from_bits(metres.to_bits() + 1)
    } else {
        metres
    }
}

/// Position and heading of a vehicle in the law's frame: metres and radians anticlockwise
/// from +x on SI backends (f32, f64, micromath); on fixed point, relative to the pursuer in
/// units of its turning radius. States come from metres through [`Limits::states`], which
/// converts for each backend; there is no constructor that takes metres on one backend and
/// something else on another:
///
/// ```compile_fail
/// // Metres given to fixed point as if they were its frame: does not compile.
/// let state = twocars::VehicleState::<twocars::Fixed>::new(3.0, 4.0, 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VehicleState<S> {
    /// x in the law's frame (metres on SI backends).
    pub x: S,
    /// y in the law's frame (metres on SI backends).
    pub y: S,
    /// Heading, radians anticlockwise from +x.
    pub theta: S,
}

impl<S: Scalar> VehicleState<S> {
    /// Validates and converts a state given in the law's frame: metres and radians on SI
    /// backends. Callers outside the crate give metres to [`Limits::states`], which converts
    /// for every backend.
    ///
    /// # Errors
    /// `NonFiniteInput` for NaN or infinity; `OutOfRange` outside the backend's envelope
    /// (`S::MAX_COORDINATE`, `S::MAX_HEADING`).
    pub(crate) fn in_law_frame(x: f32, y: f32, theta: f32) -> Result<Self, Error> {
        if !(x.is_finite() && y.is_finite() && theta.is_finite()) {
            return Err(Error::NonFiniteInput);
        }
        let c = S::MAX_COORDINATE;
        if x.abs() > c || y.abs() > c || theta.abs() > S::MAX_HEADING {
            return Err(Error::OutOfRange);
        }
        Ok(VehicleState {
            x: S::from_f32(x),
            y: S::from_f32(y),
            theta: S::from_f32(theta),
        })
    }

    /// Position, metres.
    pub fn position(&self) -> Point<S> {
        Point {
            x: self.x,
            y: self.y,
        }
    }
}

/// A minimum-radius turning circle of a vehicle at the current instant.
///
/// Kept as the vehicle's position plus a radius along its left normal, so that differences
/// between circles are formed from differences of positions and of headings, without the
/// cancellation of subtracting nearly equal centres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurningCircle<S> {
    /// Position of the vehicle on the circle, metres.
    pub position: Point<S>,
    /// The vehicle's left unit normal (-sin theta, cos theta).
    pub normal: Point<S>,
    /// Radius 1 / w_max, metres.
    pub radius: S,
    /// Direction the vehicle turns on it.
    pub direction: Direction,
}

impl<S: Scalar> TurningCircle<S> {
    /// The A and C circles of a vehicle (in that order), sharing one sine/cosine of its heading.
    /// Centres: A at (x - r sin theta, y + r cos theta), C at (x + r sin theta, y - r cos theta).
    pub fn both(state: &VehicleState<S>, limits: &VehicleLimits<S>) -> [TurningCircle<S>; 2] {
        let (sin, cos) = state.theta.sin_cos();
        let circle = |direction: Direction| TurningCircle {
            position: state.position(),
            normal: Point { x: -sin, y: cos },
            radius: limits.radius,
            direction,
        };
        [
            circle(Direction::Anticlockwise),
            circle(Direction::Clockwise),
        ]
    }

    /// sigma r: the signed radius along the left normal, metres.
    fn signed_radius(&self) -> S {
        self.direction.signed(self.radius)
    }

    /// Centre of the circle, metres: position + sigma r (-sin theta, cos theta).
    pub fn centre(&self) -> Point<S> {
        let sr = self.signed_radius();
        Point {
            x: self.position.x + sr * self.normal.x,
            y: self.position.y + sr * self.normal.y,
        }
    }

    /// The point of this circle where a vehicle moving in the circle's direction has heading
    /// (cos psi, sin psi): centre + sigma r (sin psi, -cos psi).
    pub fn point_with_heading(&self, sin_psi: S, cos_psi: S) -> Point<S> {
        let sr = self.signed_radius();
        let centre = self.centre();
        Point {
            x: centre.x + sr * sin_psi,
            y: centre.y - sr * cos_psi,
        }
    }
}

/// What the four valid tangents between a pursuer's and an evader's circles share: Algorithm 1
/// for all four pairs from one sine and cosine per vehicle.
///
/// With D = O_e - O_p (the centres) and k = sigma_e r_e - sigma_p r_p, a pair's tangent exists iff
/// |D| >= |k| and |D| > 0; its length is L = sqrt(|D|^2 - k^2). L^2 is formed without the
/// cancellation of subtracting nearly equal centres: with Delta = position_e - position_p and n the
/// left unit normals,
/// |D|^2 - k^2 = |Delta|^2 + 2 (sigma_e r_e Delta . n_e - sigma_p r_p Delta . n_p)
///   + sigma_e sigma_p r_e r_p |n_e - n_p|^2.
///
/// The four pairs' L^2, D and k are formed here, straight-line, so that a pair only reads its own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CirclePairs<S> {
    /// The pursuer's and the evader's headings reduced to [-pi, pi], radians.
    pub pursuer_heading: S,
    /// See `pursuer_heading`.
    pub evader_heading: S,
    /// Per pair `[pursuer circle][evader circle]` (A, C).
    pairs: [[PairTerms<S>; 2]; 2],
}

/// L^2 (square metres), D and k (metres) of one pair of circles.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PairTerms<S> {
    length_sq: S,
    d: Point<S>,
    k: S,
}

impl<S: Scalar> CirclePairs<S> {
    /// The shared terms of a pursuer and an evader.
    pub fn new(pursuer: &VehicleState<S>, evader: &VehicleState<S>, limits: &Limits<S>) -> Self {
        let (sin_p, cos_p) = pursuer.theta.sin_cos();
        let (sin_e, cos_e) = evader.theta.sin_cos();
        let (r_p, r_e) = (limits.pursuer.radius, limits.evader.radius);
        let delta = Point {
            x: evader.x - pursuer.x,
            y: evader.y - pursuer.y,
        };
        // r_p n_p and r_e n_e, metres.
        let pursuer_offset = Point {
            x: -limits.pursuer_radius_times(sin_p),
            y: limits.pursuer_radius_times(cos_p),
        };
        let evader_offset = Point {
            x: -r_e.mul_small(sin_e),
            y: r_e.mul_small(cos_e),
        };
        let delta_sq = delta.x * delta.x + delta.y * delta.y;
        // Delta . r_p n_p and Delta . r_e n_e, square metres (r_p n_p is a unit vector on a
        // normalised backend).
        let delta_pursuer =
            delta.x.mul_small(pursuer_offset.x) + delta.y.mul_small(pursuer_offset.y);
        let delta_evader = delta.x * evader_offset.x + delta.y * evader_offset.y;
        // r_e r_p |n_e - n_p|^2, square metres.
        let (dn_x, dn_y) = (cos_p - cos_e, sin_e - sin_p);
        let normals = limits
            .pursuer_radius_times(r_e)
            .mul_small(dn_x.mul_small(dn_x) + dn_y.mul_small(dn_y));
        let terms = |pursuer: Direction, evader: Direction| {
            let cross = if pursuer == evader { normals } else { -normals };
            let linear = evader.signed(delta_evader) - pursuer.signed(delta_pursuer);
            PairTerms {
                length_sq: delta_sq + (linear + linear) + cross,
                d: Point {
                    x: delta.x + evader.signed(evader_offset.x) - pursuer.signed(pursuer_offset.x),
                    y: delta.y + evader.signed(evader_offset.y) - pursuer.signed(pursuer_offset.y),
                },
                k: evader.signed(r_e) - pursuer.signed(r_p),
            }
        };
        let (a, c) = (Direction::Anticlockwise, Direction::Clockwise);
        CirclePairs {
            pursuer_heading: pursuer.theta.wrap_signed(),
            evader_heading: evader.theta.wrap_signed(),
            pairs: [[terms(a, a), terms(a, c)], [terms(c, a), terms(c, c)]],
        }
    }

    /// The valid tangent from the pursuer's `pursuer` circle to the evader's `evader` circle, or
    /// `None` where it does not exist.
    pub fn tangent(&self, pursuer: Direction, evader: Direction) -> Option<ValidTangent<S>> {
        // Indexed, not matched: an address computation where a match is two compares and selects.
        let terms = &self.pairs[pursuer as usize][evader as usize];
        ValidTangent::from_terms(terms.length_sq, terms.d.x, terms.d.y, terms.k)
    }
}

/// The valid directed common tangent of a PE pair (Algorithm 1): it leaves the pursuer circle and
/// meets the evader circle, each in that circle's turning direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValidTangent<S> {
    /// Heading of the tangent, radians in (-pi, pi], anticlockwise from +x.
    pub heading: S,
    /// Length from the pursuer's tangent point to the evader's, metres.
    pub length: S,
}

impl<S: Scalar> ValidTangent<S> {
    /// The tangent from L^2 = |D|^2 - k^2, D = (dx, dy) and k (metres), or `None` where it does
    /// not exist. Its direction is (L D + k D_perp) / |D|^2 with D_perp = (D_y, -D_x), so that
    /// |D| sin(psi - atan2(D)) = -k.
    fn from_terms(length_sq: S, dx: S, dy: S, k: S) -> Option<Self> {
        let zero = S::zero();
        // No tangent inside the other circle (L^2 < 0), nor for coincident circles (D = 0, so
        // L = k = 0; without a product: k is r_e +- r_p, never 0 under Assumption 1). The
        // common case first: on a Cortex-M4F the square root's own guard then folds away.
        let length = if length_sq > zero {
            length_sq.sqrt()
        } else if length_sq == zero && k != zero {
            zero
        } else {
            return None;
        };
        // The heading of (L D + k D_perp) / |D|^2, which needs no normalisation.
        Some(ValidTangent {
            heading: S::tangent_heading(length, k, dx, dy),
            length,
        })
    }

    /// The tangent points on the pursuer's and the evader's circle (the circles this tangent
    /// was computed for), metres.
    pub fn points(
        &self,
        pursuer: &TurningCircle<S>,
        evader: &TurningCircle<S>,
    ) -> (Point<S>, Point<S>) {
        let (sin_psi, cos_psi) = self.heading.sin_cos();
        (
            pursuer.point_with_heading(sin_psi, cos_psi),
            evader.point_with_heading(sin_psi, cos_psi),
        )
    }
}
