//! The prescribed relative angle θ(t) = φ_b − φ_a of a driver, with θ̇ and θ̈ (for Φ_t and γ).
//!
//! - constant speed: θ = θ0 + ω t;
//! - speed ramp from ω0 to ω1 over [t_s, t_s + T]: with τ = (t − t_s)/T clamped to [0, 1] and
//!   Δ = ω1 − ω0, θ̇ = ω0 + Δ s(τ) and θ = θ0 + ω0 t + Δ T S(τ) + Δ max(t − t_s − T, 0), where
//!   s(τ) = τ, S(τ) = τ²/2 (linear: the acceleration Δ/T jumps at both ends) or
//!   s(τ) = 3τ² − 2τ³, S(τ) = τ³ − τ⁴/2 (smooth: θ̈ = 6Δ τ(1 − τ)/T is continuous, 0 at both
//!   ends). Both have S(1) = 1/2: the ramp adds Δ T/2 to the angle, the mean of the two speeds;
//! - prescribed angle: θ(t) an expression of t, differentiated exactly by forward-mode jets
//!   ([`crate::model::Expr::eval_jet`]).

use crate::model::{Driver, DriverMotion};

/// [θ, θ̇, θ̈] (rad, rad/s, rad/s²) of `driver` at time t (s).
pub fn driver_angle(driver: &Driver, t: f64) -> [f64; 3] {
    let theta0 = driver.initial_angle;
    match &driver.motion {
        DriverMotion::ConstantSpeed => [theta0 + driver.speed * t, driver.speed, 0.0],
        DriverMotion::SpeedRamp {
            speed0,
            speed1,
            start,
            duration,
            smooth,
        } => {
            let delta = speed1 - speed0;
            let tau = ((t - start) / duration).clamp(0.0, 1.0);
            let after = (t - start - duration).max(0.0);
            let (s, big_s, ds) = if *smooth {
                (
                    tau * tau * (3.0 - 2.0 * tau),
                    tau * tau * tau * (1.0 - 0.5 * tau),
                    6.0 * tau * (1.0 - tau),
                )
            } else {
                (tau, 0.5 * tau * tau, 1.0)
            };
            let ramping = t > *start && t < start + duration;
            [
                theta0 + speed0 * t + delta * (duration * big_s + after),
                speed0 + delta * s,
                if ramping { delta * ds / duration } else { 0.0 },
            ]
        }
        DriverMotion::PrescribedAngle(e) => e.tree.eval_jet(t).0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Expr, Expression, JointId};

    fn ramp(smooth: bool) -> Driver {
        Driver {
            name: "m".into(),
            joint: JointId(0),
            speed: 30.0,
            initial_angle: 0.5,
            motion: DriverMotion::SpeedRamp {
                speed0: 10.0,
                speed1: 30.0,
                start: 1.0,
                duration: 2.0,
                smooth,
            },
        }
    }

    /// The angle is the integral of the speed and the speed that of the acceleration: checked
    /// by Simpson's rule on 2000 panels, whose error (h⁴ f⁗/180 ~ 1e-13 here; the speed's kinks
    /// at the ends of a linear ramp fall on panel edges) is far below the 1e-9 tolerance.
    #[test]
    fn ramp_angle_is_the_integral_of_its_speed() {
        for smooth in [false, true] {
            let d = ramp(smooth);
            let n = 2000;
            let (a, b) = (0.0, 4.0);
            let h = (b - a) / n as f64;
            let (mut int_w, mut int_acc) = (0.0, 0.0);
            for k in 0..=n {
                let w = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                let [_, om, al] = driver_angle(&d, a + k as f64 * h);
                int_w += w * om;
                int_acc += w * al;
            }
            int_w *= h / 3.0;
            int_acc *= h / 3.0;
            let [th_a, om_a, _] = driver_angle(&d, a);
            let [th_b, om_b, _] = driver_angle(&d, b);
            assert!(
                (th_b - th_a - int_w).abs() < 1e-9,
                "smooth {smooth}: Δθ {} vs ∫ω {int_w}",
                th_b - th_a
            );
            // A linear ramp's acceleration jumps at the ends, where Simpson's rule is only
            // first order: its constant value Δ/T is checked instead.
            if !smooth {
                assert_eq!(driver_angle(&d, 2.0)[2], 10.0, "linear ramp: Δ/T");
                continue;
            }
            assert!(
                (om_b - om_a - int_acc).abs() < 1e-9,
                "smooth {smooth}: Δω {} vs ∫α {int_acc}",
                om_b - om_a
            );
            // Closed form at the end: θ0 + ω0 t + Δ (T/2 + (t − t_s − T)) = 0.5 + 40 + 20·2 = 80.5.
            assert!(
                (th_b - 80.5).abs() < 1e-12,
                "smooth {smooth}: θ(4) = {th_b}, expected 80.5"
            );
            assert_eq!(om_b, 30.0, "smooth {smooth}: final speed");
        }
    }

    #[test]
    fn prescribed_angle_t_squared_has_speed_2t() {
        let d = Driver {
            name: "m".into(),
            joint: JointId(0),
            speed: 0.0,
            initial_angle: 0.0,
            motion: DriverMotion::PrescribedAngle(Expression {
                text: "t^2".into(),
                tree: Expr::Bin(
                    crate::model::BinOp::Pow,
                    Box::new(Expr::Var(crate::model::Variable::Time)),
                    Box::new(Expr::Num(2.0)),
                ),
            }),
        };
        assert_eq!(driver_angle(&d, 1.5), [2.25, 3.0, 2.0]);
    }
}
