//! A body with no joints at all is a free planar body: under gravity it follows the parabola
//! exactly and keeps its spin (no constraint rows, an empty Schur complement).

mod common;
use common::*;
use linkdyn::solve::Method;

#[test]
fn free_body_follows_the_parabola_and_keeps_its_spin() {
    let text = "[model]\nname = \"thrown\"\n[[bodies]]\nname = \"brick\"\nmass = 2.0\ninertia = 0.01\ninitial = { x = 0.0, y = 1.0, phi = 0.0, vx = 3.0, vy = 4.0, omega = 5.0 }\n";
    let model =
        linkdyn::model::load_str(text, "thrown.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
    let (rec, _) = run_dae(&model, 1.0, 1e-2, Method::Dopri5, 1e-10, 1e-12);
    let (x, y, phi) = (
        col(&rec, "brick.x"),
        col(&rec, "brick.y"),
        col(&rec, "brick.phi"),
    );
    for (i, t) in rec.t.iter().enumerate() {
        let (xe, ye, pe) = (3.0 * t, 1.0 + 4.0 * t - 0.5 * 9.81 * t * t, 5.0 * t);
        // The motion is a polynomial of degree 2: the 5th-order method is exact up to round-off.
        assert!(
            (x[i] - xe).abs() < 1e-12 && (y[i] - ye).abs() < 1e-12 && (phi[i] - pe).abs() < 1e-12,
            "t = {t}: ({}, {}, {}) vs ({xe}, {ye}, {pe})",
            x[i],
            y[i],
            phi[i]
        );
    }
}
