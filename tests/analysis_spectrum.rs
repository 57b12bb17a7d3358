//! Amplitude spectra recover the frequencies and amplitudes of known signals
//! (`linkdyn::analysis::spectrum`).

use std::f64::consts::PI;

use linkdyn::analysis::spectrum::{MIN_SAMPLES, amplitude_spectrum};
use linkdyn::analysis::{AnalysisError, SpectrumOptions, Window};

/// Components (frequency Hz, amplitude, phase rad): none on a bin (bins are 1/(N·Δt) = 0.25 Hz
/// apart here: 49.5, 100.4 and 162.4 bins), at least 51 bins apart, amplitudes spanning a
/// factor 30.
const COMPONENTS: [(f64, f64, f64); 3] = [(12.37, 1.5, 0.3), (25.11, 0.4, 1.1), (40.6, 0.05, -2.0)];
const N: usize = 4000;
const DT: f64 = 1e-3;

fn sum_of_sines(t: &[f64], offset: f64) -> Vec<f64> {
    t.iter()
        .map(|t| {
            offset
                + COMPONENTS
                    .iter()
                    .map(|(f, a, p)| a * (2.0 * PI * f * t + p).sin())
                    .sum::<f64>()
        })
        .collect()
}

fn grid() -> Vec<f64> {
    (0..N).map(|i| i as f64 * DT).collect()
}

fn check_peaks(
    case: &str,
    opts: &SpectrumOptions,
    t: &[f64],
    x: &[f64],
    df_bins: f64,
    da_rel: f64,
) {
    let s = match amplitude_spectrum(t, x, opts) {
        Ok(s) => s,
        Err(e) => panic!("{case}: {e}"),
    };
    let bin = 1.0 / (s.n_samples as f64 * s.dt);
    assert!(
        s.peaks.len() >= COMPONENTS.len(),
        "{case}: {} peaks found, {} expected",
        s.peaks.len(),
        COMPONENTS.len()
    );
    for (i, (f, a, _)) in COMPONENTS.iter().enumerate() {
        // Largest first: the peaks come in the order of COMPONENTS' amplitudes.
        let p = &s.peaks[i];
        assert!(
            (p.frequency - f).abs() <= df_bins * bin,
            "{case}: component {i}: frequency {} Hz vs {f} Hz (bound {df_bins} bins)",
            p.frequency
        );
        assert!(
            (p.amplitude - a).abs() <= da_rel * a,
            "{case}: component {i}: amplitude {} vs {a} (bound {da_rel} relative)",
            p.amplitude
        );
        let multiple = p.multiple.unwrap_or(f64::NAN);
        assert!(
            (multiple - p.frequency / 12.37).abs() < 1e-12,
            "{case}: multiple {multiple} of the driving frequency"
        );
    }
}

#[test]
fn hann_recovers_off_bin_sines() {
    let t = grid();
    let x = sum_of_sines(&t, 0.7);
    let opts = SpectrumOptions {
        driving_frequency: Some(12.37),
        peak_threshold: 0.005,
        ..SpectrumOptions::default()
    };
    // Bounds: the components are ≥ 51 bins apart; a Hann side lobe at Δ bins is
    // ≤ 1/(πΔ(Δ² − 1)) ≈ 2.4e-6 of its component, ≈ 7e-5 of the smallest one (30 times smaller
    // than the largest). Measured: ≤ 3e-5 bins and ≤ 3e-6 relative. Bounds 1e-3 bins, 3e-4.
    check_peaks("Hann", &opts, &t, &x, 1e-3, 3e-4);
}

#[test]
fn rectangular_window_recovers_the_largest_sine() {
    let t = grid();
    let x: Vec<f64> = t
        .iter()
        .map(|t| 2.0 * (2.0 * PI * 12.37 * t).cos())
        .collect();
    let opts = SpectrumOptions {
        window: Window::Rectangular,
        driving_frequency: Some(12.37),
        ..SpectrumOptions::default()
    };
    let s = amplitude_spectrum(&t, &x, &opts).map_err(|e| e.to_string());
    let peak = s.as_ref().ok().and_then(|s| s.peaks.first().cloned());
    let Some(p) = peak else {
        panic!("rectangular: no peak: {s:?}");
    };
    // One sine: only its own negative-frequency image leaks in, at 2·49.5 bins with the
    // rectangular 1/(πΔ) side lobe: ≈ 3e-3 relative. Measured 2.5e-3 bins and 1.1e-4
    // relative; bounds 0.01 bins and 1 %.
    assert!(
        (p.frequency - 12.37).abs() < 0.01 * 0.25 && (p.amplitude - 2.0).abs() < 0.01 * 2.0,
        "rectangular: peak {} Hz, amplitude {} (expected 12.37 Hz, 2)",
        p.frequency,
        p.amplitude
    );
    assert!(
        (p.multiple.unwrap_or(0.0) - 1.0).abs() < 1e-3,
        "multiple {:?}",
        p.multiple
    );
}

#[test]
fn non_uniform_grid_is_resampled() {
    // Jitter of ±0.2 Δt around the uniform grid (ends kept); linear interpolation damps a
    // component at f by ≤ 1 − sinc²(f·h_max) ≈ (π·40.6·1.4e-3)²/3 ≈ 1e-2 for the highest one,
    // ≈ 1e-3 for the largest: amplitudes to 2 % (measured ≤ 4.2e-3). Interpolation does not
    // move frequencies: 1e-3 bins as on the uniform grid (measured 3e-5).
    let t: Vec<f64> = (0..N)
        .map(|i| {
            let jitter = if i == 0 || i == N - 1 {
                0.0
            } else {
                0.2 * DT * ((i as f64) * 1.7).sin()
            };
            i as f64 * DT + jitter
        })
        .collect();
    let x = sum_of_sines(&t, 0.0);
    let opts = SpectrumOptions {
        driving_frequency: Some(12.37),
        peak_threshold: 0.005,
        ..SpectrumOptions::default()
    };
    let resampled = amplitude_spectrum(&t, &x, &opts).map(|s| s.resampled);
    assert!(matches!(resampled, Ok(true)), "{resampled:?}");
    check_peaks("jittered grid", &opts, &t, &x, 1e-3, 2e-2);
}

#[test]
fn pure_dc_has_no_peaks() {
    let t = grid();
    let x = vec![3.25; N];
    for remove_mean in [true, false] {
        for window in [Window::Hann, Window::Rectangular] {
            let opts = SpectrumOptions {
                remove_mean,
                window,
                ..SpectrumOptions::default()
            };
            let s = match amplitude_spectrum(&t, &x, &opts) {
                Ok(s) => s,
                Err(e) => panic!("DC: {e}"),
            };
            let case = format!("DC, remove_mean = {remove_mean}, {window:?}");
            assert!(s.peaks.is_empty(), "{case}: peaks {:?}", s.peaks);
            assert!((s.mean - 3.25).abs() < 1e-12, "{case}: mean {}", s.mean);
            // The f = 0 bin reads the constant (coherent-gain correction), or 0 once removed.
            let a0 = if remove_mean { 0.0 } else { 3.25 };
            assert!(
                (s.amplitudes[0] - a0).abs() < 1e-12,
                "{case}: A_0 = {} vs {a0}",
                s.amplitudes[0]
            );
        }
    }
}

#[test]
fn too_short_and_bad_signals_are_errors() {
    let t: Vec<f64> = (0..MIN_SAMPLES - 1).map(|i| i as f64).collect();
    let x = vec![0.0; t.len()];
    let e = amplitude_spectrum(&t, &x, &SpectrumOptions::default()).err();
    assert!(
        matches!(
            e,
            Some(AnalysisError::TooFewSamples {
                got: 7,
                need: 8,
                ..
            })
        ),
        "{e:?}"
    );
    assert_eq!(
        e.map(|e| e.to_string()).as_deref(),
        Some("spectrum signal: 7 samples, at least 8 needed")
    );

    let t = [0.0, 1.0, 2.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    let e = amplitude_spectrum(&t, &[0.0; 8], &SpectrumOptions::default()).err();
    assert_eq!(
        e.map(|e| e.to_string()).as_deref(),
        Some("invalid t: sample times must increase strictly, but t[2] = 2 s ≥ t[3] = 2 s")
    );
    let t: Vec<f64> = (0..8).map(f64::from).collect();
    let e = amplitude_spectrum(&t, &[0.0; 7], &SpectrumOptions::default()).err();
    assert_eq!(
        e.map(|e| e.to_string()).as_deref(),
        Some("invalid signal: t has 8 samples but x has 7")
    );
}
