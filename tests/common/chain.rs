//! The exact motion of models/nfourbar_chain.toml (the IFToMM N-four-bar chain): every link
//! turns by the same angle θ and every coupler translates, so the chain is the compound
//! pendulum J θ̈ = −G cos θ with, for N loops of rods of length L and mass m,
//! J = (N + 1) m L²/3 + N m L² and G = g ((N + 1) m L/2 + N m L).

/// Rod length (m), rod mass (kg), gravity (m/s²) of the shipped model.
pub const ROD_LENGTH: f64 = 1.0;
pub const ROD_MASS: f64 = 1.0;
pub const GRAVITY: f64 = 9.81;
/// The model's initial state: links straight up, tips at 1 m/s.
pub const THETA0: f64 = std::f64::consts::FRAC_PI_2;
pub const OMEGA0: f64 = 1.0;

/// (J, G) of the chain of `loops` loops: J θ̈ = −G cos θ.
pub fn pendulum(loops: usize) -> (f64, f64) {
    let (l, m) = (ROD_LENGTH, ROD_MASS);
    let links = (loops + 1) as f64;
    let couplers = loops as f64;
    let j = links * m * l * l / 3.0 + couplers * m * l * l;
    let g = GRAVITY * (links * m * l / 2.0 + couplers * m * l);
    (j, g)
}

/// θ at the times `ts` (increasing, from t = 0) by classical RK4 with step `h` on a fixed grid
/// (a sample between grid points takes a partial step to it and resumes the grid), θ and θ̇
/// summed with Kahan's compensation (2e5 additions to θ ≈ 65 rad would otherwise round off
/// ~1e-10 rad): its error, O(h⁴), is ~1e-12 rad over 20 s at h = 1e-4 s
/// (`tests/nfourbar_chain_generalized.rs` checks it by halving the step).
pub fn theta_exact(loops: usize, ts: &[f64], h: f64) -> Vec<f64> {
    let (j, g) = pendulum(loops);
    pendulum_theta(j, g, THETA0, OMEGA0, ts, h)
}

/// θ of the pendulum J θ̈ = −G cos θ from θ(0) = `theta0`, θ̇(0) = `omega0` at the times `ts`,
/// by the RK4 scheme of [`theta_exact`] (also the reference of the parallelogram fixtures,
/// `tests/singular_parallelogram.rs`).
pub fn pendulum_theta(j: f64, g: f64, theta0: f64, omega0: f64, ts: &[f64], h: f64) -> Vec<f64> {
    let f = |th: f64, w: f64| (w, -g / j * th.cos());
    let kahan = |sum: &mut f64, comp: &mut f64, x: f64| {
        let y = x - *comp;
        let s = *sum + y;
        *comp = (s - *sum) - y;
        *sum = s;
    };
    let (mut th, mut w, mut c_th, mut c_w) = (theta0, omega0, 0.0, 0.0);
    let (mut t, mut steps) = (0.0, 0u64);
    let mut out = Vec::with_capacity(ts.len());
    for &target in ts {
        while t < target - 1e-15 {
            let next = ((steps + 1) as f64 * h).min(target);
            let hh = next - t;
            let k1 = f(th, w);
            let k2 = f(th + 0.5 * hh * k1.0, w + 0.5 * hh * k1.1);
            let k3 = f(th + 0.5 * hh * k2.0, w + 0.5 * hh * k2.1);
            let k4 = f(th + hh * k3.0, w + hh * k3.1);
            kahan(
                &mut th,
                &mut c_th,
                hh / 6.0 * (k1.0 + 2.0 * (k2.0 + k3.0) + k4.0),
            );
            kahan(
                &mut w,
                &mut c_w,
                hh / 6.0 * (k1.1 + 2.0 * (k2.1 + k3.1) + k4.1),
            );
            t = next;
            if next == (steps + 1) as f64 * h {
                steps += 1;
            }
        }
        out.push(th);
    }
    out
}

/// Flat positions (θ a multiple of π) that θ passes between consecutive samples.
pub fn flat_passages(theta: &[f64]) -> usize {
    theta
        .windows(2)
        .filter(|w| (w[0] / std::f64::consts::PI).floor() != (w[1] / std::f64::consts::PI).floor())
        .count()
}
