//! The regularised pivot rule of a smooth modified Cholesky: a raw pivot d (diagonal entry s,
//! shift μ > 0) becomes d + μ³/(d + μ)², so that a pivot collapsing at a singular position
//! stays near μ and the solve stays bounded, while a healthy one keeps its value to the bit.
//! Used through the `pivot` argument of [`super::cholesky::factor_with`] and
//! [`super::skyline::factor_with`] by the DAE's Schur complement
//! (`formulation/schur.rs`, `Schur::factor_regularised`, which documents the rule).

/// Raw pivots above this multiple of their shift μ are used as they are by [`regularised`]:
/// there μ³/(d + μ)² < 1e-18 d, which adding to d cannot change.
pub const HEALTHY_PIVOT: f64 = 1e6;

/// The pivot rule of `Schur::factor_regularised` for [`super::cholesky::factor_with`] and
/// [`super::skyline::factor_with`]: the raw pivot d of a row (diagonal entry s, shift μ) becomes
/// d + μ³/(d + μ)², `None` where d ≤ −μ or the result is not positive (NaN); `min_ratio` keeps
/// the smallest d/s (`Schur::min_pivot_ratio`), `sum` gets d + μ, from which
/// `Schur::factor_regularised` records the shift [`shift_of`] once the factor is done
/// (`Schur::regularisation`).
pub fn regularised(
    min_ratio: &mut f64,
    raw: f64,
    diagonal: f64,
    shift: f64,
    sum: &mut f64,
) -> Option<f64> {
    // A division only where the ratio may be a new minimum (rarely after the first rows):
    // the test lets through every d/s below the minimum and a few rounding ties above it,
    // which `min` then settles exactly as before.
    let bound = *min_ratio * diagonal;
    if raw <= bound + 1e-12 * bound.abs() {
        *min_ratio = min_ratio.min(raw / diagonal);
    }
    *sum = raw + shift;
    // NaN fails too.
    if (*sum).partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    if raw > HEALTHY_PIVOT * shift {
        // Δ < μ³/d² < 1e-18 d, below half an ulp of d: d + Δ rounds to d, so the pivot is d
        // without waiting for a division (the next row's elimination waits for this pivot).
        return Some(raw);
    }
    // μ³/(d + μ)²: a healthy pivot moves by a relative (μ/d)³, below half an ulp wherever
    // d ≳ 2e-3 D at μ = 1e-8 D, so regular linkages keep the arithmetic of the unregularised
    // solve bit for bit; a collapsed one (d → 0) becomes μ (at least 0.89 μ on the way).
    let d = raw + shift_of(shift, *sum);
    if d.is_nan() || d <= 0.0 {
        None
    } else {
        Some(d)
    }
}

/// The shift Δ = μ³/(d + μ)² that [`regularised`] adds to a raw pivot d, from μ and d + μ.
pub fn shift_of(mu: f64, sum: f64) -> f64 {
    mu * mu * mu / (sum * sum)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulation::test_rng::Lcg;

    /// The pivot rule without its two divisions on the elimination's path: a healthy pivot (more
    /// than [`HEALTHY_PIVOT`] times its shift) is taken as it is, which must be d + μ³/(d + μ)²
    /// to the bit (below the threshold the full rule applies), and the smallest ratio d/s is found
    /// with a division only where it may fall, which must give the minimum of every ratio exactly.
    /// Pivots over 30 decades around each shift, ratios drawn near each other so that rounding
    /// ties occur.
    #[test]
    fn the_pivot_rule_is_exact_without_its_divisions() {
        let mut rng = Lcg(7);
        let (mut ratio, mut plain_ratio) = (1.0, 1.0_f64);
        for k in 0..20_000 {
            let shift = 10f64.powf(-12.0 + 8.0 * rng.next());
            let raw = shift * 10f64.powf(-2.0 + 30.0 * rng.next());
            let diagonal = if k % 2 == 0 {
                raw * (1.0 + rng.next())
            } else {
                // Near the smallest ratio so far: d/s within a few ulps of it.
                raw / (plain_ratio * (1.0 + 4.0 * f64::EPSILON * (rng.next() - 0.5)))
            };
            let mut sum = f64::NAN;
            let pivot = regularised(&mut ratio, raw, diagonal, shift, &mut sum);
            plain_ratio = plain_ratio.min(raw / diagonal);
            let full = raw + shift * shift * shift / ((raw + shift) * (raw + shift));
            assert_eq!(pivot, Some(full), "raw {raw:e}, shift {shift:e}");
            assert_eq!(sum, raw + shift);
            assert_eq!(shift_of(shift, sum), shift * shift * shift / (sum * sum));
            assert_eq!(ratio, plain_ratio, "step {k}");
        }
    }
}
