//! [`OverBudget`]: the one refusal every geometry module gives when an
//! input would take more memory or work than a budget allows. It was
//! written four times (gc, sculpt, styling, sdf) with three field sets
//! and three number formats (issue 36); each module's error now wraps
//! this one, and each module keeps its own limits (`gc::budget`,
//! `sculpt::budget`, `styling::budget`, `sdf::budget`).

use thiserror::Error;

/// The longest any accepted op may be estimated to take on this machine
/// (issue 37); each module's time estimate refuses past it.
pub const MAX_SECONDS: f64 = 10.0;

/// An input asks for more memory or work than a budget allows: reduce or
/// fix the parameter named.
#[derive(Clone, Debug, PartialEq, Error)]
#[error("{parameter}: {what} would be {}, over the limit of {}", numbers(*.estimate, *.limit).0, numbers(*.estimate, *.limit).1)]
pub struct OverBudget {
    /// The op parameter that sized the request (`sections`,
    /// `warp.delta`, `step`).
    pub parameter: String,
    /// What was estimated.
    pub what: &'static str,
    /// The estimate (may be infinite or NaN: an input of infinite size).
    pub estimate: f64,
    /// The limit.
    pub limit: f64,
}

impl OverBudget {
    /// `parameter` would make `what` `estimate`, over `limit`.
    pub fn new(
        parameter: impl Into<String>,
        what: &'static str,
        estimate: f64,
        limit: f64,
    ) -> Self {
        Self {
            parameter: parameter.into(),
            what,
            estimate,
            limit,
        }
    }
}

/// An estimate and its limit for a message, in one form: whole numbers as
/// they are when both are whole (the exponent form rounded 4,000,130 and
/// 4,001,280 to digits that read the wrong way round), else both to five
/// significant digits, so "2.1347e9" never stands beside "2000000000";
/// but both to two decimals when both are between 0.01 and 10,000 (a
/// time in seconds reads "12.13, over the limit of 10.00", not
/// "1.2126e1").
fn numbers(estimate: f64, limit: f64) -> (String, String) {
    let whole = |x: f64| x.is_finite() && x.fract() == 0.0 && x.abs() < 1e15;
    let plain = |x: f64| (0.01..1e4).contains(&x.abs());
    // Two decimals, or as many more (up to six) as it takes for two
    // different numbers not to print the same.
    let decimals = (2..=6)
        .find(|&d| estimate == limit || format!("{estimate:.d$}") != format!("{limit:.d$}"))
        .unwrap_or(6);
    let one = |x: f64| {
        if whole(estimate) && whole(limit) {
            format!("{x:.0}")
        } else if plain(estimate) && plain(limit) {
            format!("{x:.decimals$}")
        } else if x.is_finite() {
            format!("{x:.4e}")
        } else {
            format!("{x}")
        }
    };
    (one(estimate), one(limit))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_message_names_the_parameter_and_both_numbers() {
        let e = OverBudget::new("sections", "the number of key sections", 300.0, 256.0);
        assert_eq!(
            e.to_string(),
            "sections: the number of key sections would be 300, over the limit of 256"
        );
        let e = OverBudget::new("warp.delta", "the work", 3.939124e6 + 0.5, f64::INFINITY);
        assert_eq!(
            e.to_string(),
            "warp.delta: the work would be 3.9391e6, over the limit of inf"
        );
        let e = OverBudget::new("sections", "the skin's flops", 2.1347e9 + 0.25, 2e9);
        assert_eq!(
            e.to_string(),
            "sections: the skin's flops would be 2.1347e9, over the limit of 2.0000e9"
        );
        let e = OverBudget::new("parts", "the seconds", 12.126, 10.0);
        assert_eq!(
            e.to_string(),
            "parts: the seconds would be 12.13, over the limit of 10.00"
        );
        let e = OverBudget::new("parts", "the seconds", 10.004, 10.0);
        assert_eq!(
            e.to_string(),
            "parts: the seconds would be 10.004, over the limit of 10.000"
        );
    }
}
