//! Equations of motion in residual form F(t, Y, Ẏ) = 0, for DAE solvers (SUNDIALS IDA,
//! `solve::ida`).
//!
//! A formulation that has one returns it from
//! [`Formulation::residual_form`]: the DAE does
//! ([`DaeResidual`](super::dae::residual::DaeResidual), with the Lagrange multipliers λ as
//! algebraic unknowns). Every other formulation is integrated as the implicit ODE
//! F = Ẏ − f(t, Y) ([`OdeResidual`]).
//!
//! # Layout of the unknowns
//! The formulation's own state y (n components, the layout of
//! [`Formulation::n_states`]) is y = (y_s, e): the states of the
//! equations, then n_Q bookkeeping integrals e ([`ResidualForm::n_quadratures`], for the DAE
//! the three energy integrals of `--energy`). The unknowns of F are Y = (y_s, z): the states
//! y_s, then the algebraic unknowns z (for the DAE: λ of the active constraint rows). The
//! integrals are no unknowns of F: they obey ė = g(t, Y, Ẏ)
//! ([`ResidualForm::quadrature_rhs`]) and a solver integrates them as quadratures, outside its
//! Newton iteration and its error test (IDA's quadratures, `IDAQuadInit`), so that bookkeeping
//! cannot move the trajectory: a run with them takes the very steps of a run without. The
//! state an integrator hands back to the driver is (Y\[..n − n_Q\], e), and events, samples
//! and restarts see the same y as with any other method.
//!
//! # Iteration matrix
//! Implicit DAE solvers (BDF in IDA) need J = ∂F/∂Y + c ∂F/∂Ẏ, where c = α₀/h is the solver's
//! scalar (α₀ the leading BDF coefficient, h the step). [`ResidualForm::jacobian`] writes it
//! **column-major** (as SUNDIALS' dense matrices store it): `out[j * N + i]` = J_ij.

use super::sparse_jacobian::SparsePattern;
use super::{Formulation, FormulationError};
use std::cell::RefCell;

/// Equations in residual form F(t, Y, Ẏ) = 0 (see the module documentation for the layout).
pub trait ResidualForm {
    /// Number n of the formulation's states (the first n unknowns).
    fn n_states(&self) -> usize;

    /// Number N of unknowns of F: n − n_Q states plus the algebraic ones.
    fn n_unknowns(&self) -> usize;

    /// Number n_Q of bookkeeping integrals, the last n_Q of the formulation's states, which are
    /// not unknowns of F (see the module documentation). Default 0.
    fn n_quadratures(&self) -> usize {
        0
    }

    /// Their rates ė = g(t, Y, Ẏ) into `out` (length n_Q) at a solution point (Y, Ẏ) of F.
    /// Default: nothing (no integrals).
    fn quadrature_rhs(
        &self,
        _t: f64,
        _yy: &[f64],
        _yp: &[f64],
        _out: &mut [f64],
    ) -> Result<(), FormulationError> {
        Ok(())
    }

    /// Marks each unknown (length N) as differential (`true`: Ẏ_i appears in F) or algebraic
    /// (`false`).
    fn differential(&self, out: &mut [bool]);

    /// Consistent values (Y, Ẏ) at (t, y) (y of length n), given ẏ = f(t, y) of the
    /// formulation's own right-hand side: Y = (y_s, z), Ẏ = (ẏ_s, 0) with the algebraic
    /// unknowns z such that F(t, Y, Ẏ) = 0 (y_s = y\[..n − n_Q\]; the integrals start from
    /// y\[n − n_Q..\]).
    fn consistent_values(
        &self,
        t: f64,
        y: &[f64],
        dy: &[f64],
        yy: &mut [f64],
        yp: &mut [f64],
    ) -> Result<(), FormulationError>;

    /// F(t, Y, Ẏ) into `res` (length N).
    fn residual(
        &self,
        t: f64,
        yy: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), FormulationError>;

    /// The smallest pivot ratio of the constraint solve (the DAE's
    /// [`Schur::min_pivot_ratio`](super::schur::Schur::min_pivot_ratio): how near a singular
    /// position) over the residuals evaluated since the last call, which starts the count
    /// afresh; 1 where there is none. The integrator hands it to
    /// [`StepHooks::residual_stages`](crate::formulation::StepHooks::residual_stages). Default 1.
    fn take_min_pivot_ratio(&self) -> f64 {
        1.0
    }

    /// J = ∂F/∂Y + c ∂F/∂Ẏ at (t, Y, Ẏ), column-major into `out` (N², overwritten). `res`
    /// holds F(t, Y, Ẏ). Returns the number of right-hand-side calls it made (for
    /// [`SolverStats::rhs_evals`](crate::solve::SolverStats::rhs_evals); 0 for an analytic one).
    fn jacobian(
        &self,
        t: f64,
        yy: &[f64],
        yp: &[f64],
        res: &[f64],
        c: f64,
        out: &mut [f64],
    ) -> Result<usize, FormulationError>;

    /// The structural non-zeros of J (every entry [`ResidualForm::sparse_jacobian`] may make
    /// non-zero at any state, and the whole diagonal), fixed for the form's life, for a sparse
    /// linear solver; `None` (the default) where the form only writes J densely.
    fn sparse_pattern(&self) -> Option<SparsePattern> {
        None
    }

    /// J at (t, Y, Ẏ) as [`ResidualForm::jacobian`] computes it, into `values` over
    /// [`ResidualForm::sparse_pattern`] (in its order). Returns the number of right-hand-side
    /// calls made. The default refuses: only forms with a pattern implement it.
    fn sparse_jacobian(
        &self,
        _t: f64,
        _yy: &[f64],
        _yp: &[f64],
        _c: f64,
        _values: &mut [f64],
    ) -> Result<usize, FormulationError> {
        Err(FormulationError::Unsupported {
            formulation: "residual form".into(),
            reason: "no sparse iteration matrix".into(),
        })
    }
}

/// Any [`Formulation`] as the implicit ODE F(t, Y, Ẏ) = Ẏ − f(t, Y): no algebraic unknowns,
/// J = c I − ∂f/∂y with the formulation's own Jacobian ([`Formulation::jacobian`]: analytic
/// where it has one, forward differences otherwise).
pub struct OdeResidual<'a, F: Formulation + ?Sized> {
    f: &'a F,
    work: RefCell<OdeWork>,
}

/// Scratch of [`OdeResidual`].
struct OdeWork {
    f_y: Vec<f64>,
    jac: Vec<f64>,
    scratch: Vec<f64>,
}

impl<'a, F: Formulation + ?Sized> OdeResidual<'a, F> {
    /// The residual form of `f`.
    pub fn new(f: &'a F) -> Self {
        let n = f.n_states();
        OdeResidual {
            f,
            work: RefCell::new(OdeWork {
                f_y: vec![0.0; n],
                jac: vec![0.0; n * n],
                scratch: vec![0.0; 2 * n],
            }),
        }
    }
}

impl<F: Formulation + ?Sized> ResidualForm for OdeResidual<'_, F> {
    fn n_states(&self) -> usize {
        self.f.n_states()
    }

    fn n_unknowns(&self) -> usize {
        self.f.n_states()
    }

    fn differential(&self, out: &mut [bool]) {
        out.fill(true);
    }

    fn consistent_values(
        &self,
        _t: f64,
        y: &[f64],
        dy: &[f64],
        yy: &mut [f64],
        yp: &mut [f64],
    ) -> Result<(), FormulationError> {
        yy.copy_from_slice(y);
        yp.copy_from_slice(dy);
        Ok(())
    }

    fn residual(
        &self,
        t: f64,
        yy: &[f64],
        yp: &[f64],
        res: &mut [f64],
    ) -> Result<(), FormulationError> {
        self.f.rhs(t, yy, res)?;
        for (r, p) in res.iter_mut().zip(yp) {
            *r = p - *r;
        }
        Ok(())
    }

    fn jacobian(
        &self,
        t: f64,
        yy: &[f64],
        _yp: &[f64],
        _res: &[f64],
        c: f64,
        out: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let n = self.f.n_states();
        let mut work = self.work.borrow_mut();
        let OdeWork { f_y, jac, scratch } = &mut *work;
        self.f.rhs(t, yy, f_y)?;
        let calls = 1 + self.f.jacobian(t, yy, f_y, jac, scratch)?;
        // Row-major ∂f/∂y into column-major c I − ∂f/∂y.
        for i in 0..n {
            for j in 0..n {
                out[j * n + i] = -jac[i * n + j];
            }
            out[i * n + i] += c;
        }
        Ok(calls)
    }
}

/// Central-difference J = ∂F/∂Y + c ∂F/∂Ẏ of any residual form, column-major (N² into `out`):
/// the check of analytic Jacobians in tests. Column j perturbs Y_j by ±δ_j and Ẏ_j by ±δ'_j,
/// δ = 10⁻⁸·max(1, |x|) (truncation error O((δ/ℓ)²) for a residual that varies on a length ℓ
/// — 1e-4 for contact forces at a micrometre of penetration —, rounding ε|F|/δ ≈ 1e-8 of the
/// residual's terms) and δ' = 10⁻⁴·max(1, |x|): the residuals of linkages are linear in Ẏ,
/// where central differences are exact, and a large δ' keeps the rounding, multiplied by c,
/// small), and adds the two quotients with weights 1 and c. Costs 4N residual
/// evaluations.
pub fn finite_difference_jacobian(
    form: &dyn ResidualForm,
    t: f64,
    yy: &[f64],
    yp: &[f64],
    c: f64,
    out: &mut [f64],
) -> Result<(), FormulationError> {
    let n = form.n_unknowns();
    let (mut y1, mut p1) = (yy.to_vec(), yp.to_vec());
    let (mut plus, mut minus) = (vec![0.0; n], vec![0.0; n]);
    let step = |x: f64| 1e-8 * x.abs().max(1.0);
    for j in 0..n {
        let d = step(yy[j]);
        y1[j] = yy[j] + d;
        form.residual(t, &y1, yp, &mut plus)?;
        y1[j] = yy[j] - d;
        form.residual(t, &y1, yp, &mut minus)?;
        y1[j] = yy[j];
        for i in 0..n {
            out[j * n + i] = (plus[i] - minus[i]) / (2.0 * d);
        }
        let dp = 1e4 * step(yp[j]);
        p1[j] = yp[j] + dp;
        form.residual(t, yy, &p1, &mut plus)?;
        p1[j] = yp[j] - dp;
        form.residual(t, yy, &p1, &mut minus)?;
        p1[j] = yp[j];
        for i in 0..n {
            out[j * n + i] += c * (plus[i] - minus[i]) / (2.0 * dp);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formulation::NoStepHooks;

    /// x'' = −x − x³ as (x, v).
    struct Duffing;
    impl NoStepHooks for Duffing {}

    impl Formulation for Duffing {
        fn n_states(&self) -> usize {
            2
        }
        fn initial_state(&self) -> Vec<f64> {
            vec![0.8, -0.3]
        }
        fn rhs(&self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
            dy[0] = y[1];
            dy[1] = -y[0] - y[0] * y[0] * y[0];
            Ok(())
        }
    }

    /// The ODE residual vanishes at (y, f(y)) and its iteration matrix is c I − ∂f/∂y:
    /// [[c, −1], [1 + 3x², c]] (column-major), to the forward-difference error ≈ 1e-7.
    #[test]
    fn ode_residual_and_its_jacobian() -> Result<(), FormulationError> {
        let f = Duffing;
        let form = OdeResidual::new(&f);
        let y = f.initial_state();
        let mut dy = [0.0; 2];
        f.rhs(0.0, &y, &mut dy)?;
        let (mut yy, mut yp, mut res) = ([0.0; 2], [0.0; 2], [1.0; 2]);
        form.consistent_values(0.0, &y, &dy, &mut yy, &mut yp)?;
        form.residual(0.0, &yy, &yp, &mut res)?;
        assert_eq!(res, [0.0, 0.0], "residual at consistent values");
        let c = 250.0;
        let mut jac = [0.0; 4];
        form.jacobian(0.0, &yy, &yp, &res, c, &mut jac)?;
        let x = y[0];
        let exact = [c, 1.0 + 3.0 * x * x, -1.0, c];
        for (k, (a, b)) in jac.iter().zip(exact).enumerate() {
            assert!((a - b).abs() < 1e-6, "entry {k}: {a} vs exact {b}");
        }
        Ok(())
    }
}
