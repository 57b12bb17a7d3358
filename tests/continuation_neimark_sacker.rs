//! A Neimark–Sacker point located on a system whose multipliers are known in closed form: the
//! Hopf normal form
//!
//! ```text
//! z' = (μ + iω) z − |z|² z,   z = x + iy,
//! ```
//!
//! whose rest state z = 0 is, for every μ, an orbit of any period T. Its monodromy over T is
//! e^{μT} R(ωT): the complex pair e^{(μ ± iω)T}, which crosses the unit circle at μ = 0 (a torus
//! — here the circle |z| = √μ, a quasi-periodic motion when ωT/2π is irrational — branches off).
//! Continued in μ from −0.5 to 0.5 with T = 1 and ω = 2 (the pair at angle ±2 rad, off the
//! real axis), the branch must have exactly one special point, a Neimark–Sacker point at μ = 0,
//! and at every point the pair e^{μT}·e^{±2i}.
//! (Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer, 2004, §3.4
//! and §4.7.)

mod common;

use common::branch::the_one_special_point;
use linkdyn::analysis::AnalysisError;
use linkdyn::analysis::orbit::{
    ContinuationOptions, OrbitAt, OrbitFamily, SpecialKind, continue_orbit,
};
use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{Method, SolverOptions};

const OMEGA: f64 = 2.0;
const PERIOD: f64 = 1.0;

#[derive(Clone)]
struct HopfNormalForm {
    mu: f64,
}

impl NoStepHooks for HopfNormalForm {}
impl Formulation for HopfNormalForm {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0, 0.0]
    }
    fn rhs(&self, _t: f64, z: &[f64], dz: &mut [f64]) -> Result<(), FormulationError> {
        let r2 = z[0] * z[0] + z[1] * z[1];
        dz[0] = (self.mu - r2) * z[0] - OMEGA * z[1];
        dz[1] = OMEGA * z[0] + (self.mu - r2) * z[1];
        Ok(())
    }
    fn jacobian(
        &self,
        _t: f64,
        z: &[f64],
        _f_y: &[f64],
        out: &mut [f64],
        _work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let (x, y) = (z[0], z[1]);
        let r2 = x * x + y * y;
        out.copy_from_slice(&[
            self.mu - r2 - 2.0 * x * x,
            -OMEGA - 2.0 * x * y,
            OMEGA - 2.0 * x * y,
            self.mu - r2 - 2.0 * y * y,
        ]);
        Ok(0)
    }
    /// The rest state takes any step; the variational equations ride on its steps (as in
    /// `continuation_mathieu_pendulum.rs`).
    fn max_step(&self, _t: f64, _y: &[f64]) -> f64 {
        PERIOD / 200.0
    }
}

struct InMu;
impl OrbitFamily for InMu {
    type F = HopfNormalForm;
    fn at(&self, mu: f64) -> Result<OrbitAt<HopfNormalForm>, AnalysisError> {
        Ok(OrbitAt {
            f: HopfNormalForm { mu },
            t0: 0.0,
            period: PERIOD,
        })
    }
}

#[test]
fn the_rest_state_has_one_neimark_sacker_point_at_mu_0() {
    let solver = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-11)
        .atol(1e-13);
    let b = continue_orbit(
        &InMu,
        &[0.0, 0.0],
        &ContinuationOptions::new(-0.5, 0.5, 0.1),
        &solver,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let located = the_one_special_point(&b, SpecialKind::NeimarkSacker);
    assert!(located.abs() < 1e-6, "NS at μ = {located}");
    for p in &b.points {
        let mu = p.parameter;
        assert!(p.y0.iter().all(|z| *z == 0.0), "{p:?}");
        // The pair e^{μT}·e^{±iωT}, the one with positive imaginary part first or second.
        assert_eq!(p.multipliers.len(), 2);
        let modulus = (mu * PERIOD).exp();
        for z in &p.multipliers {
            assert!(
                (z[0].hypot(z[1]) - modulus).abs() < 1e-8,
                "μ = {mu}: {:?}, modulus {modulus}",
                p.multipliers
            );
            assert!(
                (z[1].atan2(z[0]).abs() - OMEGA * PERIOD).abs() < 1e-8,
                "μ = {mu}: {:?}, angle ±{OMEGA}",
                p.multipliers
            );
        }
        if p.special.is_none() {
            assert_eq!(p.stable, mu < 0.0, "μ = {mu}");
        }
    }
}
