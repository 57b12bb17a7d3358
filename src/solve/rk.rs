//! Kernels shared by the explicit Runge–Kutta methods: counted right-hand-side calls, stage
//! sums y + h Σ a_j k_j, and the error scale of Hairer's error norm.

use super::error::SolveError;
use crate::formulation::Formulation;

/// Buffers one step works in (all of length n, allocated once by the stepper).
pub(crate) struct StepBuffers<'a> {
    /// Stage derivatives; `k[0]` must hold f(t, y) on entry.
    pub k: &'a mut [Vec<f64>],
    /// Receives y_new.
    pub y_new: &'a mut [f64],
    /// Scratch for stage arguments.
    pub y_stage: &'a mut [f64],
}

/// Evaluates dy = f(t, y), counts the call in `evals` and attaches t to a failure.
pub(crate) fn eval_rhs<F: Formulation + ?Sized>(
    f: &F,
    t: f64,
    y: &[f64],
    dy: &mut [f64],
    evals: &mut u64,
) -> Result<(), SolveError> {
    *evals += 1;
    f.rhs(t, y, dy)
        .map_err(|source| SolveError::Formulation { t, source })
}

/// out = y + h Σ_j coeffs_j k_j. Zero coefficients are skipped (the DOP853 tableau is sparse).
///
/// A mechanism of a few states (the reduced four-bar has 5) gets a copy of the loop for its
/// exact length, unrolled by the compiler: the general loop over a 5-vector per stage was
/// mostly loop overhead (a sixth of a reduced run). Same additions in the same order either
/// way, so the results are the same to the bit.
pub(crate) fn combine(y: &[f64], h: f64, coeffs: &[f64], k: &[Vec<f64>], out: &mut [f64]) {
    // Up to 24 states: the reduced four-bar (5), the DAE four-bar (19), small chains.
    macro_rules! by_length {
        ($($n:literal)*) => {
            match y.len() {
                $($n => combine_fixed::<$n>(y, h, coeffs, k, out),)*
                _ => false,
            }
        };
    }
    let done = by_length!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24);
    if !done {
        combine_any(y, h, coeffs, k, out);
    }
}

/// [`combine`] for vectors of length N; false (nothing written) where a vector is not.
fn combine_fixed<const N: usize>(
    y: &[f64],
    h: f64,
    coeffs: &[f64],
    k: &[Vec<f64>],
    out: &mut [f64],
) -> bool {
    let (Some(y), Some(out)) = (y.first_chunk::<N>(), out.first_chunk_mut::<N>()) else {
        return false;
    };
    let mut acc = *y;
    for (&a, kj) in coeffs.iter().zip(k) {
        if a != 0.0 {
            let ha = h * a;
            let Some(kj) = kj.first_chunk::<N>() else {
                return false;
            };
            for (o, &v) in acc.iter_mut().zip(kj) {
                *o += ha * v;
            }
        }
    }
    *out = acc;
    true
}

/// The nonzero coefficients (j, a_j) of one row of a Butcher tableau, in the order of j, found
/// at compile time: the stage sums of a fixed-size step ([`combine_stages`]) then skip the
/// tableau's zeros without testing each one (DOP853's rows are a third zeros).
#[derive(Debug, Clone, Copy)]
pub(crate) struct NonzeroRow {
    entries: [(usize, f64); MAX_ROW],
    len: usize,
}

/// Longest tableau row [`NonzeroRow`] holds (DOP853's dense-output rows have 16 entries).
const MAX_ROW: usize = 16;

impl NonzeroRow {
    /// The nonzero entries of `row` (at most [`MAX_ROW`] long; longer rows fail to compile
    /// where the constant is built).
    pub(crate) const fn of(row: &[f64]) -> NonzeroRow {
        let mut entries = [(0, 0.0); MAX_ROW];
        let mut len = 0;
        let mut j = 0;
        while j < row.len() {
            // As `combine`: an entry equal to zero (of either sign) adds nothing and is skipped.
            if row[j] != 0.0 {
                entries[len] = (j, row[j]);
                len += 1;
            }
            j += 1;
        }
        NonzeroRow { entries, len }
    }

    /// The entries (j, a_j).
    #[inline(always)]
    pub(crate) fn entries(&self) -> &[(usize, f64)] {
        self.entries.get(..self.len).unwrap_or(&[])
    }
}

/// out = y + h Σ_j a_j k_j over the nonzero entries of a tableau row, for vectors of length N
/// with the stage vectors in a fixed-size array: the sums of [`combine`] (the same products
/// h·a_j and additions in the same order, so the same bits). Called with a constant row, the
/// loop over its entries unrolls into straight-line sums over known stages.
#[inline(always)]
pub(crate) fn combine_stages<const N: usize, const S: usize>(
    y: &[f64; N],
    h: f64,
    row: &NonzeroRow,
    k: &[[f64; N]; S],
    out: &mut [f64; N],
) {
    let mut acc = *y;
    for &(j, a) in row.entries() {
        // A row refers to earlier stages only; the tables are checked by the tests.
        let Some(kj) = k.get(j) else {
            debug_assert!(false, "tableau entry for stage {j} of {S}");
            continue;
        };
        let ha = h * a;
        for (o, &v) in acc.iter_mut().zip(kj) {
            *o += ha * v;
        }
    }
    *out = acc;
}

/// [`combine_stages`] with the stage vectors by reference.
#[inline(always)]
pub(crate) fn combine_refs<const N: usize, const S: usize>(
    y: &[f64; N],
    h: f64,
    row: &NonzeroRow,
    k: &[&[f64; N]; S],
    out: &mut [f64; N],
) {
    let mut acc = *y;
    for &(j, a) in row.entries() {
        let Some(kj) = k.get(j) else {
            debug_assert!(false, "tableau entry for stage {j} of {S}");
            continue;
        };
        let ha = h * a;
        for (o, &v) in acc.iter_mut().zip(kj.iter()) {
            *o += ha * v;
        }
    }
    *out = acc;
}

/// [`combine`] for any length.
pub(crate) fn combine_any(y: &[f64], h: f64, coeffs: &[f64], k: &[Vec<f64>], out: &mut [f64]) {
    out.copy_from_slice(y);
    for (&a, kj) in coeffs.iter().zip(k) {
        if a != 0.0 {
            let ha = h * a;
            for (o, &v) in out.iter_mut().zip(kj) {
                *o += ha * v;
            }
        }
    }
}

/// out = Σ_j coeffs_j k_j (zero coefficients skipped): [`combine`] from zero.
pub(crate) fn weighted_sum(coeffs: &[f64], k: &[Vec<f64>], out: &mut [f64]) {
    let zero = [0.0; 24];
    match zero.get(..out.len()) {
        // 0 + a·k is a·k exactly (and +0 for −0, as the loop from a zero vector gives).
        Some(zero) => {
            let mut sum = [0.0; 24];
            let n = out.len();
            combine(zero, 1.0, coeffs, k, &mut sum[..n]);
            out.copy_from_slice(&sum[..n]);
        }
        None => {
            out.fill(0.0);
            for (&a, kj) in coeffs.iter().zip(k) {
                if a != 0.0 {
                    for (o, &v) in out.iter_mut().zip(kj) {
                        *o += a * v;
                    }
                }
            }
        }
    }
}

/// err / sk, where sk = atol + rtol·max(|y_i|, |y_new_i|) is the error scale of component i.
/// With atol = 0 a component that is exactly zero has sk = 0: a zero error then counts as 0,
/// any other error as infinitely large (the step is rejected).
#[inline]
pub(crate) fn scaled(err: f64, y: f64, y_new: f64, rtol: f64, atol: f64) -> f64 {
    let sk = atol + rtol * y.abs().max(y_new.abs());
    if sk > 0.0 {
        err / sk
    } else if err == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// Index of the first NaN or infinite entry.
pub(crate) fn first_non_finite(v: &[f64]) -> Option<usize> {
    v.iter().position(|x| !x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The copies for fixed lengths give the general loop's results to the bit (zeros in the
    /// tableau, signed zeros and every length they cover included), so that a run does not
    /// depend on which one ran.
    #[test]
    fn fixed_length_sums_equal_the_general_loop_bit_for_bit() {
        let mut state = 0x2545_F491_4F6C_DD1D_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for n in 1..=30 {
            let k: Vec<Vec<f64>> = (0..16)
                .map(|_| {
                    (0..n)
                        .map(|i| if i == 0 { -0.0 } else { next() * 1e3 })
                        .collect()
                })
                .collect();
            let y: Vec<f64> = (0..n).map(|_| next()).collect();
            let coeffs: Vec<f64> = (0..16)
                .map(|j| if j % 3 == 1 { 0.0 } else { next() })
                .collect();
            let (mut fast, mut plain) = (vec![0.0; n], vec![0.0; n]);
            combine(&y, 1e-3, &coeffs, &k, &mut fast);
            combine_any(&y, 1e-3, &coeffs, &k, &mut plain);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fast), bits(&plain), "combine, n = {n}");
            weighted_sum(&coeffs, &k, &mut fast);
            plain.fill(0.0);
            for (&a, kj) in coeffs.iter().zip(&k) {
                if a != 0.0 {
                    for (o, &v) in plain.iter_mut().zip(kj) {
                        *o += a * v;
                    }
                }
            }
            assert_eq!(bits(&fast), bits(&plain), "weighted_sum, n = {n}");
        }
    }

    #[test]
    fn combine_adds_weighted_stages() {
        let k = vec![vec![1.0, 2.0], vec![10.0, 20.0], vec![100.0, 200.0]];
        let mut out = [0.0; 2];
        combine(&[1.0, 1.0], 0.5, &[1.0, 0.0, 2.0], &k, &mut out);
        assert_eq!(out, [1.0 + 0.5 + 100.0, 1.0 + 1.0 + 200.0]);
        weighted_sum(&[1.0, 0.0, 2.0], &k, &mut out);
        assert_eq!(out, [201.0, 402.0]);
    }

    #[test]
    fn scale_handles_zero_tolerance() {
        assert_eq!(scaled(1e-9, 1.0, -2.0, 1e-6, 1e-9), 1e-9 / (1e-9 + 2e-6));
        assert_eq!(scaled(0.0, 0.0, 0.0, 1e-6, 0.0), 0.0);
        assert_eq!(scaled(1e-30, 0.0, 0.0, 1e-6, 0.0), f64::INFINITY);
        assert_eq!(first_non_finite(&[1.0, f64::NAN]), Some(1));
        assert_eq!(first_non_finite(&[1.0]), None);
    }
}
