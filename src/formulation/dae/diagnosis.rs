//! Why a run stalled: what [`Formulation::diagnose`](super::Formulation::diagnose) says at
//! the state where the no-progress rule stopped it (`solve::progress`), for the DAE and the
//! generalised-coordinate formulation.
//!
//! **Near-dependent constraint rows.** At (t, q) the active rows of the constraint Jacobian
//! are scaled as in the coordinate partitioning (`generalized`): angle rows and angle columns
//! measured as arc lengths L·φ, L the linkage's length scale, so that metres and radians
//! compare fairly. Let σ_1 ≥ … ≥ σ_m be the singular values of the scaled Φ̃_q and u the left
//! singular vector of σ_m: Σᵢ uᵢ Φ̃_q,i = σ_m vᵀ, so the rows with large |uᵢ| are the ones
//! that are (nearly) a combination of each other — at a singular position (a toggle, a
//! parallelogram's flat position) σ_m/σ_1 → 0 and those rows are the constraints that lose
//! their independence. The diagnosis names them, largest |uᵢ| first, when
//! σ_m/σ_1 < [`NEAR_SINGULAR`]. The SVD is dense, O(m·n²): it runs once, when a run has
//! already failed.
//!
//! **Clearance joints at the contact boundary.** A journal whose penetration δ lies within
//! [`BOUNDARY_FRACTION`] of the radial clearance c of zero sits where its contact starts and
//! ends: impact events pile up there (chattering, a Zeno sequence of impacts) or the contact
//! grazes. The diagnosis names every such joint with δ.
//!
//! **Generalised coordinates.** Besides both of the above at the projected state, the pivot
//! ratio of the coordinate partition's dependent block (≈ 1/cond) against the best block
//! available: a block much worse than the best is one that should have been repartitioned.

use super::{Dae, sin_cos_of};
use crate::formulation::FormulationError;
use crate::mechanics::constraints::ConstraintEval;
use nalgebra::DMatrix;

/// σ_min/σ_max of the scaled constraint Jacobian below which the rows count as nearly
/// dependent (a thousandth: at a distance s from a simple singular position the ratio is of
/// the order of s/L, so this names positions within about 0.1 % of the linkage's size of one).
pub const NEAR_SINGULAR: f64 = 1e-3;

/// Fraction of the radial clearance within which a penetration δ counts as the contact
/// boundary (|δ| < 1e-3 c: a thousandth of the clearance, far closer than a journal in free
/// flight or in a settled contact sits for long).
pub const BOUNDARY_FRACTION: f64 = 1e-3;

/// Rows named at most (the largest |uᵢ| first).
const MAX_ROWS: usize = 6;

/// Rows with |uᵢ| below this fraction of the largest take no part worth naming.
const ROW_SHARE: f64 = 0.1;

/// The DAE's diagnosis at (t, y): near-dependent rows and clearance joints at the contact
/// boundary, joined by "; ", or `None` when neither applies.
pub fn dae(dae: &Dae, t: f64, y: &[f64]) -> Option<String> {
    let n = dae.n_coordinates();
    let (q, v) = (y.get(..n)?, y.get(n..2 * n)?);
    let mut found: Vec<String> = Vec::new();
    if let Some(rows) = dependent_rows(dae, t, q, v) {
        found.push(rows);
    }
    found.extend(boundary_contacts(dae, y));
    (!found.is_empty()).then(|| found.join("; "))
}

/// The generalised formulation's diagnosis: the partition's condition (the pivot ratio ρ of
/// the current dependent block and of the best one), then the DAE's diagnosis at the
/// projected state `projected` (or at the stored, unprojected one if the projection failed,
/// with the reason).
pub fn generalized(
    base: &Dae,
    t: f64,
    projected: Result<&[f64], &FormulationError>,
    stored: &[f64],
    quality: Option<(f64, f64, String)>,
) -> Option<String> {
    let mut found: Vec<String> = Vec::new();
    if let Some((current, best, independent)) = quality {
        // Pivot ratios (≈ 1/cond) of the dependent blocks: report any block that is itself
        // nearly singular or ten times worse conditioned than the best (the factor of the
        // repartition event, which compares volumes of the blocks instead).
        if current < NEAR_SINGULAR || current < 0.1 * best {
            found.push(format!(
                "the coordinate partition is ill-conditioned (independent coordinates {independent}; pivot ratio of the dependent block {current:.3e}, best available {best:.3e})"
            ));
        }
    }
    let y = match projected {
        Ok(y) => y,
        Err(e) => {
            found.push(format!(
                "the dependent coordinates cannot be recovered ({e})"
            ));
            stored
        }
    };
    if let Some(d) = dae(base, t, y) {
        found.push(d);
    }
    (!found.is_empty()).then(|| found.join("; "))
}

/// "constraint rows "A.x" (u = 0.71), … are nearly dependent (σ_min/σ_max = …)", if so.
fn dependent_rows(dae: &Dae, t: f64, q: &[f64], v: &[f64]) -> Option<String> {
    let set = dae.constraints();
    let model = dae.model();
    let active = dae.active_rows();
    let (m, n) = (active.len(), q.len());
    if m == 0 || n == 0 {
        return None;
    }
    let sin_cos = sin_cos_of(q);
    let mut eval = ConstraintEval::with_rows(set.n_rows());
    set.evaluate_into(t, q, v, &sin_cos, &mut eval);
    let l = dae.length_scale();
    let mut jac = DMatrix::<f64>::zeros(m, n);
    for (i, &k) in active.iter().enumerate() {
        let row = eval.rows.get(k)?;
        let weight = dae.row_length_weight(k);
        for (body, j) in [(row.body_a, row.jac_a), (row.body_b, row.jac_b)] {
            let Some(b) = body else { continue };
            for (c, value) in j.iter().enumerate() {
                let column = if c == 2 { 1.0 / l } else { 1.0 };
                jac[(i, 3 * b + c)] += weight * value * column;
            }
        }
    }
    if !jac.iter().all(|x| x.is_finite()) {
        return None;
    }
    // Left singular vectors of Φ̃_q are the eigenvectors of Φ̃_q Φ̃_qᵀ (m × m); the SVD of
    // the transpose (n × m, n ≥ m for a formulation that assembled) gives them as its right
    // singular vectors, all m of them.
    let svd = crate::formulation::assembly::bounded_svd(jac.transpose(), false, true)?;
    let v_t = svd.v_t?;
    let (mut k_min, mut s_min, mut s_max) = (0, f64::INFINITY, 0.0_f64);
    for (k, &s) in svd.singular_values.iter().enumerate() {
        s_max = s_max.max(s);
        if s < s_min {
            (k_min, s_min) = (k, s);
        }
    }
    // A rank-deficient Φ̃_q with fewer columns than rows cannot come from an assembled model;
    // all m singular values exist since n ≥ m.
    if svd.singular_values.len() < m || s_max <= 0.0 || s_min / s_max >= NEAR_SINGULAR {
        return None;
    }
    let u = v_t.row(k_min);
    let largest = u.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    let mut rows: Vec<(usize, f64)> = u
        .iter()
        .enumerate()
        .filter(|(_, x)| x.abs() >= ROW_SHARE * largest)
        .map(|(i, x)| (i, x.abs()))
        .collect();
    rows.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    let more = rows.len().saturating_sub(MAX_ROWS);
    let names: Vec<String> = rows
        .iter()
        .take(MAX_ROWS)
        .filter_map(|&(i, w)| {
            let k = *active.get(i)?;
            Some(format!("\"{}\" ({w:.2})", set.row_name(model, k)))
        })
        .collect();
    let tail = if more > 0 {
        format!(" and {more} more")
    } else {
        String::new()
    };
    Some(format!(
        "the constraint rows {}{tail} are nearly dependent: the linkage is at or near a singular position (σ_min/σ_max = {:.3e} of the scaled constraint Jacobian; in parentheses each row's share |u_i| of the dependence)",
        names.join(", "),
        s_min / s_max
    ))
}

/// "clearance joint "B" sits at its contact boundary (δ = … m, clearance … m): …", per joint.
fn boundary_contacts(dae: &Dae, y: &[f64]) -> Vec<String> {
    let n = dae.n_coordinates();
    let model = dae.model();
    let mut out = Vec::new();
    for (k, site) in dae.contacts().sites().iter().enumerate() {
        if y.len() <= 2 * n + k {
            break;
        }
        let c = site.contact.clearance;
        let delta = dae.contact_state(k, y).kinematics.delta;
        if delta.abs() < BOUNDARY_FRACTION * c {
            out.push(format!(
                "clearance joint \"{}\" sits at its contact boundary (δ = {delta:.3e} m, clearance {c:.3e} m): impacts may pile up there (chattering, a Zeno sequence) or the contact grazes",
                model.joint(site.joint).name
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulation::{DaeOptions, Formulation};

    /// The reference four-bar with its clearance joint B (c = 0.5 mm, journal on the rocker,
    /// body 2), journal centred at t = 0.
    fn reference() -> Dae {
        let model = crate::model::load("models/farahan2016.toml".as_ref(), &[])
            .unwrap_or_else(|e| panic!("{e}"));
        Dae::new(&model, &DaeOptions::default()).unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn a_healthy_state_has_nothing_to_report() {
        let dae = reference();
        // Journal centred (δ = −c) and the linkage far from a toggle.
        assert_eq!(dae.diagnose(0.0, &dae.initial_state()), None);
    }

    #[test]
    fn a_journal_at_its_contact_boundary_is_named() {
        let dae = reference();
        let mut y = dae.initial_state();
        // Move the rocker (the journal's body) by c along x: |e| = c, δ = 0 to round-off.
        y[6] += 5e-4;
        let delta = dae.contact_state(0, &y).kinematics.delta;
        assert!(delta.abs() < 1e-15, "δ = {delta:e} m after the shift");
        assert_eq!(
            dae.diagnose(0.0, &y),
            Some(format!(
                "clearance joint \"B\" sits at its contact boundary (δ = {delta:.3e} m, clearance 5.000e-4 m): impacts may pile up there (chattering, a Zeno sequence) or the contact grazes"
            ))
        );
        // A thousandth of c away counts no more (|δ| < 1e-3 c is the rule).
        y[6] -= 1e-6;
        assert_eq!(dae.diagnose(0.0, &y), None);
    }
}
