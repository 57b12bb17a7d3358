//! The reduced Lagrangian model of Farahan et al. (2016): a four-bar whose coupler–rocker joint
//! has clearance, with the crank angle prescribed.
//!
//! Generalised coordinates: the link angles θ2 (crank, prescribed), θ3 (coupler) and θ4 (rocker).
//! The driver prescribes φ_b − φ_a = θ0 + ω t on the crank's ground joint, so
//! θ2 = s θ0 + β2 + s ω t with s = +1 when ground is the joint's first body and −1 when it is the
//! second. With the clearance joint the journal centre is no longer tied to the bearing centre,
//! so θ3 and θ4 are independent; the eccentricity e follows from them.
//!
//! **State** y = [θ3, θ4, θ̇3, θ̇4, δ̇⁽⁻⁾] (rad, rad/s, m/s). The last component is the impact
//! velocity stored for the current contact (0 = none recorded): its derivative is 0 and only
//! [`Formulation::apply_event`] changes it, as in the DAE. So the equations and every output are
//! pure functions of (t, y) — an output computed later from a stored sample sees the δ̇⁽⁻⁾ that
//! was valid at its time ([`crate::contact::events`]).
//!
//! **Angles from the model.** A link angle θ is the direction of the line from a body's first
//! joint point to its second: crank O2 → A, coupler A → clearance point, rocker O4 → clearance
//! point. In its body frame that line has the direction β, so θ = φ + β for the body orientation φ,
//! whatever the body frame; L is the distance between the two points. Each body's centre of mass
//! (its frame origin) sits at ρ_G, written in the link's line frame (origin at the first joint
//! point, x-axis along the line); no mid-length assumption. Ground pivots O2, O4 may be anywhere.
//!
//! **Equations of motion** (derived from Lagrange's equations in `docs/reduced_lagrangian.md`;
//! J = rotation by +90°, × the scalar cross product, a_k = R(θ_k) ρ_Gk the arm from the link's
//! first joint point to its centre of mass, d_k = L_k u_k with u_k = (cos θ_k, sin θ_k)):
//!
//! ```text
//!   (I3 + m3|ρ_G3|²) θ̈3 = a3 × m3 (g − a_A) + d3 × F3 + M3 + τ3 + Σ_coupler (R(θ3) ρ_P) × F_P
//!   (I4 + m4|ρ_G4|²) θ̈4 = a4 × m4 g          + d4 × F4 + M4 + τ4 + Σ_rocker  (R(θ4) ρ_P) × F_P
//!   a_A = −θ̇2² d2                                   (acceleration of A, θ̈2 = 0)
//!   M2  = d2 × F_A − a2 × m2 g − τ2 − Σ_crank (R(θ2) ρ_P) × F_P
//!   F_A = m3 (a_G3 − g) − F3 − Σ_coupler F_P,    a_G3 = a_A + θ̈3 J a3 − θ̇3² a3
//! ```
//!
//! | symbol | meaning | unit |
//! |---|---|---|
//! | m_k, I_k | mass, moment of inertia about the centre of mass | kg, kg·m² |
//! | g | gravity vector (`settings.gravity`) | m/s² |
//! | F3, F4 | contact force on coupler / rocker at its contact point ([`crate::contact`]) | N |
//! | M3, M4 | moment of that force about the body's clearance-joint centre | N·m |
//! | τ_k, F_P | constant torques and point forces of the model on body k | N·m, N |
//! | M2 | torque the driver applies to the crank to keep ω constant (counter-clockwise +) | N·m |
//! | F_A | force of the crank on the coupler at A | N |
//!
//! For the reference four-bar (centres at mid-length, no loads) these are the paper's eqs. 23–25
//! exactly as printed, with the contact force direction ψ from a corrected eq. 13. Corrections to
//! the paper (table in `docs/reduced_lagrangian.md` §9): eq. 21 (and 22) `½ L3 θ3` → `½ L3 sin θ3`;
//! eq. 19 the undefined γ is ψ, and the radii are R_B on the coupler, R_J on the rocker (printed
//! R_i, R_j, swapped with respect to eq. 8); eq. 13 tan φ = −c_f c_d X/|X| (printed X/X loses the
//! direction of sliding); eq. 15 α = atan2(Y, X); eq. 6 −r ṅ → −ṙ n; eq. 11 c_d cases swapped;
//! F_N ≥ 0 and the fallback without an impact velocity (eq. 7); c_f = 0.1 is dimensionless.
//!
//! **Contact.** δ = |e| − c is the event function; a Rising zero stores δ̇⁽⁻⁾ = max(δ̇, 0) in y, a
//! Falling one clears it; both are logged in a [`ContactMemory`] and restart the integrator. The
//! law uses the stored δ̇⁽⁻⁾, or the current δ̇ when none is stored ([`impact_velocity`]). While
//! free, [`Formulation::max_step`] applies the grazing guard [`free_flight_max_step`]. With a
//! friction law, events 1–4 mark its kinks (v_t = ±v0, ±v1) while in contact, so that Radau5
//! ends its steps there; they change nothing (`contact/kinks.rs`,
//! [`ReducedLagrangian::friction_kink_events`]).
//!
//! **Requirements** (otherwise `FormulationError::Unsupported { formulation: "reduced", .. }`):
//! exactly 3 moving bodies; exactly one driver, on a revolute joint between ground and a body (the
//! crank); an ideal revolute joint crank–coupler; exactly one clearance joint, between the coupler
//! and the rocker (either of them may carry the bearing); an ideal revolute joint rocker–ground;
//! no other joint; force elements only constant torques and constant point forces (gravity always).
//!
//! **Initial state.** Positions: Newton's method on the loop closure r_J − r_B = e0 (the model's
//! initial eccentricity) for θ3, θ4 from the bodies' initial guesses, at t = 0. Velocities: the
//! ideal-joint velocity analysis with ė = 0. Independent of the DAE code.
//!
//! # References
//! 1. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eqs. 14–25, <https://tava.isav.ir/article_19881.html>.
//! 2. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, Dynamic behaviour of planar rigid
//!    multi-body systems including revolute joints with clearance, *Proc. IMechE Part K: Journal
//!    of Multi-body Dynamics* 221 (2007) 161–174.
//! 3. H. Goldstein, C. Poole, J. Safko, *Classical Mechanics*, 3rd ed., Addison-Wesley, 2002,
//!    §1.4–1.5 (Lagrange's equations, generalised forces by virtual work).

use std::cell::Cell;

use super::{Crossing, EventResponse, Formulation, FormulationError, Outputs};
use crate::contact::{
    CentreMotion, ClearanceJoint, ContactForces, ContactKinematics, ContactMemory,
    free_flight_max_step, impact_velocity, kinks,
};
use crate::mechanics::planar::{cross, dot, perp, rotate};
use crate::model::{
    Anchor, BodyId, ClearanceSpec, Driver, ForceElement, Frame, Joint, JointKind, Model,
};

mod jacobian;

/// Name used in `FormulationError::Unsupported`.
const NAME: &str = "reduced";
/// Loop-closure residual (m) below which the initial positions count as assembled.
const POSITION_TOLERANCE: f64 = 1e-12;
/// Newton iterations allowed for the initial positions.
const MAX_ITERATIONS: usize = 50;

/// A body seen as a link between two joint points.
#[derive(Debug, Clone)]
struct Link {
    body: BodyId,
    mass: f64,
    inertia: f64,
    /// L: distance between the two joint points (m).
    length: f64,
    /// β: direction of the line first → second joint point in the body frame (rad); θ = φ + β.
    beta: f64,
    /// Centre of mass in the line frame (m).
    com: [f64; 2],
    /// I + m |ρ_G|², the moment of inertia about the first joint point (kg·m²), kept: the
    /// right-hand side divides by it at every call.
    pivot: f64,
    /// Sum of the model's constant torques on the body (N·m).
    torque: f64,
    /// Constant point forces: (point in the line frame (m), force (N, global)).
    loads: Vec<([f64; 2], [f64; 2])>,
}

impl Link {
    fn new(
        model: &Model,
        body: BodyId,
        first: &Anchor,
        second: &Anchor,
    ) -> Result<Link, FormulationError> {
        let b = model.body(body);
        let d = [
            second.local[0] - first.local[0],
            second.local[1] - first.local[1],
        ];
        let length = d[0].hypot(d[1]);
        if length.is_nan() || length <= 1e-12 {
            return Err(unsupported(format!(
                "body \"{}\": its joint points \"{}\" and \"{}\" coincide, so its link angle is undefined",
                b.name, first.point, second.point
            )));
        }
        let beta = d[1].atan2(d[0]);
        let mut link = Link {
            body,
            mass: b.mass,
            inertia: b.inertia,
            length,
            beta,
            com: to_line_frame(beta, first.local, [0.0, 0.0]),
            pivot: 0.0,
            torque: 0.0,
            loads: Vec::new(),
        };
        link.pivot = link.inertia + link.mass * dot(link.com, link.com);
        Ok(link)
    }

    /// Moment of inertia about the link's first joint point, I + m |ρ_G|² (kg·m²).
    fn pivot_inertia(&self) -> f64 {
        self.pivot
    }

    /// Σ (R(θ) ρ_P) × F_P about the first joint point and Σ F_P, at (sin θ, cos θ).
    fn load_moment_and_sum(&self, sin_cos: (f64, f64)) -> (f64, [f64; 2]) {
        let mut moment = 0.0;
        let mut sum = [0.0, 0.0];
        for (point, force) in &self.loads {
            moment += cross(rotate(sin_cos, *point), *force);
            sum[0] += force[0];
            sum[1] += force[1];
        }
        (moment, sum)
    }
}

/// The parts of a four-bar with a coupler–rocker clearance joint, as found in a model.
struct FourBar<'m> {
    driver: &'m Driver,
    /// +1 if ground is the driven joint's first body, −1 if its second.
    sign: f64,
    /// Crank ground pivot O2 (m).
    o2: [f64; 2],
    /// Rocker ground pivot O4 (m).
    o4: [f64; 2],
    clearance_joint: &'m Joint,
    spec: &'m ClearanceSpec,
    bearing_on_coupler: bool,
    /// (body, first joint point, second joint point) of crank, coupler and rocker.
    links: [(BodyId, &'m Anchor, &'m Anchor); 3],
}

/// Finds crank, coupler and rocker and their joints, or says what the model lacks.
fn find_four_bar(model: &Model) -> Result<FourBar<'_>, FormulationError> {
    let n_bodies = model.bodies.len();
    if n_bodies != 3 {
        return Err(unsupported(format!(
            "needs exactly 3 moving bodies (crank, coupler, rocker); the model has {n_bodies}"
        )));
    }
    let [driver] = model.drivers.as_slice() else {
        return Err(unsupported(format!(
            "needs exactly one driver, on the revolute joint between ground and the crank; the model has {}",
            model.drivers.len()
        )));
    };
    let driver_joint = model.joints.get(driver.joint.0).ok_or_else(|| {
        unsupported(format!(
            "driver \"{}\" refers to a joint the model does not have",
            driver.name
        ))
    })?;
    let (crank_id, crank_pivot, o2, sign) = match (driver_joint.a.frame, driver_joint.b.frame) {
        (Frame::Ground, Frame::Body(c)) => (c, &driver_joint.b, driver_joint.a.local, 1.0),
        (Frame::Body(c), Frame::Ground) => (c, &driver_joint.a, driver_joint.b.local, -1.0),
        (a, b) => {
            return Err(unsupported(format!(
                "driver \"{}\" drives joint \"{}\" between \"{}\" and \"{}\"; it must drive the joint between ground and the crank",
                driver.name,
                driver_joint.name,
                model.frame_name(a),
                model.frame_name(b)
            )));
        }
    };
    let clearance: Vec<(usize, &Joint, &ClearanceSpec)> = model
        .joints
        .iter()
        .enumerate()
        .filter_map(|(i, j)| match &j.kind {
            JointKind::Clearance(spec) => Some((i, j, spec)),
            _ => None,
        })
        .collect();
    let [(clearance_index, clearance_joint, spec)] = clearance.as_slice() else {
        return Err(unsupported(format!(
            "needs exactly one clearance joint, between the coupler and the rocker; the model has {}",
            clearance.len()
        )));
    };
    let crank_name = &model.body(crank_id).name;
    // Crank–coupler: an ideal revolute joint from the crank to another body.
    let Some((crank_coupler_index, crank_coupler)) =
        model.joints.iter().enumerate().find(|(i, j)| {
            *i != driver.joint.0
                && matches!(j.kind, JointKind::Revolute)
                && matches!(
                    (j.a.frame, j.b.frame),
                    (Frame::Body(a), Frame::Body(b)) if (a == crank_id) != (b == crank_id)
                )
        })
    else {
        return Err(unsupported(format!(
            "needs an ideal revolute joint between the crank \"{crank_name}\" and the coupler; found none (the clearance joint must be the coupler–rocker joint)"
        )));
    };
    let (crank_a, coupler_a) = if crank_coupler.a.frame == Frame::Body(crank_id) {
        (&crank_coupler.a, &crank_coupler.b)
    } else {
        (&crank_coupler.b, &crank_coupler.a)
    };
    let Frame::Body(coupler_id) = coupler_a.frame else {
        return Err(unsupported(format!(
            "joint \"{}\" must connect the crank \"{crank_name}\" to the coupler",
            crank_coupler.name
        )));
    };
    let Some(rocker_id) = (0..3)
        .map(BodyId)
        .find(|&b| b != crank_id && b != coupler_id)
    else {
        return Err(unsupported(
            "cannot tell the rocker from the crank and the coupler".to_string(),
        ));
    };
    let (coupler_name, rocker_name) = (&model.body(coupler_id).name, &model.body(rocker_id).name);
    // Clearance joint between coupler and rocker, either way round.
    let bearing_on_coupler = match (clearance_joint.a.frame, clearance_joint.b.frame) {
        (Frame::Body(a), Frame::Body(b)) if a == coupler_id && b == rocker_id => true,
        (Frame::Body(a), Frame::Body(b)) if a == rocker_id && b == coupler_id => false,
        (a, b) => {
            return Err(unsupported(format!(
                "clearance joint \"{}\" connects \"{}\" and \"{}\"; it must connect the coupler \"{coupler_name}\" and the rocker \"{rocker_name}\"",
                clearance_joint.name,
                model.frame_name(a),
                model.frame_name(b)
            )));
        }
    };
    let (coupler_b, rocker_b) = if bearing_on_coupler {
        (&clearance_joint.a, &clearance_joint.b)
    } else {
        (&clearance_joint.b, &clearance_joint.a)
    };
    // Rocker–ground: an ideal revolute joint.
    let rocker_ground = model.joints.iter().enumerate().find(|(_, j)| {
        matches!(j.kind, JointKind::Revolute)
            && matches!(
                (j.a.frame, j.b.frame),
                (Frame::Ground, Frame::Body(b)) | (Frame::Body(b), Frame::Ground) if b == rocker_id
            )
    });
    let Some((rocker_ground_index, rocker_ground)) = rocker_ground else {
        return Err(unsupported(format!(
            "needs an ideal revolute joint between the rocker \"{rocker_name}\" and ground; found none"
        )));
    };
    let (rocker_pivot, o4) = if rocker_ground.a.frame == Frame::Ground {
        (&rocker_ground.b, rocker_ground.a.local)
    } else {
        (&rocker_ground.a, rocker_ground.b.local)
    };
    let used = [
        driver.joint.0,
        crank_coupler_index,
        *clearance_index,
        rocker_ground_index,
    ];
    if let Some(extra) = model
        .joints
        .iter()
        .enumerate()
        .find(|(i, _)| !used.contains(i))
        .map(|(_, j)| j)
    {
        return Err(unsupported(format!(
            "joint \"{}\" ({} between \"{}\" and \"{}\") is not part of the four-bar ground–crank–coupler–rocker–ground; no other joints are allowed",
            extra.name,
            extra.kind.type_name(),
            model.frame_name(extra.a.frame),
            model.frame_name(extra.b.frame)
        )));
    }

    Ok(FourBar {
        driver,
        sign,
        o2,
        o4,
        clearance_joint,
        spec,
        bearing_on_coupler,
        links: [
            (crank_id, crank_pivot, crank_a),
            (coupler_id, coupler_a, coupler_b),
            (rocker_id, rocker_pivot, rocker_b),
        ],
    })
}

/// Body-frame point `s` in the line frame of a link whose first joint point is `first` and whose
/// line has direction `beta` in the body frame: R(−β)(s − first).
fn to_line_frame(beta: f64, first: [f64; 2], s: [f64; 2]) -> [f64; 2] {
    rotate((-beta).sin_cos(), [s[0] - first[0], s[1] - first[1]])
}

fn unsupported(reason: String) -> FormulationError {
    FormulationError::Unsupported {
        formulation: NAME.to_string(),
        reason,
    }
}

/// Pose, velocity and acceleration of a body's centre of mass — the DAE's output columns
/// `B.x B.y B.phi B.vx B.vy B.omega B.ax B.ay B.alpha`.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct BodyKinematics {
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Orientation φ of the body x-axis (rad), = θ − β.
    pub phi: f64,
    /// ẋ (m/s).
    pub vx: f64,
    /// ẏ (m/s).
    pub vy: f64,
    /// φ̇ (rad/s).
    pub omega: f64,
    /// ẍ (m/s²).
    pub ax: f64,
    /// ÿ (m/s²).
    pub ay: f64,
    /// φ̈ (rad/s²).
    pub alpha: f64,
}

/// Everything the reduced model yields at one (t, y).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct ReducedOutputs {
    /// Time (s).
    pub t: f64,
    /// Crank angle θ2 (rad).
    pub theta2: f64,
    /// Coupler angle θ3 (rad).
    pub theta3: f64,
    /// Rocker angle θ4 (rad).
    pub theta4: f64,
    /// θ̇2 (rad/s), the driver's constant speed.
    pub theta2_dot: f64,
    /// θ̇3 (rad/s).
    pub theta3_dot: f64,
    /// θ̇4 (rad/s).
    pub theta4_dot: f64,
    /// θ̈3 (rad/s²).
    pub theta3_ddot: f64,
    /// θ̈4 (rad/s²).
    pub theta4_ddot: f64,
    /// Eccentricity e = journal centre − bearing centre (m).
    pub eccentricity: [f64; 2],
    /// ė (m/s).
    pub eccentricity_rate: [f64; 2],
    /// ë (m/s²).
    pub eccentricity_acceleration: [f64; 2],
    /// Penetration δ = |e| − c (m).
    pub delta: f64,
    /// Impact velocity δ̇⁽⁻⁾ stored in the state (m/s; 0 = none recorded).
    pub impact_velocity: f64,
    /// δ̇ (m/s).
    pub delta_dot: f64,
    /// Slip velocity v_t of the journal on the bearing (m/s).
    pub tangential_velocity: f64,
    /// Normal contact force F_N (N).
    pub normal_force: f64,
    /// Friction force F_T on the journal along t (N).
    pub friction_force: f64,
    /// Power of the contact forces on both bodies, −F_N δ̇ + F_T v_t (W).
    pub contact_power: f64,
    /// Crank torque M2 keeping θ̇2 constant (N·m, on the crank, counter-clockwise positive).
    pub crank_torque: f64,
    /// Crank centre of mass.
    pub crank: BodyKinematics,
    /// Coupler centre of mass.
    pub coupler: BodyKinematics,
    /// Rocker centre of mass.
    pub rocker: BodyKinematics,
}

/// The reduced Lagrangian formulation of a four-bar with one clearance joint (module
/// documentation).
#[derive(Debug, Clone)]
pub struct ReducedLagrangian {
    model: Model,
    crank: Link,
    coupler: Link,
    rocker: Link,
    /// Crank ground pivot O2 (m).
    o2: [f64; 2],
    /// Rocker ground pivot O4 (m).
    o4: [f64; 2],
    /// θ2 at t = 0 (rad).
    theta2_0: f64,
    /// θ̇2 (rad/s).
    theta2_dot: f64,
    gravity: [f64; 2],
    /// True if the coupler carries the bearing (and the rocker the journal).
    bearing_on_coupler: bool,
    joint: ClearanceJoint,
    joint_name: String,
    driver_name: String,
    /// Event log (bookkeeping only; the stored δ̇⁽⁻⁾ is in the state vector).
    memory: ContactMemory,
    /// Slip speeds (v0, v1) of the friction law's kinks, when they are event functions
    /// (`contact/kinks.rs`; on by default for a law with kinks).
    kink_events: Option<[f64; 2]>,
    /// Start time (s): 0, or the time of a warm start ([`ReducedLagrangian::start_from`]).
    t0: f64,
    y0: [f64; 5],
    /// The last angles (θ2, θ3, θ4) and their sines and cosines: a step's last right-hand side
    /// is at the state that the event functions, the grazing guard and the impact log read
    /// next, and `sin_cos` is a third of an evaluation.
    trig: Cell<TrigCache>,
}

/// (θ2, θ3, θ4) as bits (an exact match, −0 apart from +0) and their (sin, cos).
#[derive(Debug, Clone, Copy)]
struct TrigCache {
    angles: [u64; 3],
    sc: [(f64, f64); 3],
}

impl Default for TrigCache {
    /// A true entry (three angles +0), so that every hit is one.
    fn default() -> Self {
        TrigCache {
            angles: [0.0f64.to_bits(); 3],
            sc: [0.0f64.sin_cos(); 3],
        }
    }
}

/// Where a run of the reduced model ended, as the clearance joint sees it: enough to start a
/// run of a neighbouring model (another clearance, mass, length, speed) near the same motion
/// ([`ReducedLagrangian::start_from`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WarmState {
    /// The state [θ3, θ4, θ̇3, θ̇4, δ̇⁽⁻⁾] (rad, rad/s, m/s).
    pub y: [f64; 5],
    /// Eccentricity e = r_J − r_B (m).
    pub eccentricity: [f64; 2],
    /// ė (m/s).
    pub eccentricity_rate: [f64; 2],
    /// Radial clearance c of the model it came from (m).
    pub clearance: f64,
}

/// Kinematics of the link chain at one (t, y), before any force.
#[derive(Debug, Clone, Copy)]
struct Chain {
    theta2: f64,
    sc: [(f64, f64); 3],
    /// d2 = A − O2, d3 = C3 − A, d4 = C4 − O4 (m).
    d: [[f64; 2]; 3],
    a_pos: [f64; 2],
    a_vel: [f64; 2],
    a_acc: [f64; 2],
    /// Clearance-joint centres on the coupler (C3) and on the rocker (C4).
    coupler_centre: CentreMotion,
    rocker_centre: CentreMotion,
}

impl ReducedLagrangian {
    /// Checks that `model` is a four-bar of the supported form, reads its geometry and assembles
    /// the initial state (module documentation).
    pub fn new(model: &Model) -> Result<Self, FormulationError> {
        let four_bar = find_four_bar(model)?;
        let [
            (crank_id, crank_pivot, crank_a),
            (coupler_id, coupler_a, coupler_b),
            (rocker_id, rocker_pivot, rocker_b),
        ] = four_bar.links;
        let (driver, sign, spec) = (four_bar.driver, four_bar.sign, four_bar.spec);
        let mut crank = Link::new(model, crank_id, crank_pivot, crank_a)?;
        let mut coupler = Link::new(model, coupler_id, coupler_a, coupler_b)?;
        let mut rocker = Link::new(model, rocker_id, rocker_pivot, rocker_b)?;
        let firsts = [crank_pivot.local, coupler_a.local, rocker_pivot.local];
        for force in &model.forces {
            match force {
                ForceElement::Torque { body, torque, .. } => {
                    if let Some(link) = [&mut crank, &mut coupler, &mut rocker]
                        .into_iter()
                        .find(|l| l.body == *body)
                    {
                        link.torque += torque;
                    }
                }
                ForceElement::PointForce { at, force, .. } => {
                    if let Frame::Body(body) = at.frame {
                        for (link, first) in [&mut crank, &mut coupler, &mut rocker]
                            .into_iter()
                            .zip(firsts)
                        {
                            if link.body == body {
                                link.loads
                                    .push((to_line_frame(link.beta, first, at.local), *force));
                            }
                        }
                    }
                }
                ForceElement::SpringDamper { name, .. } => {
                    return Err(unsupported(format!(
                        "force \"{name}\" is a spring-damper; only gravity, constant torques and constant point forces are supported"
                    )));
                }
                other @ (ForceElement::TorqueLaw { .. }
                | ForceElement::ForceLaw { .. }
                | ForceElement::Motor { .. }) => {
                    return Err(unsupported(format!(
                        "{} \"{}\" is an expression of time or state; only gravity, constant torques and constant point forces are supported (use the DAE formulation)",
                        other.type_name(),
                        other.name()
                    )));
                }
            }
        }
        if !matches!(driver.motion, crate::model::DriverMotion::ConstantSpeed) {
            return Err(unsupported(format!(
                "driver \"{}\" is not a constant-speed driver; the reduced formulation integrates the four-bar at a constant crank speed (use the DAE formulation)",
                driver.name
            )));
        }
        if let Some(o) = model.outputs.first() {
            return Err(unsupported(format!(
                "output point \"{}\" is not reported by the reduced formulation (use the DAE formulation)",
                o.name
            )));
        }

        let mut reduced = ReducedLagrangian {
            model: model.clone(),
            o2: four_bar.o2,
            o4: four_bar.o4,
            theta2_0: sign * driver.initial_angle + crank.beta,
            theta2_dot: sign * driver.speed,
            gravity: model.settings.gravity,
            bearing_on_coupler: four_bar.bearing_on_coupler,
            joint: ClearanceJoint::from_spec(spec),
            joint_name: four_bar.clearance_joint.name.clone(),
            driver_name: driver.name.clone(),
            memory: ContactMemory::new(false),
            kink_events: kinks::friction_kinks(&spec.friction),
            t0: 0.0,
            y0: [0.0; 5],
            trig: Cell::default(),
            crank,
            coupler,
            rocker,
        };
        let guess = [
            model.body(coupler_id).initial.phi + reduced.coupler.beta,
            model.body(rocker_id).initial.phi + reduced.rocker.beta,
        ];
        let [th3, th4, w3, w4] =
            reduced.assemble(0.0, spec.initial_eccentricity, [0.0, 0.0], guess)?;
        // No impact recorded: a contact present at t = 0 starts without a stored δ̇⁽⁻⁾.
        reduced.y0 = [th3, th4, w3, w4, 0.0];
        let delta0 = reduced.kinematics(0.0, &reduced.y0).delta;
        reduced.memory = ContactMemory::new(delta0 > 0.0);
        Ok(reduced)
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The clearance joint's contact model.
    pub fn clearance_joint(&self) -> &ClearanceJoint {
        &self.joint
    }

    /// True if the coupler carries the bearing and the rocker the journal (as in the paper).
    pub fn bearing_on_coupler(&self) -> bool {
        self.bearing_on_coupler
    }

    /// Link lengths [L1, L2, L3, L4] (m): ground O2–O4, crank, coupler, rocker.
    pub fn link_lengths(&self) -> [f64; 4] {
        let g = [self.o4[0] - self.o2[0], self.o4[1] - self.o2[1]];
        [
            g[0].hypot(g[1]),
            self.crank.length,
            self.coupler.length,
            self.rocker.length,
        ]
    }

    /// With `on` (the default), the kinks of the friction law (slip speeds ±v0, ±v1) are event
    /// functions 1–4 while in contact, so that Radau5 ends its steps at them
    /// (`contact/kinks.rs`); off, δ is the only event function. A model without
    /// friction has none either way. [`crate::simulation::Simulation`] switches them off for
    /// every method but Radau5 (their steps do not change at events).
    #[must_use]
    pub fn friction_kink_events(mut self, on: bool) -> Self {
        self.kink_events = if on {
            kinks::friction_kinks(&self.joint.friction)
        } else {
            None
        };
        self
    }

    /// Contact events logged so far (impact times and velocities, separations).
    pub fn contact_memory(&self) -> &ContactMemory {
        &self.memory
    }

    /// Clears the event log, for a new run from the initial state.
    pub fn reset_contact_memory(&mut self) {
        let delta0 = self.kinematics(self.t0, &self.y0).delta;
        self.memory = ContactMemory::new(delta0 > 0.0);
    }

    /// The [`WarmState`] at (t, y) of a run of this model.
    pub fn warm_state(&self, t: f64, y: &[f64]) -> WarmState {
        let c = self.chain(t, y);
        WarmState {
            y: state(y),
            eccentricity: self.oriented_e(c.rocker_centre.position, c.coupler_centre.position),
            eccentricity_rate: self.oriented_e(c.rocker_centre.velocity, c.coupler_centre.velocity),
            clearance: self.joint.clearance,
        }
    }

    /// Starts the runs of this model at time `t` (s) from `warm`, the state a run of a
    /// neighbouring model ended in, instead of the model's initial state. `t` should be at the
    /// same crank angle (mod 2π) as the time `warm` was taken at, so that the motion carries on.
    ///
    /// The eccentricity is carried into this model's clearance c from the earlier one's c′:
    /// inside the clearance (|e| ≤ c′) it is scaled by c/c′ with its rate, so the journal keeps
    /// its place relative to the wall; in contact the journal keeps its penetration δ = |e| − c
    /// and ė, so the contact force stays what it was (a shift by c − c′ alone would turn a
    /// smaller clearance into a deep penetration and a large force spike). θ3, θ4 are then
    /// solved for that e by Newton's method from the earlier angles, θ̇3, θ̇4 for that ė; the
    /// stored impact velocity δ̇⁽⁻⁾ is kept while in contact and cleared otherwise.
    ///
    /// Errors: [`FormulationError::Unassemblable`] when the linkage cannot reach that e (a
    /// neighbouring model too different); the formulation is then unchanged.
    pub fn start_from(&mut self, t: f64, warm: &WarmState) -> Result<(), FormulationError> {
        let (c_new, c_old) = (self.joint.clearance, warm.clearance);
        let [ex, ey] = warm.eccentricity;
        let r = ex.hypot(ey);
        let (e, e_dot) = if r > c_old && r > 0.0 {
            let scale = (r - c_old + c_new) / r;
            ([ex * scale, ey * scale], warm.eccentricity_rate)
        } else {
            let scale = if c_old > 0.0 { c_new / c_old } else { 1.0 };
            let [vx, vy] = warm.eccentricity_rate;
            ([ex * scale, ey * scale], [vx * scale, vy * scale])
        };
        let [th3, th4, w3, w4] = self.assemble(t, e, e_dot, [warm.y[0], warm.y[1]])?;
        let mut y = [th3, th4, w3, w4, 0.0];
        let in_contact = self.kinematics(t, &y).delta > 0.0;
        if in_contact {
            y[4] = warm.y[4];
        }
        self.t0 = t;
        self.y0 = y;
        self.memory = ContactMemory::new(in_contact);
        Ok(())
    }

    /// Solves the loop closure r_J − r_B = `e0` for θ3, θ4 at time `t` by Newton's method from
    /// `guess`, then the velocities for ė = `e_dot`. Returns [θ3, θ4, θ̇3, θ̇4].
    fn assemble(
        &self,
        t: f64,
        e0: [f64; 2],
        e_dot: [f64; 2],
        guess: [f64; 2],
    ) -> Result<[f64; 4], FormulationError> {
        let closure = |th: [f64; 2]| {
            let y = [th[0], th[1], 0.0, 0.0, 0.0];
            let c = self.chain(t, &y);
            let e = self.oriented_e(c.rocker_centre.position, c.coupler_centre.position);
            [e[0] - e0[0], e[1] - e0[1]]
        };
        let norm = |r: [f64; 2]| r[0].abs().max(r[1].abs());
        let mut th = guess;
        let mut r = closure(th);
        let mut residual = norm(r);
        let mut iterations = 0;
        while residual > POSITION_TOLERANCE && iterations < MAX_ITERATIONS {
            iterations += 1;
            // Columns ∂(r_J − r_B)/∂θ3 and ∂/∂θ4 (orientation sign s: see `oriented_e`).
            let (c3, c4) = self.closure_columns(th);
            let det = cross(c3, c4);
            if det.is_nan() || det.abs() <= 1e-12 * self.coupler.length * self.rocker.length {
                break;
            }
            // Newton step Δθ = −[c3 c4]⁻¹ r by Cramer's rule.
            let step = [-cross(r, c4) / det, -cross(c3, r) / det];
            let mut length = 1.0;
            let mut accepted = false;
            while length > 1e-6 {
                let trial = [th[0] + length * step[0], th[1] + length * step[1]];
                let rt = closure(trial);
                if norm(rt) < residual {
                    th = trial;
                    r = rt;
                    residual = norm(rt);
                    accepted = true;
                    break;
                }
                length *= 0.5;
            }
            if !accepted {
                break;
            }
        }
        if residual.is_nan() || residual > POSITION_TOLERANCE {
            return Err(FormulationError::Unassemblable {
                joint: self.joint_name.clone(),
                residual,
                iterations,
            });
        }
        // Velocities: ė = s (v_C4 − v_C3) = θ̇3 c3 + θ̇4 c4 − s v_A.
        let (c3, c4) = self.closure_columns(th);
        let c = self.chain(t, &[th[0], th[1], 0.0, 0.0, 0.0]);
        let s = if self.bearing_on_coupler { 1.0 } else { -1.0 };
        let rhs = [s * c.a_vel[0] + e_dot[0], s * c.a_vel[1] + e_dot[1]];
        let det = cross(c3, c4);
        Ok([th[0], th[1], cross(rhs, c4) / det, cross(c3, rhs) / det])
    }

    /// ∂(r_J − r_B)/∂θ3 and ∂(r_J − r_B)/∂θ4 at θ3, θ4.
    fn closure_columns(&self, th: [f64; 2]) -> ([f64; 2], [f64; 2]) {
        let s = if self.bearing_on_coupler { 1.0 } else { -1.0 };
        let (s3, c3) = th[0].sin_cos();
        let (s4, c4) = th[1].sin_cos();
        // ∂C3/∂θ3 = L3 J u3 enters r_J − r_B with −s; ∂C4/∂θ4 = L4 J u4 with +s.
        let l3 = self.coupler.length;
        let l4 = self.rocker.length;
        ([s * l3 * s3, -s * l3 * c3], [-s * l4 * s4, s * l4 * c4])
    }

    /// e = r_J − r_B from the rocker's and the coupler's clearance centres.
    fn oriented_e(&self, rocker_centre: [f64; 2], coupler_centre: [f64; 2]) -> [f64; 2] {
        let d = [
            rocker_centre[0] - coupler_centre[0],
            rocker_centre[1] - coupler_centre[1],
        ];
        if self.bearing_on_coupler {
            d
        } else {
            [-d[0], -d[1]]
        }
    }

    /// (sin, cos) of three angles: computed and kept (`FRESH`, the right-hand side: it never
    /// reads the cache, since reading back what the last evaluation has just stored stalls on
    /// store forwarding, which cost more than the sin_cos it saved), or from the cache when they
    /// are the last ones computed (the event functions, the grazing guard and the impact log at
    /// a step end, where the step's last right-hand side was).
    #[inline(always)]
    fn sin_cos<const FRESH: bool>(&self, angles: [f64; 3]) -> [(f64, f64); 3] {
        let bits = angles.map(f64::to_bits);
        if !FRESH {
            let cached = self.trig.get();
            if cached.angles == bits {
                return cached.sc;
            }
        }
        let sc = angles.map(|a| {
            let (sin, cos) = a.sin_cos();
            // Each value through its own register: otherwise the compiler lets `sincos` write
            // straight into the cache and then reads each (sin, cos) pair back with one 16-byte
            // load, which cannot be forwarded from the two 8-byte stores just made and stalls
            // (perf: about a tenth of the right-hand side's cycles).
            (std::hint::black_box(sin), std::hint::black_box(cos))
        });
        self.trig.set(TrigCache { angles: bits, sc });
        sc
    }

    /// Link kinematics at (t, y): angles, A and the two clearance centres with their velocities
    /// (`FRESH`: see [`ReducedLagrangian::sin_cos`]).
    #[inline(always)] // as `dynamics`: the right-hand side uses part of it
    fn chain_with<const FRESH: bool>(&self, t: f64, y: &[f64]) -> Chain {
        let [th3, th4, w3, w4, _] = state(y);
        let theta2 = self.theta2_0 + self.theta2_dot * t;
        let w2 = self.theta2_dot;
        let sc = self.sin_cos::<FRESH>([theta2, th3, th4]);
        let unit = |k: usize, l: f64| [l * sc[k].1, l * sc[k].0];
        let d = [
            unit(0, self.crank.length),
            unit(1, self.coupler.length),
            unit(2, self.rocker.length),
        ];
        let a_pos = [self.o2[0] + d[0][0], self.o2[1] + d[0][1]];
        let jd2 = perp(d[0]);
        let a_vel = [w2 * jd2[0], w2 * jd2[1]];
        let a_acc = [-w2 * w2 * d[0][0], -w2 * w2 * d[0][1]];
        let jd3 = perp(d[1]);
        let jd4 = perp(d[2]);
        Chain {
            theta2,
            sc,
            d,
            a_pos,
            a_vel,
            a_acc,
            coupler_centre: CentreMotion {
                position: [a_pos[0] + d[1][0], a_pos[1] + d[1][1]],
                velocity: [a_vel[0] + w3 * jd3[0], a_vel[1] + w3 * jd3[1]],
                omega: w3,
            },
            rocker_centre: CentreMotion {
                position: [self.o4[0] + d[2][0], self.o4[1] + d[2][1]],
                velocity: [w4 * jd4[0], w4 * jd4[1]],
                omega: w4,
            },
        }
    }

    /// [`ReducedLagrangian::chain_with`], the angles' sines from the cache where they are there.
    fn chain(&self, t: f64, y: &[f64]) -> Chain {
        self.chain_with::<false>(t, y)
    }

    /// Clearance-joint kinematics at (t, y).
    fn kinematics(&self, t: f64, y: &[f64]) -> ContactKinematics {
        let c = self.chain(t, y);
        self.joint_kinematics(&c)
    }

    #[inline(always)] // as `dynamics`: otherwise the chain and the kinematics go through memory
    fn joint_kinematics(&self, c: &Chain) -> ContactKinematics {
        if self.bearing_on_coupler {
            self.joint.kinematics(&c.coupler_centre, &c.rocker_centre)
        } else {
            self.joint.kinematics(&c.rocker_centre, &c.coupler_centre)
        }
    }

    /// The equations of motion at (t, y): everything the right-hand side needs, kept for
    /// [`ReducedLagrangian::outputs`].
    #[inline(always)] // the right-hand side reads two of its fields: inlined, the rest is not built
    fn dynamics(&self, t: f64, y: &[f64]) -> Result<Dynamics, FormulationError> {
        let [_, _, _, _, stored] = state(y);
        let g = self.gravity;
        let c = self.chain_with::<true>(t, y);
        let kin = self.joint_kinematics(&c);
        if kin.delta > self.joint.max_penetration() {
            return Err(FormulationError::PenetrationTooDeep {
                t,
                joint: self.joint_name.clone(),
                penetration: kin.delta,
                limit: self.joint.max_penetration(),
            });
        }
        let forces = self
            .joint
            .forces(&kin, impact_velocity(stored, kin.delta_dot));
        let (f3, m3c, f4, m4c) = if self.bearing_on_coupler {
            (
                forces.on_bearing,
                forces.bearing_moment,
                forces.on_journal,
                forces.journal_moment,
            )
        } else {
            (
                forces.on_journal,
                forces.journal_moment,
                forces.on_bearing,
                forces.bearing_moment,
            )
        };
        let (cp, rk) = (&self.coupler, &self.rocker);
        let a3 = rotate(c.sc[1], cp.com);
        let a4 = rotate(c.sc[2], rk.com);
        let weight = |m: f64| [m * g[0], m * g[1]];
        let (load3, load3_sum) = cp.load_moment_and_sum(c.sc[1]);
        let (load4, _) = rk.load_moment_and_sum(c.sc[2]);

        // Coupler: moments about A, with the d'Alembert force −m3 a_A of the moving pivot.
        let q3 = cross(a3, weight(cp.mass)) - cp.mass * cross(a3, c.a_acc)
            + cross(c.d[1], f3)
            + m3c
            + cp.torque
            + load3;
        let alpha3 = q3 / cp.pivot_inertia();
        // Rocker: moments about the fixed pivot O4.
        let q4 = cross(a4, weight(rk.mass)) + cross(c.d[2], f4) + m4c + rk.torque + load4;
        let alpha4 = q4 / rk.pivot_inertia();
        for (alpha, link) in [(alpha3, cp), (alpha4, rk)] {
            if !alpha.is_finite() {
                return Err(FormulationError::NonFinite {
                    t,
                    body: self.model.body(link.body).name.clone(),
                    what: "acceleration".into(),
                });
            }
        }
        Ok(Dynamics {
            chain: c,
            kin,
            forces,
            f3,
            load3_sum,
            a3,
            a4,
            alpha3,
            alpha4,
        })
    }

    /// ë = r̈_J − r̈_B of the clearance centres (m/s²) for the link rates [θ̇3, θ̇4] (rad/s) and
    /// accelerations [θ̈3, θ̈4] (rad/s²).
    fn e_ddot(&self, c: &Chain, rates: [f64; 2], accelerations: [f64; 2]) -> [f64; 2] {
        let [w3, w4] = rates;
        let [alpha3, alpha4] = accelerations;
        let accel = |d: [f64; 2], alpha: f64, w: f64| {
            let jd = perp(d);
            [alpha * jd[0] - w * w * d[0], alpha * jd[1] - w * w * d[1]]
        };
        let acc3 = accel(c.d[1], alpha3, w3);
        let acc_c3 = [c.a_acc[0] + acc3[0], c.a_acc[1] + acc3[1]];
        let acc_c4 = accel(c.d[2], alpha4, w4);
        let s = if self.bearing_on_coupler { 1.0 } else { -1.0 };
        [s * (acc_c4[0] - acc_c3[0]), s * (acc_c4[1] - acc_c3[1])]
    }

    /// The clearance joint at (t, y) from the link kinematics alone, without the equations of
    /// motion: its kinematics and forces (with the stored δ̇⁽⁻⁾ of y, which is returned too).
    pub fn contact_at(&self, t: f64, y: &[f64]) -> (ContactKinematics, ContactForces, f64) {
        let stored = state(y)[4];
        let kin = self.kinematics(t, y);
        let forces = self
            .joint
            .forces(&kin, impact_velocity(stored, kin.delta_dot));
        (kin, forces, stored)
    }

    /// As [`ReducedLagrangian::contact_at`], with the relative acceleration ë of the clearance
    /// centres (m/s²) from θ̈3, θ̈4 in `y_dot`, the time derivative of y.
    pub fn contact_motion_at(
        &self,
        t: f64,
        y: &[f64],
        y_dot: &[f64],
    ) -> (ContactKinematics, ContactForces, f64, [f64; 2]) {
        let [_, _, w3, w4, stored] = state(y);
        let c = self.chain(t, y);
        let kin = self.joint_kinematics(&c);
        let forces = self
            .joint
            .forces(&kin, impact_velocity(stored, kin.delta_dot));
        let [_, _, alpha3, alpha4, _] = state(y_dot);
        let e_ddot = self.e_ddot(&c, [w3, w4], [alpha3, alpha4]);
        (kin, forces, stored, e_ddot)
    }

    /// Everything at (t, y): angles and rates, θ̈3, θ̈4, the clearance joint's state and forces,
    /// the crank torque M2 and the body states. Fails with `NonFinite` if an acceleration is not
    /// finite.
    pub fn outputs(&self, t: f64, y: &[f64]) -> Result<ReducedOutputs, FormulationError> {
        let [th3, th4, w3, w4, stored] = state(y);
        let w2 = self.theta2_dot;
        let g = self.gravity;
        let Dynamics {
            chain: c,
            kin,
            forces,
            f3,
            load3_sum,
            a3,
            a4,
            alpha3,
            alpha4,
        } = self.dynamics(t, y)?;
        let (cr, cp, rk) = (&self.crank, &self.coupler, &self.rocker);
        let a2 = rotate(c.sc[0], cr.com);
        let weight = |m: f64| [m * g[0], m * g[1]];
        let (load2, _) = cr.load_moment_and_sum(c.sc[0]);

        // Coupler centre-of-mass acceleration and the pin force of the crank on the coupler.
        let ja3 = perp(a3);
        let a_g3 = [
            c.a_acc[0] + alpha3 * ja3[0] - w3 * w3 * a3[0],
            c.a_acc[1] + alpha3 * ja3[1] - w3 * w3 * a3[1],
        ];
        let f_a = [
            cp.mass * (a_g3[0] - g[0]) - f3[0] - load3_sum[0],
            cp.mass * (a_g3[1] - g[1]) - f3[1] - load3_sum[1],
        ];
        let crank_torque = cross(c.d[0], f_a) - cross(a2, weight(cr.mass)) - cr.torque - load2;

        // Relative acceleration of the clearance centres (for the grazing guard).
        let e_ddot = self.e_ddot(&c, [w3, w4], [alpha3, alpha4]);

        let fixed = |p: [f64; 2]| Pivot {
            position: p,
            velocity: [0.0; 2],
            acceleration: [0.0; 2],
        };
        let a_pivot = Pivot {
            position: c.a_pos,
            velocity: c.a_vel,
            acceleration: c.a_acc,
        };
        Ok(ReducedOutputs {
            t,
            theta2: c.theta2,
            theta3: th3,
            theta4: th4,
            theta2_dot: w2,
            theta3_dot: w3,
            theta4_dot: w4,
            theta3_ddot: alpha3,
            theta4_ddot: alpha4,
            eccentricity: kin.e,
            eccentricity_rate: kin.e_dot,
            eccentricity_acceleration: e_ddot,
            delta: kin.delta,
            impact_velocity: stored,
            delta_dot: kin.delta_dot,
            tangential_velocity: kin.tangential_velocity,
            normal_force: forces.normal_force,
            friction_force: forces.friction_force,
            contact_power: forces.power,
            crank_torque,
            crank: fixed(self.o2).body(a2, c.theta2 - cr.beta, w2, 0.0),
            coupler: a_pivot.body(a3, th3 - cp.beta, w3, alpha3),
            rocker: fixed(self.o4).body(a4, th4 - rk.beta, w4, alpha4),
        })
    }
}

/// The state of the equations of motion at one (t, y) (see [`ReducedLagrangian::dynamics`]).
struct Dynamics {
    chain: Chain,
    kin: ContactKinematics,
    forces: ContactForces,
    /// Contact force on the coupler (N).
    f3: [f64; 2],
    /// Sum of the applied point forces on the coupler (N).
    load3_sum: [f64; 2],
    /// Arms O→G of coupler and rocker (m).
    a3: [f64; 2],
    a4: [f64; 2],
    /// θ̈3, θ̈4 (rad/s²).
    alpha3: f64,
    alpha4: f64,
}

/// Motion of a link's first joint point.
#[derive(Debug, Clone, Copy)]
struct Pivot {
    position: [f64; 2],
    velocity: [f64; 2],
    acceleration: [f64; 2],
}

impl Pivot {
    /// The centre of mass at arm `arm` from this pivot on a body with orientation `phi`, angular
    /// velocity `omega` and angular acceleration `alpha`: r = p + a, v = ṗ + ω J a,
    /// acc = p̈ + α J a − ω² a.
    fn body(&self, arm: [f64; 2], phi: f64, omega: f64, alpha: f64) -> BodyKinematics {
        let ja = perp(arm);
        BodyKinematics {
            x: self.position[0] + arm[0],
            y: self.position[1] + arm[1],
            phi,
            vx: self.velocity[0] + omega * ja[0],
            vy: self.velocity[1] + omega * ja[1],
            omega,
            ax: self.acceleration[0] + alpha * ja[0] - omega * omega * arm[0],
            ay: self.acceleration[1] + alpha * ja[1] - omega * omega * arm[1],
            alpha,
        }
    }
}

/// [θ3, θ4, θ̇3, θ̇4, δ̇⁽⁻⁾] from y; entries missing from a short `y` read as NaN, which the
/// finiteness check of the accelerations then reports.
fn state(y: &[f64]) -> [f64; 5] {
    debug_assert_eq!(y.len(), 5, "the reduced state is [θ3, θ4, θ̇3, θ̇4, δ̇⁽⁻⁾]");
    std::array::from_fn(|i| y.get(i).copied().unwrap_or(f64::NAN))
}

impl Outputs for ReducedLagrangian {
    /// Names of the output columns of [`Outputs::outputs_into`], in order: per body in
    /// model order `B.x B.y B.phi B.vx B.vy B.omega B.ax B.ay B.alpha` (as the DAE), then
    /// `D.torque` for the driver, then `J.ex J.ey J.delta J.fn J.ft` for the clearance joint.
    fn output_names(&self) -> Vec<String> {
        let mut names = Vec::new();
        for b in &self.model.bodies {
            for c in ["x", "y", "phi", "vx", "vy", "omega", "ax", "ay", "alpha"] {
                names.push(format!("{}.{c}", b.name));
            }
        }
        names.push(format!("{}.torque", self.driver_name));
        for c in ["ex", "ey", "delta", "fn", "ft"] {
            names.push(format!("{}.{c}", self.joint_name));
        }
        names
    }

    /// Output values at (t, y) in the order of [`Outputs::output_names`].
    fn outputs_into(&self, t: f64, y: &[f64], out: &mut Vec<f64>) -> Result<f64, FormulationError> {
        let o = self.outputs(t, y)?;
        out.clear();
        for i in 0..self.model.bodies.len() {
            let id = BodyId(i);
            let b = if id == self.crank.body {
                o.crank
            } else if id == self.coupler.body {
                o.coupler
            } else {
                o.rocker
            };
            out.extend_from_slice(&[b.x, b.y, b.phi, b.vx, b.vy, b.omega, b.ax, b.ay, b.alpha]);
        }
        out.push(o.crank_torque);
        out.extend_from_slice(&[
            o.eccentricity[0],
            o.eccentricity[1],
            o.delta,
            o.normal_force,
            o.friction_force,
        ]);
        // No constraints: θ3 and θ4 are the only coordinates.
        Ok(0.0)
    }
}

impl Formulation for ReducedLagrangian {
    /// [θ3, θ4, θ̇3, θ̇4, δ̇⁽⁻⁾].
    fn n_states(&self) -> usize {
        5
    }

    fn initial_state(&self) -> Vec<f64> {
        self.y0.to_vec()
    }

    fn t0(&self) -> f64 {
        self.t0
    }

    fn rhs(&self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), FormulationError> {
        let d = self.dynamics(t, y)?;
        let [_, _, w3, w4, _] = state(y);
        for (d, v) in dy.iter_mut().zip([w3, w4, d.alpha3, d.alpha4, 0.0]) {
            *d = v;
        }
        Ok(())
    }

    /// Analytic (contact laws by central differences of the scalar laws alone; see
    /// `reduced_lagrangian/jacobian.rs`): no RHS call.
    fn jacobian(
        &self,
        t: f64,
        y: &[f64],
        _f_y: &[f64],
        out: &mut [f64],
        _work: &mut [f64],
    ) -> Result<usize, FormulationError> {
        self.analytic_jacobian(t, y, out)?;
        Ok(0)
    }

    /// (θ3, θ4)' = (θ̇3, θ̇4), the next two states.
    fn second_order_positions(&self) -> usize {
        2
    }

    /// θ3, θ4, θ̇3, θ̇4 are error-controlled; the stored impact velocity δ̇⁽⁻⁾ (constant
    /// between events) is bookkeeping.
    fn error_controlled(&self, controlled: &mut [bool]) {
        if let Some(stored) = controlled.get_mut(4) {
            *stored = false;
        }
    }

    /// Event 0: the penetration δ (m) of the clearance joint; events 1–4, if the friction law
    /// has kinks: the slip velocity at them, v_t ∓ v0, v_t ∓ v1 (m/s), in contact only
    /// (`contact/kinks.rs`).
    fn n_events(&self) -> usize {
        1 + self.kink_events.map_or(0, |_| kinks::N_KINK_EVENTS)
    }

    fn events(&self, t: f64, y: &[f64], g: &mut [f64]) {
        let kin = self.kinematics(t, y);
        let Some((g0, rest)) = g.split_first_mut() else {
            return;
        };
        *g0 = kin.delta;
        if let Some(kinks) = self.kink_events {
            let [.., stored] = state(y);
            kinks::kink_events(kinks, stored, kin.tangential_velocity, rest);
        }
    }

    /// Rising δ (impact): stores δ̇⁽⁻⁾ = max(δ̇, 0) at the located instant in y for the whole
    /// contact; Falling δ (separation): clears it to 0. Both are logged; both change the force
    /// law, so both restart the integrator.
    fn apply_event(
        &mut self,
        t: f64,
        y: &mut [f64],
        index: usize,
        crossing: Crossing,
    ) -> EventResponse {
        if index != 0 {
            return EventResponse::Continue;
        }
        let kin = self.kinematics(t, y);
        let stored = match crossing {
            Crossing::Rising => {
                let impact = kin.delta_dot.max(0.0);
                self.memory.on_impact(t, impact);
                impact
            }
            Crossing::Falling => {
                self.memory.on_separation();
                0.0
            }
        };
        if let Some(slot) = y.get_mut(4) {
            *slot = stored;
        }
        EventResponse::Restart
    }

    /// The grazing guard while the joint is free ([`free_flight_max_step`] with |ė| and |ë| at
    /// (t, y)); unlimited in contact.
    fn max_step(&self, t: f64, y: &[f64]) -> f64 {
        // In contact the guard does not apply: skip the acceleration analysis (this is called
        // at every step).
        if super::contacts::in_contact(&self.kinematics(t, y)) {
            return f64::INFINITY;
        }
        match self.outputs(t, y) {
            Ok(o) => free_flight_max_step(
                o.delta,
                o.eccentricity_rate[0].hypot(o.eccentricity_rate[1]),
                o.eccentricity_acceleration[0].hypot(o.eccentricity_acceleration[1]),
                self.joint.clearance,
            ),
            // Not evaluable (the next rhs call reports why): no limit from here.
            _ => f64::INFINITY,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::load_str;

    /// Geometry and options of a test four-bar: the paper's Table 1 with the clearance joint at B,
    /// optionally with rotated body frames, shifted centres of mass, swapped bearing, a reversed
    /// driver joint and extra loads.
    #[derive(Clone)]
    struct Variant {
        /// Per body (crank, coupler, rocker): rotation ψ of the body frame (rad) and shift o of the
        /// centre of mass in the original body frame (m).
        frames: [(f64, [f64; 2]); 3],
        bearing_on_coupler: bool,
        friction: &'static str,
        reversed_driver: bool,
        extra: &'static str,
    }

    impl Default for Variant {
        fn default() -> Self {
            Variant {
                frames: [(0.0, [0.0, 0.0]); 3],
                bearing_on_coupler: true,
                friction: "law = \"ambrosio\"\ncoefficient = 0.1\nv0 = 1e-4\nv1 = 1e-3",
                reversed_driver: false,
                extra: "",
            }
        }
    }

    fn rot(phi: f64, s: [f64; 2]) -> [f64; 2] {
        rotate(phi.sin_cos(), s)
    }

    fn model_text(v: &Variant) -> String {
        // Reference bodies: name, mass, inertia, points, initial (x, y, phi).
        type Ref = (
            &'static str,
            f64,
            f64,
            [(&'static str, [f64; 2]); 2],
            [f64; 3],
        );
        let refs: [Ref; 3] = [
            (
                "crank",
                0.494,
                0.0046,
                [("O2", [-0.125, 0.0]), ("A", [0.125, 0.0])],
                [0.125, 0.0, 0.0],
            ),
            (
                "coupler",
                1.003,
                0.0545,
                [("A", [-0.375, 0.0]), ("B", [0.375, 0.0])],
                [0.55, 0.22, 0.64],
            ),
            (
                "rocker",
                0.74,
                0.0189,
                [("O4", [-0.225, 0.0]), ("B", [0.225, 0.0])],
                [0.83, 0.22, 1.45],
            ),
        ];
        let mut text = String::from(
            "[model]\nname = \"test\"\n[settings]\ngravity = [0.0, -9.81]\n[ground]\npoints = { O2 = [0.0, 0.0], O4 = [0.8, 0.0] }\n",
        );
        for ((name, mass, inertia, points, init), (psi, o)) in refs.iter().zip(v.frames) {
            // New body frame: origin at the shifted centre o, rotated by ψ: s' = R(−ψ)(s − o).
            let p: Vec<String> = points
                .iter()
                .map(|(n, s)| {
                    let q = rot(-psi, [s[0] - o[0], s[1] - o[1]]);
                    format!("{n} = [{:.17e}, {:.17e}]", q[0], q[1])
                })
                .collect();
            let shift = rot(init[2], o);
            text += &format!(
                "[[bodies]]\nname = \"{name}\"\nmass = {mass}\ninertia = {inertia}\npoints = {{ {} }}\ninitial = {{ x = {:.17e}, y = {:.17e}, phi = {:.17e} }}\n",
                p.join(", "),
                init[0] + shift[0],
                init[1] + shift[1],
                init[2] + psi
            );
        }
        let (a, b) = if v.reversed_driver {
            ("crank", "ground")
        } else {
            ("ground", "crank")
        };
        text += &format!(
            "[[joints]]\nname = \"O2\"\ntype = \"revolute\"\nbody_a = \"{a}\"\npoint_a = \"O2\"\nbody_b = \"{b}\"\npoint_b = \"O2\"\n"
        );
        text += "[[joints]]\nname = \"A\"\ntype = \"revolute\"\nbody_a = \"crank\"\npoint_a = \"A\"\nbody_b = \"coupler\"\npoint_b = \"A\"\n";
        let (bearing, journal) = if v.bearing_on_coupler {
            ("coupler", "rocker")
        } else {
            ("rocker", "coupler")
        };
        text += &format!(
            "[[joints]]\nname = \"B\"\ntype = \"clearance\"\nbearing = \"{bearing}\"\nbearing_point = \"B\"\njournal = \"{journal}\"\njournal_point = \"B\"\nclearance = 0.5e-3\njournal_radius = 0.01\n[joints.friction]\n{}\n",
            v.friction
        );
        text += "[[joints]]\nname = \"O4\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O4\"\nbody_b = \"rocker\"\npoint_b = \"O4\"\n";
        // The driver prescribes the crank's body angle φ; θ2 = 0 at t = 0 needs φ = ψ_crank.
        let (speed, angle) = if v.reversed_driver {
            (-250.0, -v.frames[0].0)
        } else {
            (250.0, v.frames[0].0)
        };
        text += &format!(
            "[[drivers]]\nname = \"motor\"\ntype = \"constant-speed\"\njoint = \"O2\"\nspeed_rpm = {speed}\ninitial_angle = {angle:.17e}\n"
        );
        text += v.extra;
        text
    }

    fn model(v: &Variant) -> Model {
        match load_str(&model_text(v), "test.toml", &[]) {
            Ok(m) => m,
            Err(e) => panic!("test model does not load: {e}\n{}", model_text(v)),
        }
    }

    fn reduced(v: &Variant) -> ReducedLagrangian {
        match ReducedLagrangian::new(&model(v)) {
            Ok(r) => r,
            Err(e) => panic!("reduced formulation refused the test model: {e}"),
        }
    }

    fn outputs(r: &ReducedLagrangian, t: f64, y: &[f64]) -> ReducedOutputs {
        match r.outputs(t, y) {
            Ok(o) => o,
            Err(e) => panic!("outputs at t = {t}, y = {y:?}: {e}"),
        }
    }

    use crate::formulation::test_rng::Lcg;

    /// A random state at a random time: the loop closed at eccentricity |e| = c + `delta` in a
    /// random direction, with random angular velocities (±40 rad/s, i.e. up to ~1.5× the
    /// crank speed of 26 rad/s), and no stored impact velocity.
    fn random_state(r: &ReducedLagrangian, rng: &mut Lcg, delta: f64) -> (f64, [f64; 5]) {
        let t = rng.range(0.0, 0.24);
        let angle = rng.range(0.0, std::f64::consts::TAU);
        let radius = r.joint.clearance + delta;
        let e0 = [radius * angle.cos(), radius * angle.sin()];
        let guess = [r.y0[0], r.y0[1]];
        // Walk the crank from θ2(0) to θ2(t) in small increments so Newton stays on the branch.
        let mut th = guess;
        for k in 1..=20 {
            let tk = t * f64::from(k) / 20.0;
            match r.assemble(tk, e0, [0.0, 0.0], th) {
                Ok(y) => th = [y[0], y[1]],
                Err(e) => panic!("cannot assemble at t = {tk}: {e}"),
            }
        }
        (
            t,
            [
                th[0],
                th[1],
                rng.range(-40.0, 40.0),
                rng.range(-40.0, 40.0),
                0.0,
            ],
        )
    }

    /// Masses and inertias by body order of the outputs (crank, coupler, rocker).
    fn mass_props(r: &ReducedLagrangian) -> [(f64, f64); 3] {
        [
            (r.crank.mass, r.crank.inertia),
            (r.coupler.mass, r.coupler.inertia),
            (r.rocker.mass, r.rocker.inertia),
        ]
    }

    /// dE/dt of T + U (gravity) from the body states, and the sum of the magnitudes of its terms
    /// (the scale for a relative tolerance).
    fn energy_rate(r: &ReducedLagrangian, o: &ReducedOutputs) -> (f64, f64) {
        let g = r.gravity;
        let mut rate = 0.0;
        let mut scale = 0.0;
        for ((m, i), b) in mass_props(r)
            .into_iter()
            .zip([o.crank, o.coupler, o.rocker])
        {
            let terms = [
                m * (b.vx * b.ax + b.vy * b.ay),
                i * b.omega * b.alpha,
                -m * (g[0] * b.vx + g[1] * b.vy),
            ];
            rate += terms.iter().sum::<f64>();
            scale += terms.iter().map(|x| x.abs()).sum::<f64>();
        }
        (rate, scale)
    }

    /// parameters.md check values: open assembly at θ2 = 0 with the journal centred,
    /// θ3 = 36.5795°, θ4 = 83.3294°, θ̇3 = θ̇4 = −11.899972 rad/s at 250 rpm. Tolerances: half a
    /// unit of the last quoted digit.
    #[test]
    fn initial_state_matches_reference_values() {
        let r = reduced(&Variant::default());
        let y = r.initial_state();
        assert!(
            (y[0].to_degrees() - 36.5795).abs() < 5e-5,
            "θ3 = {}°",
            y[0].to_degrees()
        );
        assert!(
            (y[1].to_degrees() - 83.3294).abs() < 5e-5,
            "θ4 = {}°",
            y[1].to_degrees()
        );
        assert!((y[2] + 11.899972).abs() < 5e-7, "θ̇3 = {}", y[2]);
        assert!((y[3] + 11.899972).abs() < 5e-7, "θ̇4 = {}", y[3]);
        assert_eq!(y[4], 0.0, "no impact recorded at t = 0");
        let o = outputs(&r, 0.0, &y);
        // θ3 = coupler.phi and θ4 = rocker.phi for the reference frames; e = 0, so free.
        assert_eq!(o.coupler.phi, y[0]);
        assert_eq!(o.rocker.phi, y[1]);
        assert!(
            o.eccentricity[0].hypot(o.eccentricity[1]) < 1e-12,
            "e = {:?}",
            o.eccentricity
        );
        assert!((o.delta + 0.5e-3).abs() < 1e-12, "δ = {}", o.delta);
        assert_eq!(r.link_lengths(), [0.8, 0.25, 0.75, 0.45]);
        assert!(!r.contact_memory().in_contact);
    }

    /// A prescribed initial eccentricity is honoured: r_J − r_B = e0 at t = 0 and ė = 0.
    #[test]
    fn initial_eccentricity_is_assembled() {
        let text = model_text(&Variant::default()).replace(
            "journal_radius = 0.01\n",
            "journal_radius = 0.01\ninitial_eccentricity = [3e-4, -2e-4]\n",
        );
        let m = load_str(&text, "e0.toml", &[]).map_err(|e| e.to_string());
        let r = ReducedLagrangian::new(&m.unwrap_or_else(|e| panic!("{e}")))
            .unwrap_or_else(|e| panic!("{e}"));
        let o = outputs(&r, 0.0, &r.initial_state());
        assert!(
            (o.eccentricity[0] - 3e-4).abs() < 1e-12 && (o.eccentricity[1] + 2e-4).abs() < 1e-12,
            "e = {:?}",
            o.eccentricity
        );
        assert!(
            o.eccentricity_rate[0].hypot(o.eccentricity_rate[1]) < 1e-12,
            "ė = {:?}",
            o.eccentricity_rate
        );
    }

    /// (a) Free journal (δ < 0): the power balance dE/dt = M2 θ̇2 at random states, with E = T + U
    /// from the body states. Tolerance 1e-9 of the sum of the magnitudes of the energy-rate terms
    /// (rounding in sums of ~10 products).
    #[test]
    fn free_flight_energy_rate_equals_crank_power() {
        for variant in [
            Variant::default(),
            Variant {
                frames: [
                    (0.3, [0.01, -0.02]),
                    (-1.1, [0.05, 0.03]),
                    (2.0, [-0.04, 0.01]),
                ],
                ..Variant::default()
            },
        ] {
            let r = reduced(&variant);
            let mut rng = Lcg(7);
            for _ in 0..20 {
                let delta = -rng.range(1e-5, 4.9e-4);
                let (t, y) = random_state(&r, &mut rng, delta);
                let o = outputs(&r, t, &y);
                assert!(
                    o.delta < 0.0 && o.normal_force == 0.0,
                    "free state: δ = {}",
                    o.delta
                );
                let (rate, scale) = energy_rate(&r, &o);
                let power = o.crank_torque * o.theta2_dot;
                assert!(
                    (rate - power).abs() <= 1e-9 * scale,
                    "t = {t}, y = {y:?}: dE/dt = {rate}, M2 ω = {power} (scale {scale})"
                );
            }
        }
    }

    /// (b) In contact: dE/dt = M2 θ̇2 + power of the contact forces (−F_N δ̇ + F_T v_t), at random
    /// contact states, with and without friction, for the bearing on either body, with shifted
    /// centres of mass. Same tolerance as (a), the contact power added to the scale.
    #[test]
    fn contact_energy_rate_equals_crank_and_contact_power() {
        let shifted = [
            (0.3, [0.01, -0.02]),
            (-1.1, [0.05, 0.03]),
            (2.0, [-0.04, 0.01]),
        ];
        let variants = [
            Variant::default(),
            Variant {
                friction: "law = \"none\"",
                ..Variant::default()
            },
            Variant {
                bearing_on_coupler: false,
                frames: shifted,
                ..Variant::default()
            },
        ];
        for variant in variants {
            let r = reduced(&variant);
            let mut rng = Lcg(11);
            let mut contacts = 0;
            for k in 0..30 {
                let delta = rng.range(1e-7, 2e-5);
                let (t, mut y) = random_state(&r, &mut rng, delta);
                // Alternate: a recorded impact, and a stage past an unlocated impact.
                if k % 2 == 0 {
                    y[4] = rng.range(0.01, 1.0);
                }
                let o = outputs(&r, t, &y);
                assert!(o.delta > 0.0, "contact state: δ = {}", o.delta);
                if o.normal_force > 0.0 {
                    contacts += 1;
                }
                let (rate, scale) = energy_rate(&r, &o);
                let power = o.crank_torque * o.theta2_dot + o.contact_power;
                let scale = scale + o.contact_power.abs() + (o.crank_torque * o.theta2_dot).abs();
                assert!(
                    (rate - power).abs() <= 1e-9 * scale,
                    "t = {t}, y = {y:?}: dE/dt = {rate}, M2 ω + P_c = {power} (F_N {}, scale {scale})",
                    o.normal_force
                );
            }
            assert!(contacts > 10, "enough states with a force: {contacts}");
        }
    }

    /// Loads: constant torques and point forces add their power: dE/dt = M2 θ̇2 + Σ τ ω + Σ F·v_P.
    #[test]
    fn loads_add_their_power() {
        let extra = "[[forces]]\nname = \"t3\"\ntype = \"torque\"\nbody = \"coupler\"\ntorque = 1.5\n\
                     [[forces]]\nname = \"t2\"\ntype = \"torque\"\nbody = \"crank\"\ntorque = -0.7\n\
                     [[forces]]\nname = \"p4\"\ntype = \"force\"\nbody = \"rocker\"\npoint = \"B\"\nforce = [3.0, -4.0]\n\
                     [[forces]]\nname = \"p3\"\ntype = \"force\"\nbody = \"coupler\"\npoint = \"A\"\nforce = [-2.0, 1.0]\n\
                     [[forces]]\nname = \"p2\"\ntype = \"force\"\nbody = \"crank\"\npoint = \"A\"\nforce = [0.5, 6.0]\n";
        let variant = Variant {
            frames: [
                (0.3, [0.01, -0.02]),
                (-1.1, [0.05, 0.03]),
                (2.0, [-0.04, 0.01]),
            ],
            extra,
            ..Variant::default()
        };
        let r = reduced(&variant);
        let m = r.model().clone();
        let mut rng = Lcg(3);
        for _ in 0..10 {
            let (t, y) = random_state(&r, &mut rng, -2e-4);
            let o = outputs(&r, t, &y);
            let (rate, scale) = energy_rate(&r, &o);
            let state_of = |name: &str| match name {
                "crank" => o.crank,
                "coupler" => o.coupler,
                _ => o.rocker,
            };
            let mut load_power = 0.0;
            for f in &m.forces {
                match f {
                    ForceElement::Torque { body, torque, .. } => {
                        load_power += torque * state_of(&m.body(*body).name).omega
                    }
                    ForceElement::PointForce { at, force, .. } => {
                        let Frame::Body(id) = at.frame else { continue };
                        let b = state_of(&m.body(id).name);
                        let arm = rot(b.phi, at.local);
                        let v = [b.vx - b.omega * arm[1], b.vy + b.omega * arm[0]];
                        load_power += dot(*force, v);
                    }
                    _ => {}
                }
            }
            let power = o.crank_torque * o.theta2_dot + load_power;
            assert!(
                (rate - power).abs() <= 1e-9 * (scale + load_power.abs()),
                "t = {t}: dE/dt = {rate}, M2 ω + loads = {power}"
            );
        }
    }

    /// (c) The printed equations 23–25, implemented as printed with the corrections (ψ = α + φ
    /// with tan φ = −c_f c_d sign(X), X = ω_B R_B − ω_J R_J − r α̇ from the corrected eq. 6;
    /// α from eq. 15 read as atan2; r, ṙ, α̇ from eqs. 14–16) give the same θ̈3, θ̈4 and M2 as the
    /// vector form at random contact states of the reference geometry. Tolerance 1e-9 of the
    /// largest term of each equation: the two forms compute δ = |e| − c from coordinates of
    /// ~0.5 m rounded differently (~1e-16 m); with δ ≥ 1e-6 m that is ≤ 3e-10 relative in F_N.
    /// In the c_d ramp the slip-velocity rounding is added (see the comment in the loop).
    #[test]
    fn printed_equations_agree_with_derivation() {
        let (l1, l2, l3, l4) = (0.8, 0.25, 0.75, 0.45);
        let (m2, m3, m4) = (0.494, 1.003, 0.74);
        let (i3, i4) = (0.0545, 0.0189);
        let g = 9.81;
        let (c, rj) = (0.5e-3, 0.01);
        let rb = rj + c;
        let (cf, v0, v1) = (0.1, 1e-4, 1e-3);
        let r = reduced(&Variant::default());
        let k = r.joint.law.stiffness;
        let chi = 0.75 * (1.0 - 0.81);
        let mut rng = Lcg(5);
        let mut regions = [0usize; 3];
        for n in 0..40 {
            let delta = rng.range(1e-6, 2e-5);
            let (t, mut y) = random_state(&r, &mut rng, delta);
            // Every fourth state: slip velocity near zero, to reach the c_d ramp and the dead
            // zone. v_t is affine in θ̇4: solve for the θ̇4 that gives the target.
            if n % 4 == 0 {
                let target = rng.range(-2e-3, 2e-3);
                let v_a = outputs(&r, t, &y).tangential_velocity;
                let mut y1 = y;
                y1[3] += 1.0;
                let slope = outputs(&r, t, &y1).tangential_velocity - v_a;
                y[3] += (target - v_a) / slope;
            }
            let impact = rng.range(0.05, 1.0);
            y[4] = impact;
            let o = outputs(&r, t, &y);
            let (t2, t3, t4) = (o.theta2, y[0], y[1]);
            let (w, w3, w4) = (o.theta2_dot, y[2], y[3]);
            // Eqs. 14–16.
            let x = l1 - l2 * t2.cos() - l3 * t3.cos() + l4 * t4.cos();
            let yy = l4 * t4.sin() - l2 * t2.sin() - l3 * t3.sin();
            let rr = x.hypot(yy);
            let alpha = yy.atan2(x);
            let xd = l2 * w * t2.sin() + l3 * w3 * t3.sin() - l4 * w4 * t4.sin();
            let yd = l4 * w4 * t4.cos() - l2 * w * t2.cos() - l3 * w3 * t3.cos();
            let rdot = alpha.cos() * xd + alpha.sin() * yd;
            let alpha_dot = (-alpha.sin() * xd + alpha.cos() * yd) / rr;
            // Eq. 7 (clamped) and eqs. 10–13.
            let delta = rr - c;
            let f_n = (k * delta.powf(1.5) * (1.0 + chi * rdot / impact)).max(0.0);
            let slip = w3 * rb - w4 * rj - rr * alpha_dot;
            let cd = if slip.abs() < v0 {
                0.0
            } else if slip.abs() > v1 {
                1.0
            } else {
                (slip.abs() - v0) / (v1 - v0)
            };
            regions[if cd == 0.0 {
                0
            } else if cd == 1.0 {
                2
            } else {
                1
            }] += 1;
            let phi = (-cf * cd * slip.signum()).atan();
            let qc = f_n * (1.0 + cf * cf * cd * cd).sqrt();
            let psi = alpha + phi;
            // Eqs. 24, 25, 23.
            let terms3 = [
                l3 * qc * (psi - t3).sin(),
                rb * qc * (psi - alpha).sin(),
                0.5 * m3 * l2 * l3 * w * w * (t2 - t3).sin(),
                -0.5 * m3 * g * l3 * t3.cos(),
            ];
            let th3dd = terms3.iter().sum::<f64>() / (i3 + 0.25 * m3 * l3 * l3);
            let terms4 = [
                l4 * qc * (t4 - psi).sin(),
                rj * qc * (alpha - psi).sin(),
                -0.5 * m4 * g * l4 * t4.cos(),
            ];
            let th4dd = terms4.iter().sum::<f64>() / (i4 + 0.25 * m4 * l4 * l4);
            let terms2 = [
                0.5 * m3 * l2 * l3 * th3dd * (t2 - t3).cos(),
                0.5 * m3 * l2 * l3 * w3 * w3 * (t2 - t3).sin(),
                0.5 * m2 * g * l2 * t2.cos(),
                m3 * g * l2 * t2.cos(),
                l2 * qc * (t2 - psi).sin(),
            ];
            let m2_printed: f64 = terms2.iter().sum();
            let scale = |terms: &[f64]| terms.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            // In the c_d ramp F_T depends on v_t with slope c_f F_N/(v1 − v0), and v_t carries a
            // rounding error |ė| · ~1e-15 m / |e|: the direction n of e, a difference of
            // coordinates of ~0.5 m, is known to ~1e-16 m/|e|, and v_t contains ė·t.
            let e_rate = o.eccentricity_rate[0].hypot(o.eccentricity_rate[1]);
            let slip_error = if cd > 0.0 && cd < 1.0 {
                cf * f_n * e_rate * 1e-15 / (rr * (v1 - v0))
            } else {
                0.0
            };
            let (p3, p4) = (i3 + 0.25 * m3 * l3 * l3, i4 + 0.25 * m4 * l4 * l4);
            let tol3 = 1e-9 * scale(&terms3) / p3 + (l3 + rb) * slip_error / p3;
            let tol4 = 1e-9 * scale(&terms4) / p4 + (l4 + rj) * slip_error / p4;
            let tol2 = 1e-9 * scale(&terms2) + l2 * slip_error + 0.5 * m3 * l2 * l3 * tol3;
            assert!(
                (o.normal_force - f_n).abs() <= 1e-9 * f_n.max(1.0),
                "F_N {} vs {f_n}",
                o.normal_force
            );
            assert!(
                (o.theta3_ddot - th3dd).abs() <= tol3,
                "state {n}: θ̈3 = {}, printed {th3dd}",
                o.theta3_ddot
            );
            assert!(
                (o.theta4_ddot - th4dd).abs() <= tol4,
                "state {n}: θ̈4 = {}, printed {th4dd}",
                o.theta4_ddot
            );
            assert!(
                (o.crank_torque - m2_printed).abs() <= tol2,
                "state {n}: M2 = {}, printed {m2_printed}",
                o.crank_torque
            );
        }
        assert!(
            regions.iter().all(|&n| n > 0),
            "all three c_d regions visited: {regions:?}"
        );
    }

    /// Body states are consistent with the model's body-frame points: the ideal joints hold
    /// (positions and velocities), and journal − bearing point = e. Rotated frames and shifted
    /// centres of mass; bearing on either body. Tolerances: 1e-12 m, 1e-10 m/s (rounding).
    #[test]
    fn body_states_respect_the_joints() {
        let frames = [
            (0.3, [0.01, -0.02]),
            (-1.1, [0.05, 0.03]),
            (2.0, [-0.04, 0.01]),
        ];
        for bearing_on_coupler in [true, false] {
            let r = reduced(&Variant {
                frames,
                bearing_on_coupler,
                ..Variant::default()
            });
            let m = r.model().clone();
            let mut rng = Lcg(17);
            for _ in 0..10 {
                let delta = rng.range(-4e-4, 1e-5);
                let (t, y) = random_state(&r, &mut rng, delta);
                let o = outputs(&r, t, &y);
                let point = |body: &str, p: &str| {
                    let b = match body {
                        "crank" => o.crank,
                        "coupler" => o.coupler,
                        _ => o.rocker,
                    };
                    let id = m.body_id(body).unwrap_or_else(|| panic!("{body}"));
                    let s = m
                        .body(id)
                        .points
                        .iter()
                        .find(|(n, _)| n == p)
                        .map(|(_, s)| *s)
                        .unwrap_or_else(|| panic!("{p}"));
                    let arm = rot(b.phi, s);
                    (
                        [b.x + arm[0], b.y + arm[1]],
                        [b.vx - b.omega * arm[1], b.vy + b.omega * arm[0]],
                    )
                };
                let close = |a: [f64; 2], b: [f64; 2], tol: f64, what: &str| {
                    assert!(
                        (a[0] - b[0]).abs() < tol && (a[1] - b[1]).abs() < tol,
                        "{what}: {a:?} vs {b:?}"
                    );
                };
                close(point("crank", "O2").0, [0.0, 0.0], 1e-12, "O2");
                close(point("crank", "O2").1, [0.0, 0.0], 1e-10, "O2 velocity");
                close(point("rocker", "O4").0, [0.8, 0.0], 1e-12, "O4");
                close(point("rocker", "O4").1, [0.0, 0.0], 1e-10, "O4 velocity");
                close(point("crank", "A").0, point("coupler", "A").0, 1e-12, "A");
                close(
                    point("crank", "A").1,
                    point("coupler", "A").1,
                    1e-10,
                    "A velocity",
                );
                let (journal, bearing) = if bearing_on_coupler {
                    ("rocker", "coupler")
                } else {
                    ("coupler", "rocker")
                };
                let (pj, vj) = point(journal, "B");
                let (pb, vb) = point(bearing, "B");
                close([pj[0] - pb[0], pj[1] - pb[1]], o.eccentricity, 1e-12, "e");
                close(
                    [vj[0] - vb[0], vj[1] - vb[1]],
                    o.eccentricity_rate,
                    1e-10,
                    "ė",
                );
            }
        }
    }

    /// Body accelerations against central differences of the body velocities along the flow
    /// y ± h f(y) (d/dt v = ∂v/∂t + ∂v/∂y · f). Tolerance 1e-6 relative + 1e-6 absolute: O(h²)
    /// with h = 1e-6 s and rounding ~1e-16/1e-6.
    #[test]
    fn body_accelerations_match_finite_differences() {
        let r = reduced(&Variant {
            frames: [
                (0.3, [0.01, -0.02]),
                (-1.1, [0.05, 0.03]),
                (2.0, [-0.04, 0.01]),
            ],
            ..Variant::default()
        });
        let mut rng = Lcg(23);
        let h = 1e-6;
        for _ in 0..10 {
            let (t, y) = random_state(&r, &mut rng, -1e-4);
            let o = outputs(&r, t, &y);
            let f = [
                o.theta3_dot,
                o.theta4_dot,
                o.theta3_ddot,
                o.theta4_ddot,
                0.0,
            ];
            let yp: Vec<f64> = y.iter().zip(f).map(|(a, b)| a + h * b).collect();
            let ym: Vec<f64> = y.iter().zip(f).map(|(a, b)| a - h * b).collect();
            let (op, om) = (outputs(&r, t + h, &yp), outputs(&r, t - h, &ym));
            for (name, b, bp, bm) in [
                ("crank", o.crank, op.crank, om.crank),
                ("coupler", o.coupler, op.coupler, om.coupler),
                ("rocker", o.rocker, op.rocker, om.rocker),
            ] {
                for (a, fd) in [
                    (b.ax, (bp.vx - bm.vx) / (2.0 * h)),
                    (b.ay, (bp.vy - bm.vy) / (2.0 * h)),
                    (b.alpha, (bp.omega - bm.omega) / (2.0 * h)),
                    (b.vx, (bp.x - bm.x) / (2.0 * h)),
                    (b.vy, (bp.y - bm.y) / (2.0 * h)),
                    (b.omega, (bp.phi - bm.phi) / (2.0 * h)),
                ] {
                    assert!(
                        (a - fd).abs() < 1e-6 * a.abs() + 1e-6,
                        "{name}: {a} vs finite difference {fd}"
                    );
                }
            }
            let ed = o.eccentricity_acceleration;
            let fd = [
                (op.eccentricity_rate[0] - om.eccentricity_rate[0]) / (2.0 * h),
                (op.eccentricity_rate[1] - om.eccentricity_rate[1]) / (2.0 * h),
            ];
            assert!(
                (ed[0] - fd[0]).abs() < 1e-6 * ed[0].abs() + 1e-6
                    && (ed[1] - fd[1]).abs() < 1e-6 * ed[1].abs() + 1e-6,
                "ë {ed:?} vs {fd:?}"
            );
        }
    }

    /// Body frames are a matter of description: rotating every body frame (centres of mass kept)
    /// changes φ by the rotation but nothing in θ̈3, θ̈4, M2, F_N. Reversing the driver joint
    /// (ground as its second body, negative speed) changes nothing either. Without friction, the
    /// side that carries the bearing does not matter (the normal force passes through both
    /// centres). Tolerance 1e-9 relative: the rotated point coordinates round differently, which
    /// moves the centres by ~1e-16 m; δ = |e| − c cancels down to 1e-6 m in these states, so F_N
    /// (∝ δ^1.5) carries up to ~1.5 · 2e-16/1e-6 = 3e-10 relative rounding.
    #[test]
    fn invariant_to_frames_driver_orientation_and_frictionless_bearing_side() {
        let base = Variant {
            friction: "law = \"none\"",
            ..Variant::default()
        };
        let r0 = reduced(&base);
        let others = [
            Variant {
                frames: [(0.7, [0.0, 0.0]), (-2.5, [0.0, 0.0]), (1.2, [0.0, 0.0])],
                ..base.clone()
            },
            Variant {
                reversed_driver: true,
                ..base.clone()
            },
            Variant {
                bearing_on_coupler: false,
                ..base.clone()
            },
        ];
        let mut rng = Lcg(29);
        let states: Vec<(f64, [f64; 5])> = (0..10)
            .map(|k| {
                let delta = if k % 2 == 0 {
                    rng.range(1e-6, 1e-5)
                } else {
                    -1e-4
                };
                let (t, mut y) = random_state(&r0, &mut rng, delta);
                y[4] = rng.range(0.05, 1.0);
                (t, y)
            })
            .collect();
        for variant in others {
            let r = reduced(&variant);
            for (t, y) in &states {
                let (a, b) = (outputs(&r0, *t, y), outputs(&r, *t, y));
                for (x, z, what) in [
                    (a.theta3_ddot, b.theta3_ddot, "θ̈3"),
                    (a.theta4_ddot, b.theta4_ddot, "θ̈4"),
                    (a.crank_torque, b.crank_torque, "M2"),
                    (a.normal_force, b.normal_force, "F_N"),
                    (a.delta, b.delta, "δ"),
                ] {
                    assert!(
                        (x - z).abs() <= 1e-9 * x.abs().max(1.0),
                        "{what}: {x} vs {z}, variant: bearing on coupler {}, reversed driver {}, frames {:?}",
                        variant.bearing_on_coupler,
                        variant.reversed_driver,
                        variant.frames
                    );
                }
            }
        }
    }

    /// The analytic Jacobian against central differences of the whole right-hand side, free and
    /// in contact, with and without a stored impact velocity, on the paper's four-bar, with the
    /// bearing on the rocker, and with shifted centres of mass and point loads.
    #[test]
    fn analytic_jacobian_matches_central_differences() {
        let extra = "[[forces]]\nname = \"p4\"\ntype = \"force\"\nbody = \"rocker\"\npoint = \"B\"\nforce = [3.0, -4.0]\n\
                     [[forces]]\nname = \"p3\"\ntype = \"force\"\nbody = \"coupler\"\npoint = \"A\"\nforce = [-2.0, 1.0]\n";
        let variants = [
            Variant::default(),
            Variant {
                bearing_on_coupler: false,
                ..Variant::default()
            },
            Variant {
                frames: [
                    (0.3, [0.01, -0.02]),
                    (-1.1, [0.05, 0.03]),
                    (2.0, [-0.04, 0.01]),
                ],
                extra,
                ..Variant::default()
            },
        ];
        let mut rng = Lcg(41);
        for (v, variant) in variants.iter().enumerate() {
            let r = reduced(variant);
            for (delta, stored) in [(-2e-4, 0.0), (1e-5, 0.0), (1e-5, 0.3), (3e-5, 0.05)] {
                let (t, mut y) = random_state(&r, &mut rng, delta);
                y[4] = stored;
                let mut exact = [0.0; 25];
                let calls = r.jacobian(t, &y, &[0.0; 5], &mut exact, &mut [0.0; 10]);
                assert_eq!(calls.ok(), Some(0), "variant {v}: analytic, no RHS call");
                // Central differences with h_j = 1e-7·max(|y_j|, 1): the truncation error is
                // (h/δ)²·O(1) of an entry; in contact an angle step of 1e-7 rad moves e by
                // ≤ 1e-7 × L (0.5 m) = 5e-8 m against δ ≥ 1e-5 m, i.e. ≤ 2.5e-5 for the δ^1.5
                // law, and rounding u·|f|/h ≈ 1e-16·1e5/1e-7 = 1e-4 rad/s² against entries of
                // 1e2 (free) to 1e9 (contact). Hence 1e-3 of the row's largest entry (a margin
                // of 40 on the truncation) plus 1e-2 absolute (20× the rounding).
                let mut row_scale = [0.0_f64; 5];
                let mut numeric = [0.0; 25];
                for j in 0..5 {
                    let h = 1e-7 * y[j].abs().max(1.0);
                    let (mut up, mut down) = (y, y);
                    up[j] += h;
                    down[j] -= h;
                    let (mut fu, mut fd) = ([0.0; 5], [0.0; 5]);
                    let ok = r.rhs(t, &up, &mut fu).and(r.rhs(t, &down, &mut fd));
                    assert!(ok.is_ok(), "variant {v}: rhs {ok:?}");
                    for i in 0..5 {
                        numeric[i * 5 + j] = (fu[i] - fd[i]) / (2.0 * h);
                        row_scale[i] = row_scale[i].max(numeric[i * 5 + j].abs());
                    }
                }
                for k in 0..25 {
                    // At δ̇⁽⁻⁾ = 0 (none stored) the law switches to the current δ̇ and any
                    // perturbation stores one: no derivative to compare in that column.
                    if stored == 0.0 && k % 5 == 4 {
                        continue;
                    }
                    let (a, b) = (exact[k], numeric[k]);
                    let bound = 1e-3 * row_scale[k / 5] + 1e-2;
                    assert!(
                        (a - b).abs() <= bound,
                        "variant {v}, δ = {delta:e}, stored {stored}: J[{}][{}] analytic {a:e} vs central difference {b:e} (bound {bound:e})",
                        k / 5,
                        k % 5
                    );
                }
            }
        }
    }

    /// With Ambrósio friction, events 1–4 are v_t ∓ v0, v_t ∓ v1 while a contact with a stored
    /// δ̇⁽⁻⁾ is open and constant (no crossing) otherwise; they change nothing in the state.
    /// Without friction, or switched off, δ is the only event function.
    #[test]
    fn friction_kinks_are_events_in_contact() {
        let r = reduced(&Variant::default());
        assert_eq!(r.n_events(), 5);
        assert_eq!(r.clone().friction_kink_events(false).n_events(), 1);
        let frictionless = Variant {
            friction: "law = \"none\"",
            ..Variant::default()
        };
        assert_eq!(reduced(&frictionless).n_events(), 1);
        let mut rng = Lcg(17);
        let (t, mut y) = random_state(&r, &mut rng, 1e-6);
        let v_t = outputs(&r, t, &y).tangential_velocity;
        let mut g = [0.0; 5];
        r.events(t, &y, &mut g);
        assert_eq!(g[1..], [1.0; 4], "no stored δ̇⁽⁻⁾: kinks inactive");
        y[4] = 0.05;
        r.events(t, &y, &mut g);
        assert!(g[0] > 0.0, "in contact: δ = {}", g[0]);
        assert_eq!(g[1..], [v_t - 1e-4, v_t + 1e-4, v_t - 1e-3, v_t + 1e-3]);
        let mut m = r.clone();
        for index in 1..5 {
            let mut yy = y;
            for crossing in [Crossing::Rising, Crossing::Falling] {
                assert_eq!(
                    m.apply_event(t, &mut yy, index, crossing),
                    EventResponse::Continue
                );
                assert_eq!(yy, y, "event {index} changes nothing");
            }
        }
        assert!(m.contact_memory().impacts.is_empty());
    }

    /// Events: g = δ; a Rising crossing stores δ̇⁽⁻⁾ = max(δ̇, 0) in y and restarts; a Falling one
    /// clears it. The grazing guard limits the step while free and not in contact.
    #[test]
    fn events_and_grazing_guard() {
        let mut r = reduced(&Variant::default());
        let mut rng = Lcg(31);
        let (t, y) = random_state(&r, &mut rng, 0.0);
        let mut g = [1.0];
        r.events(t, &y, &mut g);
        assert!(g[0].abs() < 1e-12, "δ at the assembled contact: {}", g[0]);
        let mut yy = y;
        let o = outputs(&r, t, &y);
        assert_eq!(
            r.apply_event(t, &mut yy, 0, Crossing::Rising),
            EventResponse::Restart
        );
        assert_eq!(yy[4], o.delta_dot.max(0.0), "stored δ̇⁽⁻⁾");
        assert_eq!(yy[..4], y[..4], "only δ̇⁽⁻⁾ changes");
        assert_eq!(outputs(&r, t, &yy).impact_velocity, yy[4]);
        assert_eq!(r.contact_memory().impact_velocity, yy[4]);
        assert_eq!(r.contact_memory().impacts, vec![t]);
        assert!(r.contact_memory().in_contact);
        assert_eq!(
            r.apply_event(t, &mut yy, 0, Crossing::Falling),
            EventResponse::Restart
        );
        assert_eq!(yy[4], 0.0, "cleared at separation");
        assert!(!r.contact_memory().in_contact);
        assert_eq!(
            r.apply_event(t, &mut yy, 3, Crossing::Falling),
            EventResponse::Continue
        );
        r.reset_contact_memory();
        assert!(r.contact_memory().impacts.is_empty());

        let (t, y) = random_state(&r, &mut rng, -1e-4);
        let h = r.max_step(t, &y);
        let o = outputs(&r, t, &y);
        let v = o.eccentricity_rate[0].hypot(o.eccentricity_rate[1]);
        assert!(h.is_finite() && h > 0.0, "free: h = {h}");
        assert!(
            v * h <= 0.5e-4 * (1.0 + 1e-12) || h <= 2.0 * 1e-3 * 0.5e-3 / v,
            "h = {h}, |ė| = {v}"
        );
        let (t, y) = random_state(&r, &mut rng, 1e-6);
        assert_eq!(r.max_step(t, &y), f64::INFINITY, "in contact");
    }

    /// rhs writes [θ̇3, θ̇4, θ̈3, θ̈4, 0]; a non-finite state is an error, not a panic.
    #[test]
    fn rhs_layout_and_bad_state() {
        let r = reduced(&Variant::default());
        let y = r.initial_state();
        let mut dy = [1.0; 5];
        r.rhs(0.0, &y, &mut dy).unwrap_or_else(|e| panic!("{e}"));
        let o = outputs(&r, 0.0, &y);
        assert_eq!(
            dy,
            [
                o.theta3_dot,
                o.theta4_dot,
                o.theta3_ddot,
                o.theta4_ddot,
                0.0
            ]
        );
        let names = r.output_names();
        let mut out = Vec::new();
        r.outputs_into(0.0, &y, &mut out)
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(names.len(), out.len());
        assert_eq!(
            names[9..12],
            [
                "coupler.x".to_string(),
                "coupler.y".into(),
                "coupler.phi".into()
            ]
        );
        assert_eq!(
            names[27..],
            [
                "motor.torque".to_string(),
                "B.ex".into(),
                "B.ey".into(),
                "B.delta".into(),
                "B.fn".into(),
                "B.ft".into()
            ]
        );
        let nan = [f64::NAN, 0.0, 0.0, 0.0, 0.0];
        let err = r.rhs(0.0, &nan, &mut dy).map_err(|e| e.to_string());
        assert_eq!(
            err,
            Err("non-finite acceleration of body \"coupler\" at t = 0.000000000 s".to_string())
        );
    }

    fn error_text(text: &str) -> String {
        let m = load_str(text, "bad.toml", &[])
            .unwrap_or_else(|e| panic!("test model does not load: {e}"));
        match ReducedLagrangian::new(&m) {
            Ok(_) => panic!("accepted an unsupported model"),
            Err(e) => e.to_string(),
        }
    }

    /// (d) Unsupported models are refused with a message naming what is missing or different.
    #[test]
    fn unsupported_models_are_refused_with_reasons() {
        let good = model_text(&Variant::default());
        let ideal = good.replace(
            "type = \"clearance\"\nbearing = \"coupler\"\nbearing_point = \"B\"\njournal = \"rocker\"\njournal_point = \"B\"\nclearance = 0.5e-3\njournal_radius = 0.01\n[joints.friction]\nlaw = \"ambrosio\"\ncoefficient = 0.1\nv0 = 1e-4\nv1 = 1e-3\n",
            "type = \"revolute\"\nbody_a = \"coupler\"\npoint_a = \"B\"\nbody_b = \"rocker\"\npoint_b = \"B\"\n",
        );
        assert_ne!(ideal, good, "replacement applied");
        assert_eq!(
            error_text(&ideal),
            "reduced formulation: needs exactly one clearance joint, between the coupler and the rocker; the model has 0"
        );
        let pendulum = "[model]\nname = \"p\"\n[ground]\npoints = { O = [0.0, 0.0] }\n[[bodies]]\nname = \"rod\"\nmass = 1.0\ninertia = 0.1\npoints = { O = [-0.5, 0.0] }\ninitial = { x = 0.5, y = 0.0, phi = 0.0 }\n[[joints]]\nname = \"O\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O\"\nbody_b = \"rod\"\npoint_b = \"O\"\n";
        assert_eq!(
            error_text(pendulum),
            "reduced formulation: needs exactly 3 moving bodies (crank, coupler, rocker); the model has 1"
        );
        let no_driver = good
            .split("[[drivers]]")
            .next()
            .unwrap_or_default()
            .to_string();
        assert_eq!(
            error_text(&no_driver),
            "reduced formulation: needs exactly one driver, on the revolute joint between ground and the crank; the model has 0"
        );
        let driver_on_a = good.replace("joint = \"O2\"", "joint = \"A\"");
        assert_eq!(
            error_text(&driver_on_a),
            "reduced formulation: driver \"motor\" drives joint \"A\" between \"crank\" and \"coupler\"; it must drive the joint between ground and the crank"
        );
        // Clearance at A (crank–coupler) and an ideal B.
        let clearance_at_a = ideal
            .replace(
                "name = \"A\"\ntype = \"revolute\"\nbody_a = \"crank\"\npoint_a = \"A\"\nbody_b = \"coupler\"\npoint_b = \"A\"\n",
                "name = \"A\"\ntype = \"clearance\"\nbearing = \"crank\"\nbearing_point = \"A\"\njournal = \"coupler\"\njournal_point = \"A\"\nclearance = 0.5e-3\njournal_radius = 0.01\n",
            );
        assert_eq!(
            error_text(&clearance_at_a),
            "reduced formulation: needs an ideal revolute joint between the crank \"crank\" and the coupler; found none (the clearance joint must be the coupler–rocker joint)"
        );
        // Clearance at O4 (rocker–ground) and an ideal B.
        let clearance_at_o4 = ideal.replace(
            "name = \"O4\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O4\"\nbody_b = \"rocker\"\npoint_b = \"O4\"\n",
            "name = \"O4\"\ntype = \"clearance\"\nbearing = \"ground\"\nbearing_point = \"O4\"\njournal = \"rocker\"\njournal_point = \"O4\"\nclearance = 0.5e-3\njournal_radius = 0.01\n",
        );
        assert_eq!(
            error_text(&clearance_at_o4),
            "reduced formulation: clearance joint \"O4\" connects \"ground\" and \"rocker\"; it must connect the coupler \"coupler\" and the rocker \"rocker\""
        );
        let extra_joint = format!(
            "{good}[[joints]]\nname = \"extra\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O2\"\nbody_b = \"coupler\"\npoint_b = \"A\"\n"
        );
        assert_eq!(
            error_text(&extra_joint),
            "reduced formulation: joint \"extra\" (revolute between \"ground\" and \"coupler\") is not part of the four-bar ground–crank–coupler–rocker–ground; no other joints are allowed"
        );
        let no_o4 = good.replace(
            "[[joints]]\nname = \"O4\"\ntype = \"revolute\"\nbody_a = \"ground\"\npoint_a = \"O4\"\nbody_b = \"rocker\"\npoint_b = \"O4\"\n",
            "",
        );
        assert_eq!(
            error_text(&no_o4),
            "reduced formulation: needs an ideal revolute joint between the rocker \"rocker\" and ground; found none"
        );
        let spring = format!(
            "{good}[[forces]]\nname = \"s\"\ntype = \"spring-damper\"\nbody_a = \"ground\"\npoint_a = \"O4\"\nbody_b = \"coupler\"\npoint_b = \"A\"\nstiffness = 10.0\nfree_length = 0.5\n"
        );
        assert_eq!(
            error_text(&spring),
            "reduced formulation: force \"s\" is a spring-damper; only gravity, constant torques and constant point forces are supported"
        );
        let degenerate: String = good
            .lines()
            .map(|l| {
                if l.starts_with("points = { O4 =") {
                    "points = { O4 = [0.0, 0.0], B = [0.0, 0.0] }"
                } else {
                    l
                }
            })
            .collect::<Vec<_>>()
            .join("\n");
        assert_eq!(
            error_text(&degenerate),
            "reduced formulation: body \"rocker\": its joint points \"O4\" and \"B\" coincide, so its link angle is undefined"
        );
        // Link lengths that cannot close the loop: the assembly error names the clearance joint
        // (matched on the variant; its wording belongs to `FormulationError`).
        let unclosable = good.replace("O4 = [0.8, 0.0]", "O4 = [3.0, 0.0]");
        let m = load_str(&unclosable, "bad.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
        match ReducedLagrangian::new(&m) {
            Err(FormulationError::Unassemblable {
                joint, residual, ..
            }) => {
                assert_eq!(joint, "B");
                assert!(
                    residual > 1.0,
                    "O4 moved 2.2 m out of reach: residual {residual}"
                );
            }
            Err(e) => panic!("expected Unassemblable, got {e}"),
            Ok(_) => panic!("assembled an unclosable loop"),
        }
    }
}
