//! Claim: the end time is always sampled. Samples lie on t0 + k·dt_out and, when
//! t_end is not on that grid, one more sample lies exactly at t_end.

mod common;

use common::ode::{OdeRecorder, Oscillator};
use linkdyn::solve::{Method, SolveError, SolverOptions, integrate};

#[test]
fn the_end_time_is_always_sampled() -> Result<(), SolveError> {
    for method in Method::ALL {
        let opts = SolverOptions::default()
            .method(method)
            .rtol(1e-10)
            .atol(1e-12);
        // (t_end, dt_out, expected sample times)
        let cases: [(f64, f64, &[f64]); 3] = [
            (0.48, 0.3, &[0.0, 0.3, 0.48]),
            (0.48, 1.0, &[0.0, 0.48]),
            (0.5, 0.25, &[0.0, 0.25, 0.5]),
        ];
        for (t_end, dt_out, expected) in cases {
            let mut rec = OdeRecorder::default();
            let mut f = Oscillator { omega: 1.0 };
            integrate(&mut f, 0.0, &[1.0, 0.0], t_end, dt_out, &opts, &mut rec)?;
            let times: Vec<f64> = rec.samples.iter().map(|(t, _)| *t).collect();
            assert_eq!(times, expected, "{method}, t_end {t_end}, dt_out {dt_out}");
            // The last sample is the end state: cos t_end to the tolerance (rtol 1e-10 over
            // half a second: ~1e-10).
            let last = rec.samples.last().map(|(_, y)| y[0]).unwrap_or(f64::NAN);
            assert!(
                (last - t_end.cos()).abs() < 1e-9,
                "{method}, t_end {t_end}: x = {last} vs cos t_end = {}",
                t_end.cos()
            );
        }
    }
    Ok(())
}
