//! Claim: with a fixed step h the global error of DOPRI5 and Radau5 falls like h⁵ and that of
//! DOP853 like h⁸, and their dense outputs are of order 4, 3 and 7 (local interpolation error
//! h⁵, h⁴ and h⁸).
//!
//! The observed order is the least-squares slope of log(error) against log(h) over a range of h
//! where the error is well above rounding (≥ 1e-13) yet h is small enough for the leading error
//! term to dominate. The remaining higher-order terms still bend the slope by about 0.1–0.2 at
//! these h, so it is checked to ±0.3: tight enough to tell p from p ± 1, loose enough not to
//! depend on the pre-asymptotic wiggle.

mod common;

use common::ode::{ExpSin, OdeRecorder, Oscillator, observed_order};
use linkdyn::solve::{Method, SolveError, SolverOptions, Stepper, Stop, integrate};
use std::f64::consts::PI;

/// Tolerance on the observed order (see the module documentation).
const ORDER_TOL: f64 = 0.3;

/// Numbers of fixed steps over the interval per method: errors from ~1e-5 down to ~1e-12.
fn step_counts(method: Method) -> &'static [usize] {
    match method {
        Method::Dopri5 => &[48, 64, 96, 128, 256],
        Method::Dop853 => &[16, 20, 24, 28, 32],
        Method::Radau5 => &[16, 24, 32, 48, 64],
        // Not in Method::ALL: IDA has no fixed steps.
        #[cfg(feature = "ida")]
        Method::Ida => &[],
    }
}

/// Largest error over all step ends of a fixed-step run of `f` on [0, t_end].
fn max_step_error(
    method: Method,
    n: usize,
    t_end: f64,
    run: &mut dyn FnMut(&SolverOptions) -> Result<f64, SolveError>,
) -> Result<(f64, f64), SolveError> {
    let h = t_end / n as f64;
    let opts = SolverOptions::with_fixed_step(h).method(method);
    Ok((h, run(&opts)?))
}

fn oscillator_error(opts: &SolverOptions, t_end: f64) -> Result<f64, SolveError> {
    let exact = Oscillator { omega: 1.0 };
    let mut f = Oscillator { omega: 1.0 };
    let mut s = Stepper::new(&mut f, 0.0, &[1.0, 0.0], t_end, opts)?;
    let mut err: f64 = 0.0;
    loop {
        let stop = s.step()?;
        let x = exact.exact(s.t());
        err = err
            .max((s.y()[0] - x[0]).abs())
            .max((s.y()[1] - x[1]).abs());
        if stop == Stop::EndReached {
            return Ok(err);
        }
    }
}

fn expsin_error(opts: &SolverOptions, t_end: f64) -> Result<f64, SolveError> {
    let mut f = ExpSin;
    let mut s = Stepper::new(&mut f, 0.0, &[1.0], t_end, opts)?;
    let mut err: f64 = 0.0;
    loop {
        let stop = s.step()?;
        err = err.max((s.y()[0] - ExpSin::exact(s.t())).abs());
        if stop == Stop::EndReached {
            return Ok(err);
        }
    }
}

fn check_order(name: &str, method: Method, expected: f64, hs: &[f64], errs: &[f64]) {
    let p = observed_order(hs, errs);
    println!("{name}, {method}: observed order {p:.3}");
    assert!(
        (p - expected).abs() <= ORDER_TOL,
        "{name}, {method}: observed order {p:.3}, expected {expected} (h = {hs:?}, errors = {errs:?})"
    );
}

#[test]
fn global_error_has_the_method_order_on_the_harmonic_oscillator() -> Result<(), SolveError> {
    let t_end = 2.0 * PI;
    for method in Method::ALL {
        let mut hs = Vec::new();
        let mut errs = Vec::new();
        for &n in step_counts(method) {
            let (h, e) = max_step_error(method, n, t_end, &mut |o| oscillator_error(o, t_end))?;
            hs.push(h);
            errs.push(e);
        }
        check_order("oscillator", method, f64::from(method.order()), &hs, &errs);
    }
    Ok(())
}

#[test]
fn global_error_has_the_method_order_on_a_nonlinear_problem() -> Result<(), SolveError> {
    let t_end = 2.0 * PI;
    for method in Method::ALL {
        let mut hs = Vec::new();
        let mut errs = Vec::new();
        for &n in step_counts(method) {
            let (h, e) = max_step_error(method, n, t_end, &mut |o| expsin_error(o, t_end))?;
            hs.push(h);
            errs.push(e);
        }
        check_order(
            "y' = y cos t",
            method,
            f64::from(method.order()),
            &hs,
            &errs,
        );
    }
    Ok(())
}

/// One step of size h from the exact y(t0) of y' = y cos t; largest error of the dense output
/// at θ = 0.2, 0.5, 0.7. A continuous extension of order p* has local error O(h^(p*+1)).
fn local_dense_error(method: Method, h: f64) -> Result<f64, SolveError> {
    let t0 = 0.3;
    let opts = SolverOptions::with_fixed_step(h).method(method);
    let mut f = ExpSin;
    let mut s = Stepper::new(&mut f, t0, &[ExpSin::exact(t0)], t0 + 10.0, &opts)?;
    s.step()?;
    let mut err: f64 = 0.0;
    let mut out = [0.0];
    for theta in [0.2, 0.5, 0.7] {
        let t = t0 + theta * h;
        s.interpolate(t, &mut out)?;
        err = err.max((out[0] - ExpSin::exact(t)).abs());
    }
    Ok(err)
}

#[test]
fn dense_output_has_its_own_order() -> Result<(), SolveError> {
    for method in Method::ALL {
        // Local errors from ~1e-7 to ~1e-12 (DOPRI5) and ~1e-6 to ~1e-13 (DOP853).
        let hs: &[f64] = match method {
            Method::Dopri5 => &[0.2, 0.1, 0.05, 0.025],
            Method::Dop853 => &[0.8, 0.4, 0.2, 0.1],
            Method::Radau5 => &[0.2, 0.1, 0.05, 0.025],
            #[cfg(feature = "ida")]
            Method::Ida => &[],
        };
        let errs = hs
            .iter()
            .map(|&h| local_dense_error(method, h))
            .collect::<Result<Vec<_>, _>>()?;
        let p_star = f64::from(method.dense_order());
        check_order("local dense output", method, p_star + 1.0, hs, &errs);
    }
    Ok(())
}

#[test]
fn dense_samples_between_steps_converge_with_the_global_order() -> Result<(), SolveError> {
    // Samples on a grid unrelated to the steps (101 intervals): their error is the global
    // error (order p) plus the interpolation error (order p* + 1): order min(p, p* + 1), which
    // is p for the explicit pairs and 4 for Radau5 (cubic dense output).
    let t_end = 2.0 * PI;
    for method in Method::ALL {
        // The largest error over the grid depends on where the samples fall inside the steps,
        // which changes with n; a wider range of n averages that out for DOP853.
        let counts: &[usize] = match method {
            Method::Dopri5 => step_counts(method),
            Method::Dop853 | Method::Radau5 => &[16, 24, 32, 48, 64],
            #[cfg(feature = "ida")]
            Method::Ida => &[],
        };
        let mut hs = Vec::new();
        let mut errs = Vec::new();
        for &n in counts {
            let h = t_end / n as f64;
            let opts = SolverOptions::with_fixed_step(h).method(method);
            let mut rec = OdeRecorder::default();
            integrate(
                &mut ExpSin,
                0.0,
                &[1.0],
                t_end,
                t_end / 101.0,
                &opts,
                &mut rec,
            )?;
            assert_eq!(
                rec.samples.len(),
                102,
                "{method}: one sample per grid point"
            );
            let e = rec
                .samples
                .iter()
                .map(|(t, y)| (y[0] - ExpSin::exact(*t)).abs())
                .fold(0.0, f64::max);
            hs.push(h);
            errs.push(e);
        }
        check_order(
            "dense samples",
            method,
            f64::from(method.order().min(method.dense_order() + 1)),
            &hs,
            &errs,
        );
    }
    Ok(())
}
