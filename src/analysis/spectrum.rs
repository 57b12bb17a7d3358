//! Amplitude spectrum of a sampled signal and its dominant peaks (the "FFT plots" of the
//! clearance-joint literature \[4\]).
//!
//! # Method
//! 1. **Uniform grid.** The N samples (t_i, x_i) are put on the uniform grid
//!    τ_j = t_0 + j·Δt, j = 0..N−1, Δt = (t_{N−1} − t_0)/(N − 1) (same count, same span). If every
//!    t_i is within 1e-9·Δt of τ_i the samples are used as they are (`resampled = false`), which is
//!    the case for [`integrate`](fn@crate::solve::integrate)'s output grid. Otherwise x is
//!    linearly interpolated at τ_j between its two neighbouring samples (`resampled = true`);
//!    linear interpolation damps a component of frequency f by at most
//!    sinc²(f·h_max) (h_max the largest input spacing), so it is only accurate well below the
//!    input's own Nyquist frequency.
//! 2. **Mean removal** (optional, on by default): x_j ← x_j − x̄, so that a large mean does not
//!    leak into the lowest bins (without it, the Hann window puts the mean's amplitude into
//!    bin 1 as well as bin 0). The mean x̄ is reported either way.
//! 3. **Window** w_j: Hann (default), w_j = ½(1 − cos(2πj/N)) (the periodic form, whose DFT is
//!    exactly N/2 at bin 0 and −N/4 at bins ±1), or rectangular, w_j = 1.
//! 4. **FFT** (`rustfft` \[1\]): X_k = Σ_j w_j x_j e^{−2πi jk/N}.
//! 5. **One-sided amplitude spectrum** at f_k = k/(N·Δt), k = 0..⌊N/2⌋:
//!    A_0 = |X_0|/S, A_k = 2|X_k|/S (0 < k < N/2), A_{N/2} = |X_{N/2}|/S (N even), with the window
//!    sum S = Σ_j w_j (N/2 for Hann, N for rectangular). This is the coherent-gain correction: a
//!    sine of amplitude A at a bin frequency reads exactly A, a constant c reads c at f = 0.
//! 6. **Peaks.** Bins k ≥ 1 that are local maxima (A_k > A_{k−1}, A_k ≥ A_{k+1}), at least
//!    `peak_threshold`·max_{k≥1} A_k and above the rounding floor 1e-9·max_j |x_j|, largest
//!    first, at most `max_peaks`. Each is refined with the window's known shape \[2, 3\]: a sine at
//!    the fractional bin k + δ (|δ| ≤ ½) has the magnitude ratio r = |X_{k±1}|/|X_k| to its larger
//!    neighbour
//!    * Hann: r = (1 + |δ|)/(2 − |δ|), so |δ| = (2r − 1)/(1 + r), amplitude A_k/G(δ) with
//!      G(δ) = sinc(δ)/(1 − δ²);
//!    * rectangular: r = |δ|/(1 − |δ|), so |δ| = r/(1 + r), amplitude A_k/sinc(δ);
//!
//!    with sinc(δ) = sin(πδ)/(πδ) and δ signed towards the larger neighbour (clamped to [0, ½]
//!    in magnitude). These are exact for one sine in the large-N limit; what is left is the
//!    leakage of the other components (Hann side lobes fall as 1/Δ³ with the distance Δ in bins,
//!    rectangular ones as 1/Δ) and the O(δ²/N²) difference between the Dirichlet kernel and
//!    sinc. Each peak also carries f/f_drive, its multiple of a given driving frequency.
//!
//! # References
//! 1. E. Allen et al., *RustFFT* (crate `rustfft`, version 6), <https://docs.rs/rustfft>.
//! 2. F. J. Harris, "On the use of windows for harmonic analysis with the discrete Fourier
//!    transform", *Proceedings of the IEEE* 66(1), 51–83, 1978.
//! 3. D. C. Rife, R. R. Boorstyn, "Single-tone parameter estimation from discrete-time
//!    observations", *IEEE Transactions on Information Theory* 20(5), 591–598, 1974.
//! 4. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, "Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance", *Journal of Theoretical and Applied
//!    Vibration and Acoustics* (2016), Figs. 5–6 (FFT of the response),
//!    <https://tava.isav.ir/article_19881.html>.

use std::f64::consts::PI;

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use serde::Serialize;

use super::error::{AnalysisError, check_finite};

/// Smallest signal length accepted: fewer samples give too few bins for a peak with two
/// neighbours.
pub const MIN_SAMPLES: usize = 8;

/// Relative deviation (in units of Δt) below which the input grid counts as uniform.
const UNIFORM_SLACK: f64 = 1e-9;

/// Peaks must exceed this multiple of max |x_j|: below it, bins hold FFT rounding noise
/// (≈ ε·log₂N of the signal size), not signal.
const ROUNDING_FLOOR: f64 = 1e-9;

/// Window applied before the FFT.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Window {
    /// Hann window ½(1 − cos(2πj/N)): side lobes fall as 1/Δ³, so neighbouring harmonics
    /// barely leak into each other. The default.
    Hann,
    /// No window (w = 1): the narrowest main lobe but side lobes falling only as 1/Δ.
    Rectangular,
}

/// Options of [`amplitude_spectrum`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpectrumOptions {
    /// Window (default [`Window::Hann`]).
    pub window: Window,
    /// Subtract the mean before windowing (default `true`).
    pub remove_mean: bool,
    /// Smallest peak amplitude, relative to the largest amplitude at f > 0 (default 0.01).
    pub peak_threshold: f64,
    /// Most peaks reported, largest first (default 20).
    pub max_peaks: usize,
    /// Driving frequency (Hz) to express the peaks as multiples of; `None` for none (default).
    pub driving_frequency: Option<f64>,
}

impl Default for SpectrumOptions {
    fn default() -> Self {
        Self {
            window: Window::Hann,
            remove_mean: true,
            peak_threshold: 0.01,
            max_peaks: 20,
            driving_frequency: None,
        }
    }
}

/// One dominant peak of a spectrum.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Peak {
    /// Refined frequency (Hz).
    pub frequency: f64,
    /// Refined amplitude (units of the signal).
    pub amplitude: f64,
    /// Bin k of the local maximum (frequency k/(N·Δt)).
    pub bin: usize,
    /// frequency / driving frequency, if one was given.
    pub multiple: Option<f64>,
}

/// One-sided amplitude spectrum of a signal (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spectrum {
    /// Bin frequencies f_k = k/(N·Δt) (Hz), k = 0..=N/2.
    pub frequencies: Vec<f64>,
    /// Amplitudes A_k (units of the signal).
    pub amplitudes: Vec<f64>,
    /// Sample interval Δt of the uniform grid (s).
    pub dt: f64,
    /// Number of samples N.
    pub n_samples: usize,
    /// Mean x̄ of the (resampled) signal.
    pub mean: f64,
    /// Whether the samples had to be interpolated onto a uniform grid.
    pub resampled: bool,
    /// Window used.
    pub window: Window,
    /// Dominant peaks, largest amplitude first.
    pub peaks: Vec<Peak>,
}

/// Amplitude spectrum of x sampled at times t (increasing, possibly non-uniform), with its
/// dominant peaks (see the module documentation for each step).
///
/// Errors: fewer than [`MIN_SAMPLES`] samples, t and x of different lengths, t not strictly
/// increasing, non-finite values, or out-of-range options.
///
/// ```
/// use linkdyn::analysis::spectrum::{amplitude_spectrum, SpectrumOptions};
/// let t: Vec<f64> = (0..1000).map(|i| i as f64 * 1e-3).collect();
/// let x: Vec<f64> = t.iter().map(|t| 2.0 * (2.0 * std::f64::consts::PI * 50.0 * t).sin()).collect();
/// let s = amplitude_spectrum(&t, &x, &SpectrumOptions::default())?;
/// assert!((s.peaks[0].frequency - 50.0).abs() < 1e-6 && (s.peaks[0].amplitude - 2.0).abs() < 1e-6);
/// # Ok::<(), linkdyn::analysis::AnalysisError>(())
/// ```
pub fn amplitude_spectrum(
    t: &[f64],
    x: &[f64],
    opts: &SpectrumOptions,
) -> Result<Spectrum, AnalysisError> {
    validate(t, x, opts)?;
    let n = t.len();
    let (mut signal, dt, resampled) = uniform(t, x);
    let mean = signal.iter().sum::<f64>() / n as f64;
    let scale = signal.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    if opts.remove_mean {
        signal.iter_mut().for_each(|v| *v -= mean);
    }
    let w = window(opts.window, n);
    let w_sum: f64 = w.iter().sum();
    let mut buf: Vec<Complex<f64>> = signal
        .iter()
        .zip(&w)
        .map(|(v, w)| Complex::new(v * w, 0.0))
        .collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);

    let half = n / 2;
    let mags: Vec<f64> = buf.iter().take(half + 1).map(|c| c.norm()).collect();
    let one_sided = |k: usize, m: f64| {
        // Bins 0 and N/2 (N even) have no negative-frequency twin to fold in.
        if k == 0 || (n.is_multiple_of(2) && k == half) {
            m / w_sum
        } else {
            2.0 * m / w_sum
        }
    };
    let amplitudes: Vec<f64> = mags
        .iter()
        .enumerate()
        .map(|(k, &m)| one_sided(k, m))
        .collect();
    let df = 1.0 / (n as f64 * dt);
    let frequencies: Vec<f64> = (0..=half).map(|k| k as f64 * df).collect();

    let a_max = amplitudes.iter().skip(1).fold(0.0_f64, |m, &a| m.max(a));
    let floor = (opts.peak_threshold * a_max).max(ROUNDING_FLOOR * scale);
    let mut peaks = Vec::new();
    for k in 1..=half {
        let a = amplitudes[k];
        let left = mags[k - 1];
        let right = mags.get(k + 1).copied();
        let is_max = mags[k] > left && right.is_none_or(|r| mags[k] >= r);
        if !is_max || a < floor || a <= 0.0 {
            continue;
        }
        let (delta, gain) = refine(opts.window, mags[k], left, right.unwrap_or(0.0));
        let frequency = (k as f64 + delta) * df;
        peaks.push(Peak {
            frequency,
            amplitude: one_sided(k, mags[k]) / gain,
            bin: k,
            multiple: opts.driving_frequency.map(|f_d| frequency / f_d),
        });
    }
    peaks.sort_by(|a, b| b.amplitude.total_cmp(&a.amplitude));
    peaks.truncate(opts.max_peaks);
    Ok(Spectrum {
        frequencies,
        amplitudes,
        dt,
        n_samples: n,
        mean,
        resampled,
        window: opts.window,
        peaks,
    })
}

fn validate(t: &[f64], x: &[f64], opts: &SpectrumOptions) -> Result<(), AnalysisError> {
    if t.len() != x.len() {
        return Err(AnalysisError::invalid(
            "signal",
            format!("t has {} samples but x has {}", t.len(), x.len()),
        ));
    }
    if t.len() < MIN_SAMPLES {
        return Err(AnalysisError::TooFewSamples {
            what: "spectrum signal",
            got: t.len(),
            need: MIN_SAMPLES,
        });
    }
    check_finite("t", t)?;
    check_finite("x", x)?;
    if let Some(i) = t.windows(2).position(|w| w[1] <= w[0]) {
        return Err(AnalysisError::invalid(
            "t",
            format!(
                "sample times must increase strictly, but t[{}] = {} s ≥ t[{}] = {} s",
                i,
                t[i],
                i + 1,
                t[i + 1]
            ),
        ));
    }
    if !(opts.peak_threshold.is_finite() && (0.0..=1.0).contains(&opts.peak_threshold)) {
        return Err(AnalysisError::invalid(
            "peak_threshold",
            format!(
                "expected a fraction in [0, 1] of the largest amplitude, got {}",
                opts.peak_threshold
            ),
        ));
    }
    if let Some(f_d) = opts.driving_frequency
        && !(f_d.is_finite() && f_d > 0.0)
    {
        return Err(AnalysisError::invalid(
            "driving_frequency",
            format!("expected a finite frequency > 0 Hz, got {f_d}"),
        ));
    }
    Ok(())
}

/// The signal on the uniform grid τ_j = t_0 + j·Δt (same N, same span), Δt, and whether it
/// had to be interpolated.
fn uniform(t: &[f64], x: &[f64]) -> (Vec<f64>, f64, bool) {
    let n = t.len();
    let t0 = t[0];
    let dt = (t[n - 1] - t0) / (n - 1) as f64;
    let on_grid = t
        .iter()
        .enumerate()
        .all(|(j, &ti)| (ti - (t0 + j as f64 * dt)).abs() <= UNIFORM_SLACK * dt);
    if on_grid {
        return (x.to_vec(), dt, false);
    }
    let mut out = Vec::with_capacity(n);
    let mut i = 0;
    for j in 0..n {
        let tau = if j == n - 1 {
            t[n - 1]
        } else {
            t0 + j as f64 * dt
        };
        // t is increasing and so is τ: the bracketing interval only moves forward.
        while i + 2 < n && t[i + 1] < tau {
            i += 1;
        }
        let s = ((tau - t[i]) / (t[i + 1] - t[i])).clamp(0.0, 1.0);
        out.push(x[i] + s * (x[i + 1] - x[i]));
    }
    (out, dt, true)
}

/// Window coefficients w_j, j = 0..N−1.
fn window(kind: Window, n: usize) -> Vec<f64> {
    match kind {
        Window::Rectangular => vec![1.0; n],
        Window::Hann => (0..n)
            .map(|j| 0.5 * (1.0 - (2.0 * PI * j as f64 / n as f64).cos()))
            .collect(),
    }
}

/// sin(πδ)/(πδ).
fn sinc(delta: f64) -> f64 {
    if delta.abs() < 1e-12 {
        1.0
    } else {
        (PI * delta).sin() / (PI * delta)
    }
}

/// Fractional bin offset δ of a peak at bin magnitude `m` with neighbour magnitudes `left`,
/// `right`, and the window's gain G(δ) there (see the module documentation).
fn refine(kind: Window, m: f64, left: f64, right: f64) -> (f64, f64) {
    let (r, sign) = if right >= left {
        (right / m, 1.0)
    } else {
        (left / m, -1.0)
    };
    let magnitude = match kind {
        Window::Hann => (2.0 * r - 1.0) / (1.0 + r),
        Window::Rectangular => r / (1.0 + r),
    }
    .clamp(0.0, 0.5);
    let delta = sign * magnitude;
    let gain = match kind {
        Window::Hann => sinc(delta) / (1.0 - delta * delta),
        Window::Rectangular => sinc(delta),
    };
    (delta, gain)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn window_shape_inverts_the_neighbour_ratio() {
        // Exact magnitudes of one sine at k + δ in the large-N limit, fed to `refine`.
        for kind in [Window::Hann, Window::Rectangular] {
            let shape = |d: f64| match kind {
                // The Hann shape is 0/0 at one bin from the peak; its limit there is ½.
                Window::Hann if (d.abs() - 1.0).abs() < 1e-9 => 0.5,
                Window::Hann => (sinc(d) / (1.0 - d * d)).abs(),
                Window::Rectangular => sinc(d).abs(),
            };
            for delta in [-0.45, -0.2, 0.0, 0.1, 0.3, 0.5] {
                let (got, gain) =
                    refine(kind, shape(delta), shape(delta + 1.0), shape(delta - 1.0));
                assert!(
                    (got - delta).abs() < 1e-12 && (gain - shape(delta)).abs() < 1e-12,
                    "{kind:?}: δ = {delta} recovered as {got}, gain {gain} vs {}",
                    shape(delta)
                );
            }
        }
    }

    #[test]
    fn non_uniform_grid_is_interpolated_linearly() {
        // A linear signal is reproduced exactly by linear interpolation.
        let t = [0.0, 0.5, 0.6, 1.5, 2.0, 2.2, 3.5, 4.0];
        let x: Vec<f64> = t.iter().map(|t| 3.0 * t - 1.0).collect();
        let (u, dt, resampled) = uniform(&t, &x);
        assert!(resampled);
        assert!((dt - 4.0 / 7.0).abs() < 1e-15, "Δt = {dt}");
        for (j, v) in u.iter().enumerate() {
            let expected = 3.0 * (j as f64 * dt) - 1.0;
            assert!(
                (v - expected).abs() < 1e-12,
                "sample {j}: {v} vs {expected}"
            );
        }
    }
}
