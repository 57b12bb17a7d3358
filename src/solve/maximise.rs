//! The maximum of a unimodal function on an interval by golden-section search: the true peak
//! of an impact's normal force inside a step ([`crate::simulation::impacts`]) and of a
//! contact's penetration inside a step of a shot ([`crate::analysis::orbit::shoot_watching`]).

/// Finds the maximum of `f` on [lo, hi] by golden-section search, stopping when the bracket is
/// narrower than `t_tol`; returns (t, f(t)) of the best point evaluated (for a unimodal f, t is
/// within `t_tol` of the maximiser). Costs about log(( hi − lo)/t_tol)/log(φ) + 2 evaluations
/// (φ = 1.618…).
///
/// Errors: the first error of `f`.
pub fn maximise<E>(
    mut f: impl FnMut(f64) -> Result<f64, E>,
    lo: f64,
    hi: f64,
    t_tol: f64,
) -> Result<(f64, f64), E> {
    // 1/φ: each iteration keeps this fraction of the bracket and reuses one interior point.
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (lo.min(hi), lo.max(hi));
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (f(c)?, f(d)?);
    let mut best = if fc >= fd { (c, fc) } else { (d, fd) };
    // The bracket shrinks geometrically; the cap only guards against a NaN width.
    for _ in 0..200 {
        if (b - a).partial_cmp(&t_tol) != Some(std::cmp::Ordering::Greater) {
            break;
        }
        if fc >= fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c)?;
            if fc > best.1 {
                best = (c, fc);
            }
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d)?;
            if fd > best.1 {
                best = (d, fd);
            }
        }
    }
    Ok(best)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn golden_section_finds_the_maximum_of_a_known_function() {
        // f(t) = 3 − (t − 0.3)² on [0, 1]: maximum 3 at t = 0.3.
        let mut calls = 0;
        let r: Result<_, ()> = maximise(
            |t| {
                calls += 1;
                Ok(3.0 - (t - 0.3) * (t - 0.3))
            },
            0.0,
            1.0,
            1e-8,
        );
        let (t, v) = r.unwrap_or_default();
        // The bracket ends narrower than 1e-8, so |t − 0.3| < 1e-8 and f within 1e-16 of 3
        // (rounding of 3 − tiny: a few ulps).
        assert!((t - 0.3).abs() < 1e-8, "t = {t} vs 0.3");
        assert!((v - 3.0).abs() < 4.0 * f64::EPSILON * 3.0, "f = {v} vs 3");
        // log(1/1e-8)/log φ = 38.3 → 39 iterations + the 2 initial points.
        assert!(calls <= 41, "{calls} evaluations");

        // f(t) = t on [0, 1]: the maximum is at the bracket's end; the search closes in on it
        // and the best point is inside the last bracket, narrower than 1e-9.
        let r: Result<_, ()> = maximise(Ok, 0.0, 1.0, 1e-9);
        let (t, v) = r.unwrap_or_default();
        assert!(
            (t - 1.0).abs() < 1e-9 && t == v,
            "end maximum at t = {t}, f = {v}"
        );
    }

    #[test]
    fn golden_section_passes_the_first_error_on() {
        let r = maximise(|t| if t > 0.5 { Err(t) } else { Ok(t) }, 0.0, 1.0, 1e-6);
        assert!(matches!(r, Err(t) if t > 0.5), "{r:?}");
    }
}
