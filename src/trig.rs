//! Sine and cosine of one angle together, inlined into the right-hand side that calls them.
//!
//! The reduced formulation's right-hand side takes three (sin, cos) pairs per evaluation, and
//! through the C library's `sincos` they were 29 % of a whole run's instructions (callgrind,
//! farahan2016 at rtol 1e-9: 64.5 M of 223 M, ≈ 143 per call with its dispatch and its path for
//! huge arguments), out of line. This is the same algorithm as the C libraries' (fdlibm, as in
//! musl): reduction by the nearest multiple of π/2 in extended precision (Cody–Waite, π/2 in
//! three parts), then fdlibm's minimax kernels on [−π/4, π/4], each accurate to under one unit
//! in the last place. Written out here it is ≈ 95 instructions without a call for the angles a
//! linkage meets (|x| < 2^19·π/2 ≈ 8.2e5 rad), and the three pairs of an evaluation overlap;
//! larger or non-finite angles go to the C library. The results are within one unit in the
//! last place of the C library's (`tests` below, on 1.5 million angles), not always equal to
//! them: runs through this function differ from runs through `f64::sin_cos` in the last bits.
//!
//! Used by the reduced formulation only (`formulation::reduced_lagrangian`: its whole run
//! went from 1.97× to 1.78× the hand-written floor's time, docs/benchmarks.md). The DAE keeps
//! the C library's: its three bodies' sines are a small part of its evaluation (no change in
//! its time above the noise when measured), and its results stay as they were.
//!
//! The constants are fdlibm's, as the bit patterns it gives (Sun Microsystems, 1993: "Permission to use, copy, modify, and
//! distribute this software is freely granted, provided that this notice is preserved.").

/// 1.5 · 2^52: adding and subtracting it rounds a double of magnitude below 2^51 to the
/// nearest integer (ties to even) without a call.
const TO_INT: f64 = 6755399441055744.0;
/// 2/π.
const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
/// The first 33 bits of π/2: k · PIO2_1 is exact for |k| < 2^20.
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000);
/// π/2 − PIO2_1.
const PIO2_1T: f64 = f64::from_bits(0x3DD0_B461_1A62_6331);
/// The second 33 bits of π/2.
const PIO2_2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000);
/// π/2 − (PIO2_1 + PIO2_2).
const PIO2_2T: f64 = f64::from_bits(0x3BA3_198A_2E03_7073);
/// Below this |x| the reduction is done here: 2^19 · π/2 (fdlibm's medium range is 2^20 · π/2).
const REDUCE_HERE_BELOW: f64 = 823_549.6;
/// 2^−16: a first reduction below this fraction of |x| has cancelled about 16 bits.
const CANCELLED_16_BITS: f64 = 1.0 / 65536.0;

const S1: f64 = f64::from_bits(0xBFC5_5555_5555_5549);
const S2: f64 = f64::from_bits(0x3F81_1111_1110_F8A6);
const S3: f64 = f64::from_bits(0xBF2A_01A0_19C1_61D5);
const S4: f64 = f64::from_bits(0x3EC7_1DE3_57B1_FE7D);
const S5: f64 = f64::from_bits(0xBE5A_E5E6_8A2B_9CEB);
const S6: f64 = f64::from_bits(0x3DE5_D93A_5ACF_D57C);

const C1: f64 = f64::from_bits(0x3FA5_5555_5555_554C);
const C2: f64 = f64::from_bits(0xBF56_C16C_16C1_5177);
const C3: f64 = f64::from_bits(0x3EFA_01A0_19CB_1590);
const C4: f64 = f64::from_bits(0xBE92_7E4F_809C_52AD);
const C5: f64 = f64::from_bits(0x3E21_EE9E_BDB4_B1C4);
const C6: f64 = f64::from_bits(0xBDA8_FAE9_BE88_38D4);

/// (sin x, cos x), within one unit in the last place of `f64::sin_cos`.
#[inline(always)]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    // NaN, ±∞ and huge angles: the C library.
    if x.is_nan() || x.abs() >= REDUCE_HERE_BELOW {
        return x.sin_cos();
    }
    let (quadrant, r, r_tail) = reduce(x);
    let s = sin_kernel(r, r_tail);
    let c = cos_kernel(r, r_tail);
    // Quadrant k mod 4: (s, c), (c, −s), (−s, −c), (−c, s), without a branch (the crank's
    // angle moves through the quadrants).
    let (first, second) = if quadrant & 1 == 0 { (s, c) } else { (c, s) };
    let sin_sign = ((quadrant >> 1) & 1) << 63;
    let cos_sign = (((quadrant + 1) >> 1) & 1) << 63;
    (
        f64::from_bits(first.to_bits() ^ sin_sign),
        f64::from_bits(second.to_bits() ^ cos_sign),
    )
}

/// x = k·π/2 + (r + r_tail) with |r| ≲ π/4: (bits holding k mod 4, r, r_tail), r + r_tail good
/// to ≈ 85 bits
/// (fdlibm's `__rem_pio2`, medium range, one more round where the first lost many bits).
#[inline(always)]
fn reduce(x: f64) -> (u64, f64, f64) {
    let shifted = x * INV_PIO2 + TO_INT;
    // The nearest integer k sits in the low bits of `shifted` (two's complement for k < 0,
    // since 2^51 is a multiple of 4): k mod 4 without a conversion.
    let quadrant = shifted.to_bits();
    let k = shifted - TO_INT;
    let head = x - k * PIO2_1; // exact: k·PIO2_1 has at most 53 bits and is close to x
    let w = k * PIO2_1T;
    let mut r = head - w;
    let mut tail_correction = w;
    let mut head_used = head;
    // Where x lies close to a multiple of π/2 the first round cancels many bits: repeat with
    // the next 33 bits of π/2 (fdlibm's test: more than about 16 bits of x lost).
    if r.abs() < x.abs() * CANCELLED_16_BITS {
        let t = head;
        let w2 = k * PIO2_2;
        head_used = t - w2;
        tail_correction = k * PIO2_2T - ((t - head_used) - w2);
        r = head_used - tail_correction;
    }
    let r_tail = (head_used - r) - tail_correction;
    (quadrant, r, r_tail)
}

/// sin(r + r_tail) for |r| ≤ π/4 (fdlibm's `__kernel_sin` with its tail).
#[inline(always)]
fn sin_kernel(r: f64, r_tail: f64) -> f64 {
    let z = r * r;
    let w = z * z;
    let p = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let v = z * r;
    r - ((z * (0.5 * r_tail - v * p) - r_tail) - v * S1)
}

/// cos(r + r_tail) for |r| ≤ π/4 (fdlibm's `__kernel_cos` with its tail).
#[inline(always)]
fn cos_kernel(r: f64, r_tail: f64) -> f64 {
    let z = r * r;
    let w = z * z;
    let p = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let one_minus = 1.0 - hz;
    one_minus + (((1.0 - one_minus) - hz) + (z * p - r * r_tail))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place between two finite doubles of the same sign, or
    /// between two tiny ones (counted through zero).
    fn ulps(a: f64, b: f64) -> u64 {
        let key = |x: f64| {
            let bits = x.to_bits() as i64;
            if bits < 0 { i64::MIN - bits } else { bits }
        };
        key(a).abs_diff(key(b))
    }

    /// A reproducible stream of doubles in [0, 1).
    fn uniform(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    fn assert_close(x: f64) {
        let (s, c) = sin_cos(x);
        let (s_ref, c_ref) = x.sin_cos();
        assert!(
            ulps(s, s_ref) <= 1 && ulps(c, c_ref) <= 1,
            "x = {x:e}: sin {s:e} against {s_ref:e} ({} ulp), cos {c:e} against {c_ref:e} ({} ulp)",
            ulps(s, s_ref),
            ulps(c, c_ref)
        );
    }

    #[test]
    fn within_one_ulp_of_the_c_library_over_the_angles_a_linkage_meets() {
        let mut seed = 7;
        for _ in 0..400_000 {
            // Link angles, a crank angle after many turns, and small ones.
            assert_close((uniform(&mut seed) - 0.5) * 20.0);
            assert_close((uniform(&mut seed) - 0.5) * 2.0e4);
            assert_close((uniform(&mut seed) - 0.5) * 1.0e-3);
        }
    }

    #[test]
    fn within_one_ulp_next_to_multiples_of_half_pi_where_the_reduction_cancels() {
        let mut seed = 11;
        for k in -20_000i64..20_000 {
            let centre = k as f64 * std::f64::consts::FRAC_PI_2;
            for step in [0i64, 1, -1, 2, -7, 1000, -1000] {
                let bits = centre.to_bits() as i64 + step;
                assert_close(f64::from_bits(bits as u64));
            }
            assert_close(centre + (uniform(&mut seed) - 0.5) * 1e-9);
        }
    }

    #[test]
    fn exact_values_and_the_c_library_beyond_the_reduction_range() {
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0f64).to_bits());
        assert_eq!(sin_cos(1e-300), (1e-300, 1.0));
        for x in [1e6, -3.5e7, 1e300, f64::MAX] {
            assert_eq!(sin_cos(x), x.sin_cos());
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let (s, c) = sin_cos(x);
            assert!(s.is_nan() && c.is_nan());
        }
        // Across the switch to the C library nothing jumps.
        for x in [
            REDUCE_HERE_BELOW * 0.999_999,
            -REDUCE_HERE_BELOW * 0.999_999,
        ] {
            assert_close(x);
        }
    }
}
