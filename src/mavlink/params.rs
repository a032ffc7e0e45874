//! The endpoint's parameters (docs/mavlink.md): sixteen REAL32 values (eighteen with the
//! `mavlink-team` feature)
//! read and set by name or index, each checked against its range, the limits also as a whole.

use crate::law::geometry::Limits;

/// One parameter's name, default and admissible range (inclusive); `integer` ones take whole
/// numbers only (ids and enumerations, carried as REAL32 like every parameter here).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spec {
    /// The MAVLink parameter id (at most 16 characters).
    pub name: &'static str,
    /// The value at start.
    pub default: f32,
    /// The smallest admissible value.
    pub min: f32,
    /// The largest admissible value.
    pub max: f32,
    /// Whole numbers only.
    pub integer: bool,
}

const fn real(name: &'static str, default: f32, min: f32, max: f32) -> Spec {
    Spec {
        name,
        default,
        min,
        max,
        integer: false,
    }
}

const fn whole(name: &'static str, default: f32, min: f32, max: f32) -> Spec {
    Spec {
        name,
        default,
        min,
        max,
        integer: true,
    }
}

/// Index of each parameter in [`SPECS`] (the PARAM_VALUE index).
pub mod index {
    /// The pursuer's speed, m/s.
    pub const V_PM: usize = 0;
    /// The pursuer's largest curvature, 1/m.
    pub const W_PM: usize = 1;
    /// The evader's speed, m/s.
    pub const V_EM: usize = 2;
    /// The evader's largest curvature, 1/m.
    pub const W_EM: usize = 3;
    /// The target's system id.
    pub const TGT_SYSID: usize = 4;
    /// 0 ground vehicle (yaw rate), 1 fixed wing (bank angle), 2 ground vehicle by velocity
    /// (PX4 rovers), 3 fixed wing by roll alone (the autopilot holds airspeed and height), 4
    /// fixed wing with the unit's energy hold (PX4 in offboard).
    pub const VEHICLE: usize = 5;
    /// The Configure policy byte: 0 paper, 1 flight.
    pub const POLICY: usize = 6;
    /// Staleness limit of both states, s.
    pub const TIMEOUT: usize = 7;
    /// Our system id (the autopilot's).
    pub const SYSID: usize = 8;
    /// The capture radius the flight policy homes to, m (0: the paper's point capture).
    pub const CAPTURE: usize = 9;
    /// The guidance period, s: the shortest time a turn is planned over (0: the own states'
    /// spacing).
    pub const PERIOD: usize = 10;
    /// The target fixes' transport lag, s: from when the target was there to when its fix
    /// arrives.
    pub const TGT_LAG: usize = 11;
    /// One sigma of the target fixes' position, m.
    pub const TGT_SIG: usize = 12;
    /// One sigma of the target fixes' heading, rad.
    pub const TGT_SIGH: usize = 13;
    /// How long after a setpoint the vehicle turns as told, s: both states are carried that
    /// far ahead.
    pub const LEAD: usize = 14;
    /// The share of a coordinated turn's rate the aircraft makes at a bank: the bank for turn
    /// rate omega is atan(v_pm omega / (TC_BANK_EFF g)).
    pub const BANK_EFF: usize = 15;
    /// The first system id of the unit's team of pursuers (docs/team.md).
    #[cfg(feature = "mavlink-team")]
    pub const TEAM_SYS: usize = 16;
    /// How many pursuers the team has, consecutive system ids from TC_TEAM_SYS, this unit's
    /// TC_SYSID among them (below 2: no team).
    #[cfg(feature = "mavlink-team")]
    pub const TEAM_N: usize = 17;
}

/// Every parameter, in index order. Speeds and curvatures span the law's envelope
/// ([`crate::law::geometry::MAX_SPEED`] and its kin); the limits are also checked together.
pub const SPECS: [Spec; 16 + TEAM_SPECS.len()] = with_team([
    real("TC_V_PM", 2.0, 1.0e-3, 1.0e4),
    real("TC_W_PM", 2.0, 1.0e-4, 1.0e4),
    real("TC_V_EM", 1.0, 1.0e-3, 1.0e4),
    real("TC_W_EM", 1.0, 1.0e-4, 1.0e4),
    whole("TC_TGT_SYSID", 2.0, 1.0, 255.0),
    whole("TC_VEHICLE", 0.0, 0.0, 4.0),
    whole("TC_POLICY", 1.0, 0.0, 1.0),
    real("TC_TIMEOUT", 1.0, 0.01, 60.0),
    whole("TC_SYSID", 1.0, 1.0, 255.0),
    real("TC_CAPTURE", 0.0, 0.0, 100.0),
    real("TC_PERIOD", 0.0, 0.0, 1.0),
    real("TC_TGT_LAG", 0.0, 0.0, 5.0),
    real("TC_TGT_SIG", 0.0, 0.0, 100.0),
    real("TC_TGT_SIGH", 0.0, 0.0, 3.0),
    real("TC_LEAD", 0.0, 0.0, 5.0),
    real("TC_BANK_EFF", 1.0, 0.1, 2.0),
]);

/// The team's parameters, after the others (`mavlink-team`).
#[cfg(feature = "mavlink-team")]
const TEAM_SPECS: [Spec; 2] = [
    whole("TC_TEAM_SYS", 0.0, 0.0, 255.0),
    whole("TC_TEAM_N", 0.0, 0.0, 8.0),
];
#[cfg(not(feature = "mavlink-team"))]
const TEAM_SPECS: [Spec; 0] = [];

/// `base` followed by [`TEAM_SPECS`].
const fn with_team<const N: usize>(base: [Spec; 16]) -> [Spec; N] {
    let mut out = [base[0]; N];
    let mut i = 0;
    while i < N {
        out[i] = if i < 16 { base[i] } else { TEAM_SPECS[i - 16] };
        i += 1;
    }
    out
}

/// Why a PARAM_SET was refused (the STATUSTEXT says which).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// No parameter of that name.
    UnknownName,
    /// Not finite, outside the parameter's range, or not whole where it must be.
    OutOfRange,
    /// The four limits would break v_pm > v_em > 0, w_pm > w_em > 0 or the law's envelope.
    InvalidLimits,
    /// TC_TGT_LAG or TC_LEAD would reach TC_TIMEOUT: a fix would be stale when it acts.
    LagBeyondTimeout,
}

impl Refusal {
    /// The STATUSTEXT's words.
    pub fn text(self) -> &'static str {
        match self {
            Refusal::UnknownName => "TC: no such parameter",
            Refusal::OutOfRange => "TC: parameter out of range, kept",
            Refusal::InvalidLimits => "TC: limits invalid (need v_pm>v_em, w_pm>w_em)",
            Refusal::LagBeyondTimeout => "TC: lag and lead must stay below TC_TIMEOUT",
        }
    }
}

/// The parameters' values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    values: [f32; SPECS.len()],
}

impl Default for Params {
    fn default() -> Self {
        Self::new()
    }
}

impl Params {
    /// Every parameter at its default.
    pub const fn new() -> Self {
        let mut values = [0.0; SPECS.len()];
        let mut i = 0;
        while i < SPECS.len() {
            values[i] = SPECS[i].default;
            i += 1;
        }
        Params { values }
    }

    /// The index of the parameter named `name` (the bytes of a MAVLink param_id, up to the
    /// first NUL).
    pub fn find(name: &[u8]) -> Option<usize> {
        let end = name.iter().position(|&b| b == 0).unwrap_or(name.len());
        let name = name.get(..end)?;
        SPECS.iter().position(|s| s.name.as_bytes() == name)
    }

    /// The value at `index`.
    pub fn get(&self, index: usize) -> Option<f32> {
        self.values.get(index).copied()
    }

    /// Sets the value at `index` if it is admissible; otherwise keeps the old one.
    ///
    /// # Errors
    /// The [`Refusal`].
    pub fn set(&mut self, index: usize, value: f32) -> Result<(), Refusal> {
        self.set_all(&[(index, value)])
            .map_err(|(_, refusal)| refusal)
    }

    /// Whether `value` is in range (finite, within the parameter's bounds, whole where it must
    /// be) for the parameter at `index`, alone.
    ///
    /// # Errors
    /// [`Refusal::UnknownName`] or [`Refusal::OutOfRange`].
    pub fn admissible(index: usize, value: f32) -> Result<(), Refusal> {
        let spec = SPECS.get(index).ok_or(Refusal::UnknownName)?;
        let whole = value == libm::truncf(value);
        if !(value >= spec.min && value <= spec.max) || (spec.integer && !whole) {
            return Err(Refusal::OutOfRange);
        }
        Ok(())
    }

    /// Sets every (index, value) of `values` together, later ones over earlier ones, if each is
    /// admissible and the set is valid together (the limits, lag and lead below the timeout);
    /// otherwise keeps every old value. The order they are given in does not matter: a set of
    /// limits that is valid as a whole is taken even where one of them alone would not be.
    ///
    /// # Errors
    /// The first value out of range, with its place in `values`; or, with no place, the
    /// [`Refusal`] of the set as a whole.
    pub fn set_all(&mut self, values: &[(usize, f32)]) -> Result<(), (Option<usize>, Refusal)> {
        let mut next = *self;
        for (place, &(index, value)) in values.iter().enumerate() {
            Self::admissible(index, value).map_err(|refusal| (Some(place), refusal))?;
            if let Some(slot) = next.values.get_mut(index) {
                *slot = value;
            }
        }
        next.limits().ok_or((None, Refusal::InvalidLimits))?;
        let timeout = next.get(index::TIMEOUT).unwrap_or(0.0);
        let below = |i| next.get(i).is_some_and(|v| v < timeout);
        if !(below(index::TGT_LAG) && below(index::LEAD)) {
            return Err((None, Refusal::LagBeyondTimeout));
        }
        *self = next;
        Ok(())
    }

    /// The limits v_pm, w_pm, v_em, w_em; `None` if they are not valid together (never after
    /// [`Params::set`], which keeps them valid).
    pub fn limits(&self) -> Option<Limits<f32>> {
        let [v_pm, w_pm, v_em, w_em, ..] = self.values;
        Limits::new(v_pm, w_pm, v_em, w_em).ok()
    }

    /// The limits as SI values: v_pm, w_pm, v_em, w_em (m/s, 1/m); `None` as for
    /// [`Params::limits`].
    pub fn limits_si(&self) -> Option<[f32; 4]> {
        let [v_pm, w_pm, v_em, w_em, ..] = self.values;
        self.limits().map(|_| [v_pm, w_pm, v_em, w_em])
    }

    /// A whole-number parameter as a byte (ids, vehicle kind, policy).
    pub fn byte(&self, index: usize) -> u8 {
        // In range by `set`: 0 to 255.
        self.get(index).map_or(0, |v| v as u8)
    }

    /// The staleness limit in milliseconds.
    pub fn timeout_ms(&self) -> u32 {
        self.get(index::TIMEOUT)
            .map_or(1000, |s| (s * 1000.0) as u32)
    }
}
