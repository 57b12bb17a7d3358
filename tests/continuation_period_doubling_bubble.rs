//! Branch switching at a period doubling, on a system whose period-doubled orbits are known in
//! closed form: a pitchfork seen from a frame that turns by half a revolution per period.
//!
//! In the frame u = R(−t/2) z (R(θ) the rotation by θ), the motion is
//!
//! ```text
//! u₁' = (g − u₁²) u₁,   u₂' = −u₂,   g = p (1 − p),
//! ```
//!
//! and z = R(t/2) u is the state integrated: z' = ½ J z + R(t/2) f(R(−t/2) z), with J the
//! rotation by π/2. The vector field has period T = 2π in t (f is odd and R(π) = −I). The rest
//! state z = 0 is a period-T orbit for every p, with the monodromy R(π) e^{Df(0) T}, so its
//! multipliers are −e^{2πg} and −e^{−2π}: a period doubling where g = 0, at p = 0 and p = 1,
//! unstable between. For 0 < p < 1 the frame has the fixed points u = (±√g, 0), which are the
//! period-2T orbits z(t) = R(t/2)(±√g, 0): at the section t = 0, z = (√g, 0), and half a
//! period later −z. Their multipliers over 2T are e^{−2g·2T} = e^{−8πg} and e^{−4π}. So the
//! period-2T branch leaves the rest state at p = 0 and rejoins it at p = 1: a period-doubling
//! bubble, every point of it known exactly.

use linkdyn::analysis::AnalysisError;
use linkdyn::analysis::orbit::{
    Branch, BranchEnd, ContinuationOptions, OrbitAt, OrbitFamily, SpecialKind, continue_orbit,
    continue_orbit_watched, switch_branch, switch_branch_watched,
};
use linkdyn::formulation::{Formulation, FormulationError, NoStepHooks};
use linkdyn::solve::{Method, SolverOptions};
use std::f64::consts::PI;

#[derive(Clone)]
struct TurningPitchfork {
    g: f64,
}

impl TurningPitchfork {
    /// (cos, sin) of t/2: z = R(t/2) u.
    fn frame(t: f64) -> (f64, f64) {
        let (s, c) = (0.5 * t).sin_cos();
        (c, s)
    }
}

impl NoStepHooks for TurningPitchfork {}
impl Formulation for TurningPitchfork {
    fn n_states(&self) -> usize {
        2
    }
    fn initial_state(&self) -> Vec<f64> {
        vec![0.0, 0.0]
    }
    fn rhs(&self, t: f64, z: &[f64], dz: &mut [f64]) -> Result<(), FormulationError> {
        let (c, s) = Self::frame(t);
        let (u1, u2) = (c * z[0] + s * z[1], -s * z[0] + c * z[1]);
        let (f1, f2) = ((self.g - u1 * u1) * u1, -u2);
        dz[0] = -0.5 * z[1] + c * f1 - s * f2;
        dz[1] = 0.5 * z[0] + s * f1 + c * f2;
        Ok(())
    }
    fn jacobian(
        &self,
        t: f64,
        z: &[f64],
        _f_y: &[f64],
        out: &mut [f64],
        _work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        let (c, s) = Self::frame(t);
        let u1 = c * z[0] + s * z[1];
        let (d1, d2) = (self.g - 3.0 * u1 * u1, -1.0);
        // ½J + R diag(d1, d2) Rᵀ.
        out.copy_from_slice(&[
            c * c * d1 + s * s * d2,
            c * s * (d1 - d2) - 0.5,
            c * s * (d1 - d2) + 0.5,
            s * s * d1 + c * c * d2,
        ]);
        Ok(0)
    }
    /// The rest state takes any step; the variational equations ride on its steps (as the
    /// pendulum's in `continuation_mathieu_pendulum.rs`).
    fn max_step(&self, _t: f64, _y: &[f64]) -> f64 {
        PI / 200.0
    }
}

struct InP;
impl OrbitFamily for InP {
    type F = TurningPitchfork;
    fn at(&self, p: f64) -> Result<OrbitAt<TurningPitchfork>, AnalysisError> {
        Ok(OrbitAt {
            f: TurningPitchfork { g: p * (1.0 - p) },
            t0: 0.0,
            period: 2.0 * PI,
        })
    }
}

fn solver() -> SolverOptions {
    SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-11)
        .atol(1e-13)
}

fn options() -> ContinuationOptions {
    ContinuationOptions::new(-0.5, 1.5, 0.1)
}

fn rest_branch() -> Branch {
    continue_orbit(&InP, &[0.0, 0.0], &options(), &solver()).unwrap_or_else(|e| panic!("{e}"))
}

fn doublings(b: &Branch) -> Vec<f64> {
    b.points
        .iter()
        .filter(|p| p.special == Some(SpecialKind::PeriodDoubling))
        .map(|p| p.parameter)
        .collect()
}

#[test]
fn the_period_doubled_branch_is_the_closed_form_bubble_from_p_0_to_p_1() {
    let rest = rest_branch();
    assert_eq!(rest.end, BranchEnd::Reached);
    let pds = doublings(&rest);
    assert_eq!(pds.len(), 2, "{pds:?}");
    assert!(
        pds[0].abs() < 1e-6 && (pds[1] - 1.0).abs() < 1e-6,
        "{pds:?}"
    );

    let at = rest
        .points
        .iter()
        .find(|p| p.special == Some(SpecialKind::PeriodDoubling))
        .unwrap_or_else(|| panic!("no PD"));
    let bubble =
        switch_branch(&InP, 1, at, &options(), &solver()).unwrap_or_else(|e| panic!("{e}"));
    // It rejoins the rest state at the other period doubling, p = 1.
    let BranchEnd::Rejoined { parameter } = bubble.end else {
        panic!("{:?}", bubble.end)
    };
    assert!(
        (parameter - 1.0).abs() < 1e-6,
        "rejoined at p = {parameter}"
    );
    let (first, last) = (&bubble.points[0], &bubble.points[bubble.points.len() - 1]);
    for end in [first, last] {
        assert_eq!(end.special, Some(SpecialKind::PeriodDoubling));
        assert!(end.y0.iter().all(|z| z.abs() < 1e-8), "{end:?}");
        assert_eq!(end.period, 4.0 * PI);
    }
    let inner = &bubble.points[1..bubble.points.len() - 1];
    assert!(inner.len() >= 5, "{} points inside the bubble", inner.len());
    let mut highest: f64 = 0.0;
    for pt in inner {
        let p = pt.parameter;
        let g = p * (1.0 - p);
        assert!(g > 0.0, "p = {p} outside the bubble");
        // The orbit at the section is (±√g, 0), one sign along the whole branch.
        assert!(
            (pt.y0[0].abs() - g.sqrt()).abs() < 1e-7 && pt.y0[1].abs() < 1e-7,
            "p = {p}: {:?}, expected (±{}, 0)",
            pt.y0,
            g.sqrt()
        );
        assert_eq!(pt.y0[0].signum(), inner[0].y0[0].signum());
        // Multipliers e^{−8πg} and e^{−4π}, both real; stable.
        let mut expected = [(-8.0 * PI * g).exp(), (-4.0 * PI).exp()];
        expected.sort_by(|a, b| b.total_cmp(a));
        assert_eq!(pt.multipliers.len(), 2);
        for (mu, e) in pt.multipliers.iter().zip(expected) {
            assert!(
                (mu[0] - e).abs() < 1e-6 && mu[1] == 0.0,
                "p = {p}: multipliers {:?}, expected {expected:?}",
                pt.multipliers
            );
        }
        assert!(pt.stable);
        highest = highest.max(p);
    }
    // It starts where the multiplier next to +1 is at least 0.1 from it (nearer, Newton's
    // matrix is as good as singular: the switch's module documentation), and ends at the
    // first point back within 0.1 of it.
    let gap = |pt: &linkdyn::analysis::orbit::BranchPoint| 1.0 - pt.multipliers[0][0];
    assert!(gap(&inner[0]) >= 0.1, "{:?}", inner[0]);
    assert!(
        gap(&inner[inner.len() - 1]) < 0.1,
        "{:?}",
        inner[inner.len() - 1]
    );
    assert!(inner[..inner.len() - 1].iter().all(|pt| gap(pt) >= 0.1));
    // The branch goes over the top of the bubble (g = 1/4 at p = 1/2) and on towards p = 1.
    assert!(highest > 0.9, "highest p inside {highest}");
}

#[test]
fn only_a_located_period_doubling_starts_a_branch() {
    let rest = rest_branch();
    let ordinary = &rest.points[0];
    let e = switch_branch(&InP, 1, ordinary, &options(), &solver())
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert_eq!(
        e,
        "invalid at: expected a located period doubling, got the point at p = -0.5 (no special point)"
    );
}

/// Progress sees every point of both branches once, in order, as it joins: the located period
/// doublings, the end at `to` and the switched branch's start and junction included. A watch
/// that answers false ends the branch there, `stopped`, with the points so far.
#[test]
fn the_watch_sees_every_point_once_in_order() {
    let mut seen = Vec::new();
    let rest = continue_orbit_watched(&InP, &[0.0, 0.0], &options(), &solver(), &mut |p| {
        seen.push((p.parameter, p.special));
        true
    })
    .unwrap_or_else(|e| panic!("{e}"));
    let rows = |b: &Branch| -> Vec<(f64, Option<SpecialKind>)> {
        b.points.iter().map(|p| (p.parameter, p.special)).collect()
    };
    assert_eq!(seen, rows(&rest));
    let at = rest
        .points
        .iter()
        .find(|p| p.special == Some(SpecialKind::PeriodDoubling))
        .unwrap_or_else(|| panic!("no PD"));
    let mut seen = Vec::new();
    let bubble = switch_branch_watched(&InP, 1, at, &options(), &solver(), &mut |p| {
        seen.push((p.parameter, p.special));
        true
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(seen, rows(&bubble));

    // Stopped after the third point.
    let mut count = 0;
    let stopped = continue_orbit_watched(&InP, &[0.0, 0.0], &options(), &solver(), &mut |_| {
        count += 1;
        count < 3
    })
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(stopped.end, BranchEnd::Stopped);
    assert_eq!(count, 3);
    assert_eq!(stopped.points.len(), 3);
}
