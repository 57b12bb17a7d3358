//! Planar kinematics of a point fixed on a body.
//!
//! A body point with body-frame coordinates s has the global position r + A(φ) s, where
//! A(φ) = [[cos φ, −sin φ], [sin φ, cos φ]]. Its derivative with respect to φ is
//! A(φ) s rotated by +90°, written `perp(A s)`.

use crate::model::Frame;

/// Generalised coordinates or velocities of one body: (x, y, φ) or (ẋ, ẏ, φ̇).
pub type Pose = [f64; 3];

/// A s: body-frame vector rotated into the global frame, given (sin φ, cos φ).
#[inline]
pub fn rotate(sin_cos: (f64, f64), s: [f64; 2]) -> [f64; 2] {
    let (sn, cs) = sin_cos;
    [cs * s[0] - sn * s[1], sn * s[0] + cs * s[1]]
}

/// The vector rotated by +90°: (−v_y, v_x).
#[inline]
pub fn perp(v: [f64; 2]) -> [f64; 2] {
    [-v[1], v[0]]
}

/// Dot product.
#[inline]
pub fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Scalar cross product a × b = a_x b_y − a_y b_x.
#[inline]
pub fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Global position, velocity and the rotated arm A s of a point on a frame.
#[derive(Debug, Clone, Copy, Default)]
pub struct PointState {
    /// Global position r + A s (m).
    pub position: [f64; 2],
    /// Global velocity ṙ + φ̇ perp(A s) (m/s).
    pub velocity: [f64; 2],
    /// The arm A s from the centre of mass to the point, global frame (m); zero on the ground.
    pub arm: [f64; 2],
    /// φ̇ of the frame (rad/s).
    pub omega: f64,
}

/// State of the point with local coordinates `s` on `frame`, from the body coordinates `q`
/// and velocities `v` (3 per body) and per-body (sin φ, cos φ) in `sin_cos`.
#[inline]
pub fn point_state(
    frame: Frame,
    s: [f64; 2],
    q: &[f64],
    v: &[f64],
    sin_cos: &[(f64, f64)],
) -> PointState {
    let body_sin_cos = match frame {
        Frame::Ground => (0.0, 1.0),
        Frame::Body(id) => sin_cos[id.0],
    };
    point_state_with(frame, s, q, v, body_sin_cos)
}

/// [`point_state`] with the (sin φ, cos φ) of the frame's own body given (ignored on the
/// ground): for a look at one point without the sines and cosines of every body.
#[inline]
pub fn point_state_with(
    frame: Frame,
    s: [f64; 2],
    q: &[f64],
    v: &[f64],
    body_sin_cos: (f64, f64),
) -> PointState {
    match frame {
        Frame::Ground => PointState {
            position: s,
            ..PointState::default()
        },
        Frame::Body(id) => {
            let k = 3 * id.0;
            let arm = rotate(body_sin_cos, s);
            let omega = v[k + 2];
            let p = perp(arm);
            PointState {
                position: [q[k] + arm[0], q[k + 1] + arm[1]],
                velocity: [v[k] + omega * p[0], v[k + 1] + omega * p[1]],
                arm,
                omega,
            }
        }
    }
}

/// Acceleration of a body point (m/s²): P̈ = r̈ + φ̈ perp(A s) − φ̇² A s, from the point's
/// state and the body's accelerations (ẍ, ÿ, φ̈).
#[inline]
pub fn point_acceleration(p: &PointState, body_acc: [f64; 3]) -> [f64; 2] {
    let u = perp(p.arm);
    let w2 = p.omega * p.omega;
    [
        body_acc[0] + body_acc[2] * u[0] - w2 * p.arm[0],
        body_acc[1] + body_acc[2] * u[1] - w2 * p.arm[1],
    ]
}
