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

use super::{Crossing, EventResponse, Formulation, FormulationError, NoStepHooks, Outputs};
use crate::contact::{
    CentreMotion, ClearanceJoint, ContactForces, ContactKinematics, ContactMemory,
    free_flight_max_step, impact_velocity, kinks,
};
use crate::mechanics::planar::{cross, dot, perp, rotate};
use crate::model::{Anchor, BodyId, ForceElement, Frame, Model};

mod jacobian;
mod recognise;

use recognise::find_four_bar;

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
    /// 1/(I + m |ρ_G|²), the inverse moment of inertia about the first joint point (1/(kg·m²)),
    /// kept: the right-hand side multiplies by it at every call (a division there was on the
    /// critical path of every evaluation).
    inverse_pivot: f64,
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
            inverse_pivot: 0.0,
            torque: 0.0,
            loads: Vec::new(),
        };
        link.inverse_pivot = 1.0 / (link.inertia + link.mass * dot(link.com, link.com));
        Ok(link)
    }

    /// 1/(I + m |ρ_G|²) (1/(kg·m²)), the inverse moment of inertia about the link's first joint
    /// point.
    fn inverse_pivot_inertia(&self) -> f64 {
        self.inverse_pivot
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
    /// functions 1–4 while in contact, so that Radau5 and the explicit pairs end their steps at
    /// them (`contact/kinks.rs`); off, δ is the only event function. A model without
    /// friction has none either way. [`crate::simulation::Simulation`] switches them off for
    /// IDA (its steps do not change at events) and for the explicit pairs at rtol above
    /// [`crate::simulation::EXPLICIT_CUT_MAX_RTOL`].
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
        let (s3, c3) = crate::trig::sin_cos(th[0]);
        let (s4, c4) = crate::trig::sin_cos(th[1]);
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
        // One by one, not through `array::map`, whose closure the compiler kept out of line.
        let sc = [
            crate::trig::sin_cos(angles[0]),
            crate::trig::sin_cos(angles[1]),
            crate::trig::sin_cos(angles[2]),
        ];
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
        let alpha3 = q3 * cp.inverse_pivot_inertia();
        // Rocker: moments about the fixed pivot O4.
        let q4 = cross(a4, weight(rk.mass)) + cross(c.d[2], f4) + m4c + rk.torque + load4;
        let alpha4 = q4 * rk.inverse_pivot_inertia();
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

/// Nothing to check or correct at step ends: minimal coordinates have no constraints to drift.
impl NoStepHooks for ReducedLagrangian {}

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

    /// θ3 and θ4.
    fn angular_states(&self, angular: &mut [bool]) {
        for a in angular.iter_mut().take(2) {
            *a = true;
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
mod tests;
