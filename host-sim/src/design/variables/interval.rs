//! A decision variable's interval: the map from the optimiser's `[0, 1]` onto a physical value,
//! linear or on a log scale, and back. Every variable of the design (the attitude law's, the
//! vertical channel's, the local regime's) is mapped through it.

/// `(low, high, logarithmic)`: the values a variable takes, `low` at 0 and `high` at 1; with a
/// log scale equal steps in `[0, 1]` are equal ratios (`low > 0` then).
pub(crate) type Interval = (f64, f64, bool);

/// The value at `x` (clamped into `[0, 1]`) of `interval`.
pub(crate) fn value_in((lo, hi, log): Interval, x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    if log {
        (lo.ln() + x * (hi.ln() - lo.ln())).exp()
    } else {
        lo + x * (hi - lo)
    }
}

/// Where `v` sits in `interval`, clamped into `[0, 1]` (the inverse of [`value_in`] inside it).
pub(crate) fn unit_in((lo, hi, log): Interval, v: f64) -> f64 {
    let x = if log {
        (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
    } else {
        (v - lo) / (hi - lo)
    };
    x.clamp(0.0, 1.0)
}
