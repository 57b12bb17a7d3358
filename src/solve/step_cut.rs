//! Cutting an attempt at an event crossing, shared by the methods that do it (Radau5, the
//! explicit pairs): an attempt that crosses an event (an impact, a kink of the friction law)
//! is retried ending just past the earliest crossing, found by bisection on the attempt's own
//! continuous output, so that only a sliver of the step lies under the other law (see
//! `radau5/core.rs` and `explicit.rs` for why each method needs it).

/// Halvings of the bisection for the crossing (2⁻⁴⁰ of the step).
const HALVINGS: usize = 40;
/// An attempt is cut only if the crossing lies at a fraction θ of the step in
/// [`MIN_CUT`, `MAX_CUT`): near either end the other law holds on a sliver only, and near the
/// start a cut would shrink the step to that sliver.
const MIN_CUT: f64 = 0.01;
/// See [`MIN_CUT`].
const MAX_CUT: f64 = 0.99;
/// The retry ends past the crossing by this fraction of the way to it (the retry's own
/// crossing moves by its error).
const OVERSHOOT: f64 = 1.001;

/// Whether a and b lie strictly on opposite sides of zero.
pub(crate) fn crossed(a: f64, b: f64) -> bool {
    (a < 0.0 && b > 0.0) || (a > 0.0 && b < 0.0)
}

/// The end of the bracket [lo, hi] after [`HALVINGS`] halvings towards the earliest point
/// where `crossed_by(mid)` holds (it holds at `hi`, not at `lo`). Each method bisects in its
/// own parameter of the step (the explicit pairs θ ∈ [0, 1], Radau5 s ∈ [−1, 0]), so that its
/// probes stay the ones it always evaluated.
pub(crate) fn earliest_crossing(
    (mut lo, mut hi): (f64, f64),
    mut crossed_by: impl FnMut(f64) -> bool,
) -> f64 {
    for _ in 0..HALVINGS {
        let mid = 0.5 * (lo + hi);
        if crossed_by(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The step size of the retry for a crossing at the fraction `theta` of an attempt of size `h`
/// from `t`, or `None` where the attempt stays as it is (a crossing in the first or last 1 %,
/// or a cut step below the driver's floor of a few ulps of t).
pub(crate) fn cut_step(t: f64, h: f64, theta: f64) -> Option<f64> {
    let h_cut = h * theta * OVERSHOOT;
    let floor = 64.0 * f64::EPSILON * t.abs().max(h.abs());
    ((MIN_CUT..MAX_CUT).contains(&theta) && h_cut.abs() > floor).then_some(h_cut)
}
