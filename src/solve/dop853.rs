//! DOP853: Hairer's explicit Runge–Kutta pair of order 8 with embedded 5th- and 3rd-order error
//! estimators and a 7th-order continuous extension \[1, Sec. II.10; code `dop853.f`\].
//!
//! One step from (t, y) with size h uses 12 stages k_0..k_11 (k_0 = f(t, y) is the FSAL stage
//! of the previous step) and gives y_new = y + h Σ b_i k_i; k_12 = f(t + h, y_new) is evaluated
//! once the step is accepted and becomes the next k_0 (12 RHS calls per accepted step, 11 per
//! rejected one).
//!
//! **Error norm** (combined estimate of `dop853.f`, as in SciPy's `DOP853._estimate_error_norm`):
//! with sk_i = atol + rtol·max(|y_i|, |y_new_i|), err5_i = Σ E5_j k_j[i],
//! err3_i = Σ (b_j − bhh_j) k_j[i], s5 = Σ (err5_i/sk_i)², s3 = Σ (err3_i/sk_i)²:
//! ‖err‖ = |h| s5 / sqrt(n (s5 + 0.01 s3)), which behaves like h⁸ for small h.
//!
//! **Dense output** on θ = (t* − t_old)/h needs three more stages k_13..k_15 (nodes 0.1, 0.2,
//! 7/9), computed only when the step is interpolated:
//! F₀ = Δy, F₁ = h k_0 − Δy, F₂ = 2Δy − h (k_12 + k_0), F₃₊ᵣ = h Σ_j D_rj k_j (r = 0..3), and
//! y(θ) = y_old + θ (F₀ + (1−θ)(F₁ + θ (F₂ + (1−θ)(F₃ + θ (F₄ + (1−θ)(F₅ + θ F₆)))))).
//!
//! The coefficients are copied with all their digits from SciPy's
//! `scipy/integrate/_ivp/dop853_coefficients.py` \[2\] (a transcription of Hairer's `dop853.f`);
//! indices are SciPy's (0-based).
//!
//! # References
//! 1. E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I:
//!    Nonstiff Problems*, 2nd ed., Springer, 1993, Sec. II.10; Fortran code `dop853.f`
//!    (<http://www.unige.ch/~hairer/software.html>).
//! 2. SciPy, `scipy/integrate/_ivp/dop853_coefficients.py` and `rk.py` (class `DOP853`),
//!    <https://github.com/scipy/scipy>.
//! 3. P. J. Prince, J. R. Dormand, "High order embedded Runge–Kutta formulae", *J. Comput. Appl.
//!    Math.* 7(1), 67–75, 1981.

// The literals below keep every digit of the published coefficients; rounding them by hand to
// 17 significant digits would only add a chance of transcription errors.
#![allow(clippy::excessive_precision)]

use super::control::ControlParams;
use super::error::SolveError;
use super::explicit::{DenseInput, Pair};
use super::integrator::{ErrorWeights, Trial};
use super::options::Method;
use super::rk::{
    NonzeroRow, StepBuffers, combine, combine_refs, combine_stages, eval_rhs, scaled, weighted_sum,
};
use super::stats::SolverStats;
use crate::formulation::Formulation;

/// The DOP853 pair (a marker for [`ExplicitRk`](super::explicit::ExplicitRk)).
pub(crate) struct Dop853;

impl Pair for Dop853 {
    const METHOD: Method = Method::Dop853;
    const STAGES: usize = STAGES;
    const FSAL: usize = FSAL;
    const LAST_STAGE: usize = N_STAGES - 1;
    const DENSE_VECTORS: usize = DENSE_VECTORS;
    const CONTROL: ControlParams = ControlParams {
        q: 8.0,
        kappa: 0.2,
        fac_min: 0.333,
        fac_max: 6.0,
    };
    /// Hairer's `dop853.f` (hλ > 6.1).
    const STABILITY_BOUNDARY: f64 = 6.1;

    fn stages<F: Formulation + ?Sized>(
        f: &F,
        trial: &Trial<'_>,
        buf: StepBuffers<'_>,
        evals: &mut u64,
    ) -> Result<(), SolveError> {
        step(f, trial.t, trial.h, trial.y, buf, evals)
    }

    fn error_norm(
        h: f64,
        y: &[f64],
        y_new: &[f64],
        k: &[Vec<f64>],
        weights: &ErrorWeights,
        scratch: (&mut [f64], &mut [f64]),
    ) -> f64 {
        error_norm(h, y, y_new, k, weights, scratch)
    }

    fn after_accept<F: Formulation + ?Sized>(
        f: &F,
        t_new: f64,
        y_new: &[f64],
        k: &mut [Vec<f64>],
        evals: &mut u64,
    ) -> Result<(), SolveError> {
        fsal(f, t_new, y_new, k, evals)
    }

    fn prepare_dense<F: Formulation + ?Sized>(
        f: &F,
        step: &DenseInput<'_>,
        k: &mut [Vec<f64>],
        dense: &mut [Vec<f64>],
        y_stage: &mut [f64],
        stats: &mut SolverStats,
    ) -> Result<(), SolveError> {
        extra_stages(
            f,
            step.t_old,
            step.h,
            step.y_old,
            k,
            y_stage,
            &mut stats.rhs_evals,
        )?;
        stats.dense_evals += DENSE_EXTRA_EVALS;
        dense_vectors(step.h, step.y_old, step.y_new, k, dense);
        Ok(())
    }

    fn eval_dense(theta: f64, y_old: &[f64], dense: &[Vec<f64>], out: &mut [f64]) {
        eval_dense(theta, y_old, dense, out);
    }
}

/// Stages of one step proper (k_0..k_11).
pub(crate) const N_STAGES: usize = 12;
/// Index of the FSAL stage k_12 = f(t + h, y_new).
pub(crate) const FSAL: usize = 12;
/// Stage vectors kept per step: 12 stages, the FSAL stage and 3 dense-output stages.
pub(crate) const STAGES: usize = 16;
/// Vectors F₀..F₆ of the dense output.
pub(crate) const DENSE_VECTORS: usize = 7;
/// Extra RHS calls per interpolated step.
pub(crate) const DENSE_EXTRA_EVALS: u64 = 3;

/// Nodes c_i (SciPy `C`, 16 entries: 12 stages, the FSAL stage 12 at c = 1, and the
/// three extra dense-output stages 13, 14, 15).
pub(crate) const C: [f64; 16] = [
    0.0,
    0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
    1.0,
    0.1,
    0.2,
    0.777777777777777777777777777778,
];

/// Lower-triangular coupling coefficients a_ij (SciPy `A`): row i holds a_i0 .. a_i(i-1).
/// Row 12 is the weight vector b (the FSAL stage is evaluated at y_new); rows 13..15 are
/// the extra stages of the dense output.
pub(crate) const A: [&[f64]; 16] = [
    &[],
    // row 1
    &[5.26001519587677318785587544488e-2],
    // row 2
    &[
        1.97250569845378994544595329183e-2,
        5.91751709536136983633785987549e-2,
    ],
    // row 3
    &[
        2.95875854768068491816892993775e-2,
        0.0,
        8.87627564304205475450678981324e-2,
    ],
    // row 4
    &[
        2.41365134159266685502369798665e-1,
        0.0,
        -8.84549479328286085344864962717e-1,
        9.24834003261792003115737966543e-1,
    ],
    // row 5
    &[
        3.7037037037037037037037037037e-2,
        0.0,
        0.0,
        1.70828608729473871279604482173e-1,
        1.25467687566822425016691814123e-1,
    ],
    // row 6
    &[
        3.7109375e-2,
        0.0,
        0.0,
        1.70252211019544039314978060272e-1,
        6.02165389804559606850219397283e-2,
        -1.7578125e-2,
    ],
    // row 7
    &[
        3.70920001185047927108779319836e-2,
        0.0,
        0.0,
        1.70383925712239993810214054705e-1,
        1.07262030446373284651809199168e-1,
        -1.53194377486244017527936158236e-2,
        8.27378916381402288758473766002e-3,
    ],
    // row 8
    &[
        6.24110958716075717114429577812e-1,
        0.0,
        0.0,
        -3.36089262944694129406857109825,
        -8.68219346841726006818189891453e-1,
        2.75920996994467083049415600797e1,
        2.01540675504778934086186788979e1,
        -4.34898841810699588477366255144e1,
    ],
    // row 9
    &[
        4.77662536438264365890433908527e-1,
        0.0,
        0.0,
        -2.48811461997166764192642586468,
        -5.90290826836842996371446475743e-1,
        2.12300514481811942347288949897e1,
        1.52792336328824235832596922938e1,
        -3.32882109689848629194453265587e1,
        -2.03312017085086261358222928593e-2,
    ],
    // row 10
    &[
        -9.3714243008598732571704021658e-1,
        0.0,
        0.0,
        5.18637242884406370830023853209,
        1.09143734899672957818500254654,
        -8.14978701074692612513997267357,
        -1.85200656599969598641566180701e1,
        2.27394870993505042818970056734e1,
        2.49360555267965238987089396762,
        -3.0467644718982195003823669022,
    ],
    // row 11
    &[
        2.27331014751653820792359768449,
        0.0,
        0.0,
        -1.05344954667372501984066689879e1,
        -2.00087205822486249909675718444,
        -1.79589318631187989172765950534e1,
        2.79488845294199600508499808837e1,
        -2.85899827713502369474065508674,
        -8.87285693353062954433549289258,
        1.23605671757943030647266201528e1,
        6.43392746015763530355970484046e-1,
    ],
    // row 12
    &[
        5.42937341165687622380535766363e-2,
        0.0,
        0.0,
        0.0,
        0.0,
        4.45031289275240888144113950566,
        1.89151789931450038304281599044,
        -5.8012039600105847814672114227,
        3.1116436695781989440891606237e-1,
        -1.52160949662516078556178806805e-1,
        2.01365400804030348374776537501e-1,
        4.47106157277725905176885569043e-2,
    ],
    // row 13
    &[
        5.61675022830479523392909219681e-2,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        2.53500210216624811088794765333e-1,
        -2.46239037470802489917441475441e-1,
        -1.24191423263816360469010140626e-1,
        1.5329179827876569731206322685e-1,
        8.20105229563468988491666602057e-3,
        7.56789766054569976138603589584e-3,
        -8.298e-3,
    ],
    // row 14
    &[
        3.18346481635021405060768473261e-2,
        0.0,
        0.0,
        0.0,
        0.0,
        2.83009096723667755288322961402e-2,
        5.35419883074385676223797384372e-2,
        -5.49237485713909884646569340306e-2,
        0.0,
        0.0,
        -1.08347328697249322858509316994e-4,
        3.82571090835658412954920192323e-4,
        -3.40465008687404560802977114492e-4,
        1.41312443674632500278074618366e-1,
    ],
    // row 15
    &[
        -4.28896301583791923408573538692e-1,
        0.0,
        0.0,
        0.0,
        0.0,
        -4.69762141536116384314449447206,
        7.68342119606259904184240953878,
        4.06898981839711007970213554331,
        3.56727187455281109270669543021e-1,
        0.0,
        0.0,
        0.0,
        -1.39902416515901462129418009734e-3,
        2.9475147891527723389556272149,
        -9.15095847217987001081870187138,
    ],
];

/// Weights b_i of the 8th-order solution (row 12 of [`A`]; SciPy `B = A[12, :12]`).
pub(crate) const B: &[f64] = A[12];

/// Coefficients of the 5th-order error estimate err5 = Σ E5_i k_i (SciPy `E5`, 12 stages;
/// SciPy's 13th entry, for the FSAL stage, is zero).
pub(crate) const E5: [f64; 12] = [
    0.1312004499419488073250102996e-1,
    0.0,
    0.0,
    0.0,
    0.0,
    -0.1225156446376204440720569753e+1,
    -0.4957589496572501915214079952,
    0.1664377182454986536961530415e+1,
    -0.3503288487499736816886487290,
    0.3341791187130174790297318841,
    0.8192320648511571246570742613e-1,
    -0.2235530786388629525884427845e-1,
];

/// Weights `bhh` of the 3rd-order embedded solution: SciPy forms `E3 = B - bhh`, subtracting
/// these three values from b_0, b_8 and b_11.
pub(crate) const BHH: [(usize, f64); 3] = [
    (0, 0.244094488188976377952755905512),
    (8, 0.733846688281611857341361741547),
    (11, 0.220588235294117647058823529412e-1),
];

/// Dense-output coefficients (SciPy `D`, 4 rows × 16 stages): the 4th..7th polynomial
/// coefficients are h Σ_j D_rj k_j.
pub(crate) const D: [[f64; 16]; 4] = [
    [
        -0.84289382761090128651353491142e+1,
        0.0,
        0.0,
        0.0,
        0.0,
        0.56671495351937776962531783590,
        -0.30689499459498916912797304727e+1,
        0.23846676565120698287728149680e+1,
        0.21170345824450282767155149946e+1,
        -0.87139158377797299206789907490,
        0.22404374302607882758541771650e+1,
        0.63157877876946881815570249290,
        -0.88990336451333310820698117400e-1,
        0.18148505520854727256656404962e+2,
        -0.91946323924783554000451984436e+1,
        -0.44360363875948939664310572000e+1,
    ],
    [
        0.10427508642579134603413151009e+2,
        0.0,
        0.0,
        0.0,
        0.0,
        0.24228349177525818288430175319e+3,
        0.16520045171727028198505394887e+3,
        -0.37454675472269020279518312152e+3,
        -0.22113666853125306036270938578e+2,
        0.77334326684722638389603898808e+1,
        -0.30674084731089398182061213626e+2,
        -0.93321305264302278729567221706e+1,
        0.15697238121770843886131091075e+2,
        -0.31139403219565177677282850411e+2,
        -0.93529243588444783865713862664e+1,
        0.35816841486394083752465898540e+2,
    ],
    [
        0.19985053242002433820987653617e+2,
        0.0,
        0.0,
        0.0,
        0.0,
        -0.38703730874935176555105901742e+3,
        -0.18917813819516756882830838328e+3,
        0.52780815920542364900561016686e+3,
        -0.11573902539959630126141871134e+2,
        0.68812326946963000169666922661e+1,
        -0.10006050966910838403183860980e+1,
        0.77771377980534432092869265740,
        -0.27782057523535084065932004339e+1,
        -0.60196695231264120758267380846e+2,
        0.84320405506677161018159903784e+2,
        0.11992291136182789328035130030e+2,
    ],
    [
        -0.25693933462703749003312586129e+2,
        0.0,
        0.0,
        0.0,
        0.0,
        -0.15418974869023643374053993627e+3,
        -0.23152937917604549567536039109e+3,
        0.35763911791061412378285349910e+3,
        0.93405324183624310003907691704e+2,
        -0.37458323136451633156875139351e+2,
        0.10409964950896230045147246184e+3,
        0.29840293426660503123344363579e+2,
        -0.43533456590011143754432175058e+2,
        0.96324553959188282948394950600e+2,
        -0.39177261675615439165231486172e+2,
        -0.14972683625798562581422125276e+3,
    ],
];

/// Coefficients of the 3rd-order error estimate: E3 = b − bhh (SciPy `E3[:12]`).
pub(crate) const E3: [f64; 12] = {
    let mut e = [0.0; 12];
    let mut j = 0;
    while j < 12 {
        e[j] = B[j];
        j += 1;
    }
    let mut m = 0;
    while m < BHH.len() {
        let (idx, v) = BHH[m];
        e[idx] -= v;
        m += 1;
    }
    e
};

/// The nonzero entries of the rows of [`A`] (row 12: the weights b), for the stage sums of
/// [`step_fixed`].
const A_NONZERO: [NonzeroRow; STAGES] = {
    let mut rows = [NonzeroRow::of(&[]); STAGES];
    let mut i = 0;
    while i < STAGES {
        rows[i] = NonzeroRow::of(A[i]);
        i += 1;
    }
    rows
};
/// The nonzero entries of [`E5`] and [`E3`], for [`error_norm_fixed`].
const E5_NONZERO: NonzeroRow = NonzeroRow::of(&E5);
const E3_NONZERO: NonzeroRow = NonzeroRow::of(&E3);

/// Computes stages k_1..k_11 and y_new of one step of size h from (t, y) (11 RHS calls).
pub(crate) fn step<F: Formulation + ?Sized>(
    f: &F,
    t: f64,
    h: f64,
    y: &[f64],
    buf: StepBuffers<'_>,
    evals: &mut u64,
) -> Result<(), SolveError> {
    let StepBuffers { k, y_new, y_stage } = buf;
    // Up to 24 states (as `combine`): a step for the exact length, whose stage sums are inlined
    // and skip the tableau's zeros. The call and dispatch per stage sum, the test of every
    // coefficient and the loop over a runtime length were more than half of their cost (a
    // tenth of a reduced four-bar run); the sums themselves are the same, to the bit.
    macro_rules! by_length {
        ($($n:literal)*) => {
            match y.len() {
                $($n => {
                    if let (Some(y), Some(y_new), Some(y_stage)) = (
                        y.first_chunk::<$n>(),
                        y_new.first_chunk_mut::<$n>(),
                        y_stage.first_chunk_mut::<$n>(),
                    ) {
                        return step_fixed(f, t, h, y, k, y_new, y_stage, evals);
                    }
                })*
                _ => {}
            }
        };
    }
    by_length!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24);
    step_any(f, t, h, y, k, y_new, y_stage, evals)
}

/// [`step`] for any number of states.
#[allow(clippy::too_many_arguments)] // `step`'s arguments with the buffers unpacked
fn step_any<F: Formulation + ?Sized>(
    f: &F,
    t: f64,
    h: f64,
    y: &[f64],
    k: &mut [Vec<f64>],
    y_new: &mut [f64],
    y_stage: &mut [f64],
    evals: &mut u64,
) -> Result<(), SolveError> {
    for s in 1..N_STAGES {
        let (done, rest) = k.split_at_mut(s);
        combine(y, h, A[s], done, y_stage);
        if let Some(ks) = rest.first_mut() {
            eval_rhs(f, t + C[s] * h, y_stage, ks, evals)?;
        }
    }
    combine(y, h, B, &k[..N_STAGES], y_new);
    Ok(())
}

/// [`step`] for N states. The stages live in a local array while the step is computed (no
/// vector to look up per term) and are copied into `k` at the end; each stage sum is written
/// out for its own constant row, so that it unrolls.
#[allow(clippy::too_many_arguments)] // `step`'s arguments with the buffers at their fixed size
fn step_fixed<F: Formulation + ?Sized, const N: usize>(
    f: &F,
    t: f64,
    h: f64,
    y: &[f64; N],
    k: &mut [Vec<f64>],
    y_new: &mut [f64; N],
    y_stage: &mut [f64; N],
    evals: &mut u64,
) -> Result<(), SolveError> {
    let mut ks = [[0.0; N]; N_STAGES];
    match k.first().and_then(|k0| k0.first_chunk::<N>()) {
        Some(k0) => ks[0] = *k0,
        None => debug_assert!(false, "DOP853 stage vectors of length {N}"),
    }
    macro_rules! stages {
        ($($s:literal)*) => {$(
            {
                const ROW: NonzeroRow = A_NONZERO[$s];
                combine_stages(y, h, &ROW, &ks, y_stage);
                eval_rhs(f, t + C[$s] * h, y_stage, &mut ks[$s], evals)?;
            }
        )*};
    }
    stages!(1 2 3 4 5 6 7 8 9 10 11);
    const WEIGHTS: NonzeroRow = A_NONZERO[FSAL];
    combine_stages(y, h, &WEIGHTS, &ks, y_new);
    for (kj, local) in k.iter_mut().zip(&ks).skip(1) {
        if let Some(kj) = kj.first_chunk_mut::<N>() {
            *kj = *local;
        }
    }
    Ok(())
}

/// Evaluates the FSAL stage k_12 = f(t_new, y_new) of an accepted step (1 RHS call).
pub(crate) fn fsal<F: Formulation + ?Sized>(
    f: &F,
    t_new: f64,
    y_new: &[f64],
    k: &mut [Vec<f64>],
    evals: &mut u64,
) -> Result<(), SolveError> {
    match k.get_mut(FSAL) {
        Some(k12) => eval_rhs(f, t_new, y_new, k12, evals),
        None => {
            debug_assert!(false, "DOP853 needs {STAGES} stage vectors");
            Ok(())
        }
    }
}

/// The combined error norm (see the module documentation), with n the number m of
/// error-controlled components and the sums over those only. `scratch` holds two vectors of
/// length n.
pub(crate) fn error_norm(
    h: f64,
    y: &[f64],
    y_new: &[f64],
    k: &[Vec<f64>],
    weights: &ErrorWeights,
    scratch: (&mut [f64], &mut [f64]),
) -> f64 {
    if weights.is_empty() {
        return 0.0;
    }
    // As `step`: the same sums at a fixed length, inlined.
    macro_rules! by_length {
        ($($n:literal)*) => {
            match y.len() {
                $($n => {
                    if let Some(norm) = error_norm_fixed::<$n>(h, y, y_new, k, weights) {
                        return norm;
                    }
                })*
                _ => {}
            }
        };
    }
    by_length!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24);
    error_norm_any(h, y, y_new, k, weights, scratch)
}

/// [`error_norm`] for any number of states (m > 0).
fn error_norm_any(
    h: f64,
    y: &[f64],
    y_new: &[f64],
    k: &[Vec<f64>],
    weights: &ErrorWeights,
    scratch: (&mut [f64], &mut [f64]),
) -> f64 {
    let (rtol, atol) = (weights.rtol, weights.atol);
    let (err5, err3) = scratch;
    let m = weights.len();
    weighted_sum(&E5, k, err5);
    weighted_sum(&E3, k, err3);
    let mut s5 = 0.0;
    let mut s3 = 0.0;
    // Bookkeeping components have weight 0 and add exactly +0 (see `ErrorWeights`).
    for ((((&w, &a), &b), &r5), &r3) in weights
        .mask
        .iter()
        .zip(y)
        .zip(y_new)
        .zip(&*err5)
        .zip(&*err3)
    {
        let e5 = scaled(r5, a, b, rtol, atol);
        let e3 = scaled(r3, a, b, rtol, atol);
        s5 += w * (e5 * e5);
        s3 += w * (e3 * e3);
    }
    if s5 == 0.0 && s3 == 0.0 {
        return 0.0;
    }
    h.abs() * s5 / ((s5 + 0.01 * s3) * m as f64).sqrt()
}

/// [`error_norm`] for N states; `None` if a vector is not of length N.
fn error_norm_fixed<const N: usize>(
    h: f64,
    y: &[f64],
    y_new: &[f64],
    k: &[Vec<f64>],
    weights: &ErrorWeights,
) -> Option<f64> {
    let (rtol, atol) = (weights.rtol, weights.atol);
    let (y, y_new) = (y.first_chunk::<N>()?, y_new.first_chunk::<N>()?);
    let mask = weights.mask.first_chunk::<N>()?;
    if k.len() < N_STAGES {
        return None;
    }
    let stages: [&[f64; N]; N_STAGES] = {
        let mut stages = [&[0.0; N]; N_STAGES];
        for (s, kj) in stages.iter_mut().zip(k) {
            *s = kj.first_chunk::<N>()?;
        }
        stages
    };
    // `weighted_sum` is `combine` from zero with h = 1 (1·a = a exactly).
    let zero = [0.0; N];
    let (mut err5, mut err3) = ([0.0; N], [0.0; N]);
    combine_refs(&zero, 1.0, &E5_NONZERO, &stages, &mut err5);
    combine_refs(&zero, 1.0, &E3_NONZERO, &stages, &mut err3);
    let mut s5 = 0.0;
    let mut s3 = 0.0;
    for ((((&w, &a), &b), &r5), &r3) in mask.iter().zip(y).zip(y_new).zip(&err5).zip(&err3) {
        let e5 = scaled(r5, a, b, rtol, atol);
        let e3 = scaled(r3, a, b, rtol, atol);
        s5 += w * (e5 * e5);
        s3 += w * (e3 * e3);
    }
    if s5 == 0.0 && s3 == 0.0 {
        return Some(0.0);
    }
    Some(h.abs() * s5 / ((s5 + 0.01 * s3) * weights.len() as f64).sqrt())
}

/// Evaluates the three dense-output stages k_13..k_15 of a step of size h from
/// (t_old, y_old); k_0..k_12 must be those of that step (3 RHS calls).
pub(crate) fn extra_stages<F: Formulation + ?Sized>(
    f: &F,
    t_old: f64,
    h: f64,
    y_old: &[f64],
    k: &mut [Vec<f64>],
    y_stage: &mut [f64],
    evals: &mut u64,
) -> Result<(), SolveError> {
    for s in FSAL + 1..STAGES {
        let (done, rest) = k.split_at_mut(s);
        combine(y_old, h, A[s], done, y_stage);
        if let Some(ks) = rest.first_mut() {
            eval_rhs(f, t_old + C[s] * h, y_stage, ks, evals)?;
        }
    }
    Ok(())
}

/// Fills F₀..F₆ from all 16 stages of a step of size h from y_old to y_new.
pub(crate) fn dense_vectors(
    h: f64,
    y_old: &[f64],
    y_new: &[f64],
    k: &[Vec<f64>],
    dense: &mut [Vec<f64>],
) {
    let [f0, f1, f2, rest @ ..] = dense else {
        debug_assert!(false, "dense output needs {DENSE_VECTORS} vectors");
        return;
    };
    let (Some(k0), Some(k12)) = (k.first(), k.get(FSAL)) else {
        debug_assert!(false, "dense output needs {STAGES} stages");
        return;
    };
    for i in 0..y_old.len() {
        let dy = y_new[i] - y_old[i];
        f0[i] = dy;
        f1[i] = h * k0[i] - dy;
        f2[i] = 2.0 * dy - h * (k12[i] + k0[i]);
    }
    for (fr, d) in rest.iter_mut().zip(&D) {
        weighted_sum(d, k, fr);
        for v in fr.iter_mut() {
            *v *= h;
        }
    }
}

/// Evaluates the dense output at θ = (t* − t_old)/h into `out`.
pub(crate) fn eval_dense(theta: f64, y_old: &[f64], dense: &[Vec<f64>], out: &mut [f64]) {
    let [f0, f1, f2, f3, f4, f5, f6, ..] = dense else {
        debug_assert!(false, "dense output needs {DENSE_VECTORS} vectors");
        return;
    };
    let t1 = 1.0 - theta;
    for (i, o) in out.iter_mut().enumerate() {
        let p = f5[i] + theta * f6[i];
        let p = f4[i] + t1 * p;
        let p = f3[i] + theta * p;
        let p = f2[i] + t1 * p;
        let p = f1[i] + theta * p;
        let p = f0[i] + t1 * p;
        *o = y_old[i] + theta * p;
    }
}

#[cfg(test)]
mod tests {
    use super::super::order_conditions::{Tableau, continuous_weights, max_defect};
    use super::*;

    #[test]
    fn rows_sum_to_nodes() {
        for (i, row) in A.iter().enumerate() {
            let sum: f64 = row.iter().sum();
            // Entries up to ~43 in size: a few ulps of them.
            assert!(
                (sum - C[i]).abs() < 1e-13,
                "row {i}: Σa = {sum}, c = {}",
                C[i]
            );
        }
        assert_eq!(C[FSAL], 1.0);
    }

    #[test]
    fn weights_have_order_8() {
        let t = Tableau::new(&A[..N_STAGES], N_STAGES);
        let d8 = max_defect(&t, B, 8);
        // The 30-digit coefficients rounded to f64, multiplied through trees of up to 8 nodes
        // with entries up to ~43, leave defects of order 1e-14.
        assert!(d8 < 1e-12, "order-8 defect {d8}");
    }

    #[test]
    fn embedded_estimators_have_orders_5_and_3() {
        let t = Tableau::new(&A[..N_STAGES], N_STAGES);
        let b5: Vec<f64> = B.iter().zip(E5).map(|(b, e)| b - e).collect();
        let b3: Vec<f64> = B.iter().zip(E3).map(|(b, e)| b - e).collect();
        let (d5, d6) = (max_defect(&t, &b5, 5), max_defect(&t, &b5, 6));
        assert!(
            d5 < 1e-12 && d6 > 1e-6,
            "b − E5: order-5 defect {d5}, order-6 {d6}"
        );
        let (d3, d4) = (max_defect(&t, &b3, 3), max_defect(&t, &b3, 4));
        assert!(
            d3 < 1e-12 && d4 > 1e-6,
            "bhh: order-3 defect {d3}, order-4 {d4}"
        );
    }

    #[test]
    fn dense_output_has_order_7() {
        let t = Tableau::new(&A, STAGES);
        for theta in [0.1, 0.37, 0.5, 0.83, 1.0] {
            let w = continuous_weights(STAGES, |k, out| {
                let y_old = vec![0.0; STAGES];
                let mut y_new = vec![0.0; STAGES];
                combine(&y_old, 1.0, B, &k[..N_STAGES], &mut y_new);
                let mut dense = vec![vec![0.0; STAGES]; DENSE_VECTORS];
                dense_vectors(1.0, &y_old, &y_new, k, &mut dense);
                eval_dense(theta, &y_old, &dense, out);
            });
            let d7 = t.max_continuous_defect(&w, theta, 7);
            assert!(d7 < 1e-11, "θ = {theta}: order-7 defect {d7}");
        }
    }

    /// A small nonlinear system with a little of everything (products, a sine, time, a constant
    /// component), whose stages differ in every component.
    struct Mixed(usize);

    impl crate::formulation::NoStepHooks for Mixed {}

    impl Formulation for Mixed {
        fn n_states(&self) -> usize {
            self.0
        }
        fn initial_state(&self) -> Vec<f64> {
            (0..self.0).map(|i| 0.3 + 0.1 * i as f64).collect()
        }
        fn rhs(
            &self,
            t: f64,
            y: &[f64],
            dy: &mut [f64],
        ) -> Result<(), crate::formulation::FormulationError> {
            let n = y.len();
            for i in 0..n {
                dy[i] = (y[(i + 1) % n] * y[i]).sin() - 0.7 * y[(i + 2) % n] + t * i as f64;
            }
            if let Some(last) = dy.last_mut() {
                *last = 0.0;
            }
            Ok(())
        }
    }

    /// The fixed-size step and error norm give the general loops' stages, solution and norm to
    /// the bit (the same sums in the same order), with a bookkeeping component left out of the
    /// norm, for one state and the sizes of the reduced four-bar (5) and the DAE four-bar (19).
    #[test]
    fn fixed_size_step_equals_the_general_loop_bit_for_bit() -> Result<(), SolveError> {
        for n in [1, 5, 19] {
            let f = Mixed(n);
            let y = f.initial_state();
            let (t, h) = (0.25, 0.05);
            let run = |fixed: bool| -> Result<_, SolveError> {
                let mut k = vec![vec![0.0; n]; STAGES];
                let mut evals = 0;
                eval_rhs(&f, t, &y, &mut k[0], &mut evals)?;
                let (mut y_new, mut y_stage) = (vec![0.0; n], vec![0.0; n]);
                let buf = StepBuffers {
                    k: &mut k,
                    y_new: &mut y_new,
                    y_stage: &mut y_stage,
                };
                if fixed {
                    step(&f, t, h, &y, buf, &mut evals)?;
                } else {
                    step_any(&f, t, h, &y, buf.k, buf.y_new, buf.y_stage, &mut evals)?;
                }
                let mut mask = vec![true; n];
                if n > 1 {
                    mask[n - 1] = false;
                }
                let weights = ErrorWeights {
                    rtol: 1e-9,
                    atol: 1e-12,
                    controlled: (0..n).filter(|&i| mask[i]).collect(),
                    mask: mask.iter().map(|&c| if c { 1.0 } else { 0.0 }).collect(),
                };
                let (mut s1, mut s2) = (vec![0.0; n], vec![0.0; n]);
                let norm = if fixed {
                    error_norm(h, &y, &y_new, &k, &weights, (&mut s1, &mut s2))
                } else {
                    error_norm_any(h, &y, &y_new, &k, &weights, (&mut s1, &mut s2))
                };
                Ok((k, y_new, y_stage, norm, evals))
            };
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            let (fast, plain) = (run(true)?, run(false)?);
            for s in 0..N_STAGES {
                assert_eq!(bits(&fast.0[s]), bits(&plain.0[s]), "n = {n}, stage {s}");
            }
            assert_eq!(bits(&fast.1), bits(&plain.1), "n = {n}, y_new");
            assert_eq!(
                bits(&fast.2),
                bits(&plain.2),
                "n = {n}, last stage argument"
            );
            assert_eq!(
                fast.3.to_bits(),
                plain.3.to_bits(),
                "n = {n}, error norm {} vs {}",
                fast.3,
                plain.3
            );
            assert_eq!(fast.4, plain.4, "n = {n}, RHS calls");
        }
        Ok(())
    }

    #[test]
    fn dense_output_matches_the_step_ends() {
        let n = 2;
        let k: Vec<Vec<f64>> = (0..STAGES)
            .map(|j| (0..n).map(|i| ((i + 3 * j) as f64 * 0.7).sin()).collect())
            .collect();
        let (h, y_old) = (0.4, [2.0, -0.25]);
        let mut y_new = [0.0; 2];
        combine(&y_old, h, B, &k[..N_STAGES], &mut y_new);
        let mut dense = vec![vec![0.0; n]; DENSE_VECTORS];
        dense_vectors(h, &y_old, &y_new, &k, &mut dense);
        let mut out = [0.0; 2];
        eval_dense(0.0, &y_old, &dense, &mut out);
        assert_eq!(out, y_old);
        eval_dense(1.0, &y_old, &dense, &mut out);
        for i in 0..n {
            assert!((out[i] - y_new[i]).abs() < 1e-14, "θ = 1, component {i}");
        }
    }
}
