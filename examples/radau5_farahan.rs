//! Cost of reaching a given accuracy on the reference clearance case (models/farahan2016.toml,
//! 250 rpm, 2 crank turns): Radau5 against DOP853, both formulations.
//!
//! For each formulation a tight DOP853 run (rtol 1e-13) is the reference; each method is then
//! run over a ladder of rtol, and for each run we print the largest error of the coupler and
//! rocker angles over the 1 ms samples (rad), the RHS calls (Jacobians included), Jacobians,
//! Newton iterations, steps, rejections, impacts and the best-of-5 wall time.
//!
//! Run: `cargo run --release --example radau5_farahan`. Environment variables for tuning:
//! `METHODS=radau5` (Radau5 only), `RADAU5_THETA_JAC`, `RADAU5_NEWTON_TOL`, `RADAU5_NIT`,
//! `RADAU5_HAIRER_TOL=0` (see [`Radau5Settings`]); `RTOLS=1e-9,5e-10` replaces the rtol
//! ladder; `WHERE=1` prints, per run, the sample of the largest error and the error at every
//! 20th sample (20 ms) to stderr. `end_err` is the angle error at t_end alone.

use std::time::Instant;

use linkdyn::formulation::{Dae, DaeOptions, Formulation, Outputs, ReducedLagrangian};
use linkdyn::solve::radau5::Radau5Settings;
use linkdyn::solve::{Method, Recorder, SolverOptions, SolverStats, integrate};

const T_END: f64 = 0.48;
const DT: f64 = 1e-3;

fn run<F: Formulation + Outputs + Clone>(
    f: &F,
    opts: &SolverOptions,
) -> Result<(Recorder, SolverStats), linkdyn::Error> {
    let mut f = f.clone();
    let y0 = f.initial_state();
    let mut rec = Recorder::new(&f);
    let stats = integrate(&mut f, 0.0, &y0, T_END, DT, opts, &mut rec)?;
    Ok((rec, stats))
}

/// Angle error at the last sample (t_end, a step end) only.
fn end_error(rec: &Recorder, reference: &Recorder) -> f64 {
    let mut err: f64 = 0.0;
    for name in ["coupler.phi", "rocker.phi"] {
        let (Some(a), Some(b)) = (rec.column(name), reference.column(name)) else {
            return f64::NAN;
        };
        if let (Some(x), Some(y)) = (a.last(), b.last()) {
            err = err.max((x - y).abs());
        }
    }
    err
}

fn angle_error(rec: &Recorder, reference: &Recorder) -> f64 {
    let mut err: f64 = 0.0;
    let mut at = 0;
    for name in ["coupler.phi", "rocker.phi"] {
        let (Some(a), Some(b)) = (rec.column(name), reference.column(name)) else {
            return f64::NAN;
        };
        for (i, (x, y)) in a.iter().zip(&b).enumerate() {
            if (x - y).abs() > err {
                err = (x - y).abs();
                at = i;
            }
        }
    }
    if std::env::var("WHERE").is_ok() {
        let errs: Vec<String> = (0..rec.len())
            .step_by(20)
            .map(|i| {
                let e = ["coupler.phi", "rocker.phi"]
                    .iter()
                    .map(|n| match (rec.column(n), reference.column(n)) {
                        (Some(a), Some(b)) => (a[i] - b[i]).abs(),
                        _ => f64::NAN,
                    })
                    .fold(0.0, f64::max);
                format!("{:.0e}", e)
            })
            .collect();
        eprintln!("max at sample {at}; every 20th: {}", errs.join(" "));
    }
    err
}

/// `METHODS=radau5` runs Radau5 only.
fn methods() -> Vec<Method> {
    match std::env::var("METHODS").as_deref() {
        Ok("radau5") => vec![Method::Radau5],
        _ => vec![Method::Dop853, Method::Radau5],
    }
}

fn sweep<F: Formulation + Outputs + Clone>(name: &str, f: &F) -> Result<(), linkdyn::Error> {
    let reference_opts = SolverOptions::default()
        .method(Method::Dop853)
        .rtol(1e-13)
        .atol(1e-15)
        .build()?;
    let (reference, ref_stats) = run(f, &reference_opts)?;
    println!(
        "\n{name}: reference DOP853 rtol 1e-13: {} impacts, {} RHS calls",
        reference.events.len(),
        ref_stats.rhs_evals
    );
    println!(
        "{:>8} {:>8} {:>10} {:>10} {:>9} {:>7} {:>7} {:>7} {:>6} {:>15} {:>7} {:>9}",
        "method",
        "rtol",
        "error_rad",
        "end_err",
        "rhs",
        "jac",
        "newton",
        "steps",
        "rej",
        "err/newt/recov",
        "events",
        "wall_ms"
    );
    for method in methods() {
        let rtols: Vec<f64> = match std::env::var("RTOLS") {
            Ok(v) => v.split(',').filter_map(|x| x.parse().ok()).collect(),
            Err(_) => vec![1e-6, 1e-7, 1e-8, 1e-9, 1e-10],
        };
        for rtol in rtols {
            let opts = SolverOptions::default()
                .method(method)
                .rtol(rtol)
                .atol(rtol * 1e-3)
                .radau5(radau_settings())
                .build()?;
            let (rec, stats) = run(f, &opts)?;
            let mut best = f64::INFINITY;
            for _ in 0..5 {
                let start = Instant::now();
                run(f, &opts)?;
                best = best.min(start.elapsed().as_secs_f64());
            }
            println!(
                "{:>8} {:>8.0e} {:>10.2e} {:>10.2e} {:>9} {:>7} {:>7} {:>7} {:>6} {:>15} {:>7} {:>9.2}",
                method.name(),
                rtol,
                angle_error(&rec, &reference),
                end_error(&rec, &reference),
                stats.rhs_evals,
                stats.jacobian_evals,
                stats.newton_iterations,
                stats.steps,
                stats.rejected,
                format!(
                    "{}/{}/{}",
                    stats.error_test_failures, stats.newton_failures, stats.recovered_rejections
                ),
                rec.events.len(),
                best * 1e3
            );
        }
    }
    Ok(())
}

/// Radau5 settings: `RADAU5_THETA_JAC` (default 0.001) and `RADAU5_HAIRER_TOL` (1/0) from the
/// environment, for tuning runs.
fn radau_settings() -> Radau5Settings {
    let theta = std::env::var("RADAU5_THETA_JAC")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.001);
    let hairer = std::env::var("RADAU5_HAIRER_TOL").map_or(true, |v| v != "0");
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<f64>().ok());
    let mut s = Radau5Settings::default()
        .theta_jac(theta)
        .hairer_tolerances(hairer);
    s.newton_tol = env("RADAU5_NEWTON_TOL");
    if let Some(nit) = env("RADAU5_NIT") {
        s.max_newton_iter = nit as usize;
    }
    s
}

fn main() -> Result<(), linkdyn::Error> {
    let model = linkdyn::model::load("models/farahan2016.toml".as_ref(), &[])?;
    sweep("reduced", &ReducedLagrangian::new(&model)?)?;
    sweep("dae", &Dae::new(&model, &DaeOptions::default())?)?;
    Ok(())
}
