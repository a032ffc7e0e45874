//! Status codes of the law, named as in the contract (`docs/contract.md`).

/// Outcome class of one evaluation of the law; every status other than `Ok` comes with a safe
/// command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Status {
    /// Valid input and a finite upper value: the law's command.
    Ok,
    /// NaN or infinity in an input field: command 0, 0.
    NonFiniteInput,
    /// Not (v_pm > v_em > 0 and w_pm > w_em > 0): command 0, 0.
    InvalidLimits,
    /// Outside the backend's documented envelope: command 0, 0.
    OutOfRange,
    /// Pursuer and evader positions coincide (distance <= 1e-6 r_p): command 0, 0.
    Captured,
    /// Valid input but upper value infinite (every pursuer row has a pair without a valid
    /// tangent): the documented fallback command (pursuer toward the evader, evader away).
    NoValidTangent,
}

impl Status {
    /// Whether an evaluation with this status has a game (`Ok`, `NoValidTangent`): the four
    /// pairs and a solution.
    pub fn has_game(self) -> bool {
        matches!(self, Status::Ok | Status::NoValidTangent)
    }

    /// The contract's name of the status, as printed in the CSV doors.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::NonFiniteInput => "non_finite_input",
            Status::InvalidLimits => "invalid_limits",
            Status::OutOfRange => "out_of_range",
            Status::Captured => "captured",
            Status::NoValidTangent => "no_valid_tangent",
        }
    }
}
