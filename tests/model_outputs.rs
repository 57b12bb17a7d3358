//! `[[outputs]]` points: a coupler point's position, velocity and acceleration columns agree
//! with the body's own columns through P = r + A(φ) s, Ṗ = ṙ + φ̇ A s⊥, P̈ = r̈ + φ̈ A s⊥ − φ̇² A s,
//! and the velocity column is the derivative of the position column.

mod common;
use common::*;
use linkdyn::model::load_str;
use linkdyn::solve::Method;

#[test]
fn coupler_point_columns_follow_the_body_kinematics() {
    let text = std::fs::read_to_string("models/fourbar_ideal.toml").unwrap_or_default()
        + "\n[[outputs]]\nname = \"P\"\nbody = \"coupler\"\nlocal = [0.1, 0.05]\n";
    let model = match load_str(&text, "fourbar_ideal.toml", &[]) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    let (rec, _) = run_dae(&model, 0.05, 1e-4, Method::Dop853, 1e-10, 1e-12);
    let c = |n: &str| col(&rec, n);
    let (x, y, phi, vx, vy, w, ax, ay, al) = (
        c("coupler.x"),
        c("coupler.y"),
        c("coupler.phi"),
        c("coupler.vx"),
        c("coupler.vy"),
        c("coupler.omega"),
        c("coupler.ax"),
        c("coupler.ay"),
        c("coupler.alpha"),
    );
    let (px, py, pvx, pvy, pax, pay) = (
        c("P.x"),
        c("P.y"),
        c("P.vx"),
        c("P.vy"),
        c("P.ax"),
        c("P.ay"),
    );
    let s = [0.1, 0.05];
    for k in 0..rec.len() {
        let (sn, cs) = phi[k].sin_cos();
        let a = [cs * s[0] - sn * s[1], sn * s[0] + cs * s[1]];
        let want = [
            x[k] + a[0],
            y[k] + a[1],
            vx[k] - w[k] * a[1],
            vy[k] + w[k] * a[0],
            ax[k] - al[k] * a[1] - w[k] * w[k] * a[0],
            ay[k] + al[k] * a[0] - w[k] * w[k] * a[1],
        ];
        let got = [px[k], py[k], pvx[k], pvy[k], pax[k], pay[k]];
        for (i, name) in ["x", "y", "vx", "vy", "ax", "ay"].iter().enumerate() {
            // Same formula, other evaluation order: a few ulp of the largest term.
            let scale = want[i].abs().max(1.0);
            assert!(
                (got[i] - want[i]).abs() < 1e-12 * scale,
                "P.{name} at t = {}: {} vs {}",
                rec.t[k],
                got[i],
                want[i]
            );
        }
    }
    // Central differences of the position (dt = 1e-4 s): error dt² |P⃛|/6 ~ 1e-5 m/s at the
    // ~1e3 m/s³ jerk of this crank speed; 1e-3 relative to the peak speed is ample.
    let peak = pvx.iter().chain(&pvy).fold(0.0_f64, |m, v| m.max(v.abs()));
    for k in 1..rec.len() - 1 {
        let h = rec.t[k + 1] - rec.t[k - 1];
        let dx = (px[k + 1] - px[k - 1]) / h;
        let dy = (py[k + 1] - py[k - 1]) / h;
        assert!(
            (dx - pvx[k]).abs() < 1e-3 * peak && (dy - pvy[k]).abs() < 1e-3 * peak,
            "P velocity at t = {}: ({}, {}) vs differences ({dx}, {dy})",
            rec.t[k],
            pvx[k],
            pvy[k]
        );
    }
}
