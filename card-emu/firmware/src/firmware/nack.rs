//! The card's nack for each refusal of the motion algorithms, shared by the command manager,
//! the axes and the groups.

use firmware_proto::NackCode;

/// [`scurve::check_limits`](crate::motion::scurve::check_limits) with the card's nack codes.
pub(crate) fn check_ranges(rate_hz: u32, limits: &[(i32, f64)]) -> Result<(), NackCode> {
    crate::motion::scurve::check_limits(limits, rate_hz).map_err(plan_nack)
}

/// The nack for a planner refusal.
pub(crate) fn plan_nack(e: crate::motion::scurve::PlanError) -> NackCode {
    use crate::motion::scurve::PlanError;
    match e {
        PlanError::NonFinite => NackCode::NotFinite,
        PlanError::NonPositiveLimit => NackCode::NonPositiveLimit,
        PlanError::Infeasible | PlanError::StartVelocityTooHigh => NackCode::Infeasible,
        PlanError::LimitRange => NackCode::LimitRange,
        PlanError::PlanCheck => NackCode::PlanCheck,
    }
}
