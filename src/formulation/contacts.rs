//! Clearance joints in absolute coordinates: where each joint's bearing and journal centres are,
//! and how its contact forces enter the generalised force vector Q of the DAE.
//!
//! A clearance joint adds no constraint row. Its discrete state — the impact velocity δ̇⁽⁻⁾ of
//! the current contact — is kept in the state vector as one extra component per joint with zero
//! derivative (0 = no impact recorded), changed only at located events. So the equations stay a
//! pure function of (t, y): every sample, restart and clone sees the δ̇⁽⁻⁾ that was valid at its
//! time, and the same run gives the same numbers.
//!
//! The corners of prismatic-clearance joints are contact sites too, four per joint
//! ([`CornerSite`]), numbered after the revolute joints: site k < [`ContactSites::sites`]`.len()`
//! is a revolute joint, the rest corners in [`ContactSites::corners`] order. Every per-site
//! method takes either; a model without prismatic-clearance joints never reaches their code.

use super::FormulationError;
pub use super::corner_contacts::CornerSite;
use crate::contact::wear::{WearProfile, WornBearing};
use crate::contact::{
    CentreMotion, ClearanceJoint, ContactForces, ContactKinematics, free_flight_max_step,
    impact_velocity, kinks,
};
use crate::mechanics::planar::{PointState, cross, perp, point_state, point_state_with};
use crate::model::{Anchor, Frame, JointId, JointKind, Model};

/// One clearance joint: its anchors and its contact model.
#[derive(Debug, Clone)]
pub struct ContactSite {
    /// The joint in the model.
    pub joint: JointId,
    /// Bearing centre (body a of the joint).
    pub bearing: Anchor,
    /// Journal centre (body b of the joint).
    pub journal: Anchor,
    /// Contact law, friction and radii.
    pub contact: ClearanceJoint,
    /// The worn bearing profile set by [`ContactSites::set_wear_profile`] (`linkdyn wear`);
    /// `None`, the unworn circle, otherwise, and then no wear code runs.
    pub wear: Option<WornBearing>,
}

/// The state of one joint at (q, q̇): centres, kinematics and forces.
#[derive(Debug, Clone, Copy)]
pub struct SiteState {
    /// Bearing centre.
    pub bearing: PointState,
    /// Journal centre.
    pub journal: PointState,
    /// Relative kinematics.
    pub kinematics: ContactKinematics,
    /// Dry contact forces (all zero when free).
    pub forces: ContactForces,
    /// The oil film's forces of a lubricated joint, weighted for the transition to contact
    /// (all zero for a dry joint); the journal's act at its centre, the bearing's at its.
    pub film: ContactForces,
}

impl SiteState {
    /// The normal force the joint transmits, dry contact and film together (N).
    pub fn total_normal_force(&self) -> f64 {
        self.forces.normal_force + self.film.normal_force
    }

    /// The tangential force on the journal along t, friction and film together (N).
    pub fn total_tangential_force(&self) -> f64 {
        self.forces.friction_force + self.film.friction_force
    }
}

/// All clearance joints of a model (empty for a model without any: then no contact code runs).
#[derive(Debug, Clone, Default)]
pub struct ContactSites {
    sites: Vec<ContactSite>,
    /// The joints whose friction kinks are event functions, with their slip speeds (v0, v1)
    /// (`contact/kinks.rs`; empty unless [`ContactSites::set_kink_events`] switched them on).
    kinks: Vec<(usize, [f64; 2])>,
    /// The corner sites of the prismatic-clearance joints, after the revolute joints' sites.
    corners: Vec<CornerSite>,
}

impl ContactSites {
    /// The clearance joints of `model`, in model order.
    pub fn from_model(model: &Model) -> Self {
        let sites = model
            .joints
            .iter()
            .enumerate()
            .filter_map(|(i, j)| match &j.kind {
                JointKind::Clearance(spec) => Some(ContactSite {
                    joint: JointId(i),
                    bearing: j.a.clone(),
                    journal: j.b.clone(),
                    contact: ClearanceJoint::from_spec(spec),
                    wear: None,
                }),
                _ => None,
            })
            .collect();
        let corners = model
            .joints
            .iter()
            .enumerate()
            .filter(|(_, j)| matches!(j.kind, JointKind::PrismaticClearance(_)))
            .flat_map(|(i, _)| CornerSite::of_joint(model, JointId(i)))
            .collect();
        ContactSites {
            sites,
            kinks: Vec::new(),
            corners,
        }
    }

    /// With `on`, the friction kinks (v_t = ±v0, ±v1) of every joint whose law has them are
    /// event functions after the δ events ([`ContactSites::events_into`]); off (the default),
    /// the δ of each joint are the only ones.
    pub fn set_kink_events(&mut self, on: bool) {
        self.kinks = if on {
            self.sites
                .iter()
                .enumerate()
                .filter_map(|(k, s)| kinks::friction_kinks(&s.contact.friction).map(|v| (k, v)))
                .chain(self.corners.iter().enumerate().filter_map(|(i, c)| {
                    kinks::friction_kinks(&c.contact.friction).map(|v| (self.sites.len() + i, v))
                }))
                .collect()
        } else {
            Vec::new()
        };
    }

    /// Number of event functions: one δ per joint, then [`kinks::N_KINK_EVENTS`] per joint
    /// with kink events.
    pub fn n_events(&self) -> usize {
        self.len() + kinks::N_KINK_EVENTS * self.kinks.len()
    }

    /// Refuses an assembled state (q, q̇) at t = 0 with a slider corner on or past one of its
    /// guide's end stops (the corners against the guide surfaces are checked by the model, from
    /// the initial offset and tilt, which alone set them).
    pub fn check_end_stops_open(
        &self,
        model: &Model,
        q: &[f64],
        v: &[f64],
    ) -> Result<(), FormulationError> {
        for c in self.corners.iter().filter(|c| c.is_end_stop()) {
            let delta = c.state_alone(q, v, 0.0).kinematics.delta;
            if delta.is_nan() || delta >= 0.0 {
                let front = c.normal_is_forward();
                let names = super::corner_contacts::SITE_NAMES;
                return Err(FormulationError::SliderPastGuideEnd {
                    joint: model.joint(c.joint).name.clone(),
                    corner: names[(c.corner % 4).min(names.len() - 1)],
                    field: if front { "guide_end" } else { "guide_start" },
                    stop: if front { c.half_width } else { -c.half_width },
                    past: delta,
                });
            }
        }
        Ok(())
    }

    /// Number of contact sites: revolute clearance joints and corners.
    pub fn len(&self) -> usize {
        self.sites.len() + self.corners.len()
    }

    /// True if there are none.
    pub fn is_empty(&self) -> bool {
        self.sites.is_empty() && self.corners.is_empty()
    }

    /// The revolute clearance joints (sites 0..`sites().len()`).
    pub fn sites(&self) -> &[ContactSite] {
        &self.sites
    }

    /// The corner sites (sites `sites().len()`.. in this order).
    pub fn corners(&self) -> &[CornerSite] {
        &self.corners
    }

    /// The corner of site `k`, `None` for a revolute joint.
    fn corner(&self, k: usize) -> Option<&CornerSite> {
        k.checked_sub(self.sites.len())
            .and_then(|i| self.corners.get(i))
    }

    /// The contact law, friction and radii of site `k` (a revolute joint's or a corner's).
    pub fn contact_model(&self, k: usize) -> Option<&ClearanceJoint> {
        match self.sites.get(k) {
            Some(site) => Some(&site.contact),
            None => self.corner(k).map(|c| &c.contact),
        }
    }

    /// Centres and relative kinematics of joint `k` at (q, q̇), without forces.
    // Inlined as before the wear check was added here: out of line it cost 0.5 % more
    // instructions on farahan2016 (callgrind, docs/wear.md "Cost").
    #[inline(always)]
    fn site_kinematics(
        &self,
        k: usize,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
    ) -> (PointState, PointState, ContactKinematics) {
        let site = &self.sites[k];
        let bearing = point_state(site.bearing.frame, site.bearing.local, q, v, sin_cos);
        let journal = point_state(site.journal.frame, site.journal.local, q, v, sin_cos);
        let mut kinematics = site
            .contact
            .kinematics(&CentreMotion::from(bearing), &CentreMotion::from(journal));
        if let Some(worn) = &site.wear {
            worn_kinematics(worn, site, &mut kinematics, q, bearing.omega);
        }
        (bearing, journal, kinematics)
    }

    /// Sets the worn profile of the bearing of revolute joint `k` (an unworn profile clears it,
    /// so that the joint costs what an unworn one does). Errors: no revolute clearance joint `k`.
    pub fn set_wear_profile(
        &mut self,
        k: usize,
        profile: &WearProfile,
    ) -> Result<(), FormulationError> {
        let site = self
            .sites
            .get_mut(k)
            .ok_or_else(|| FormulationError::Unsupported {
                formulation: "DAE".into(),
                reason: format!("no revolute clearance joint {k} to wear"),
            })?;
        site.wear = (!profile.is_unworn()).then(|| WornBearing {
            profile: profile.clone(),
        });
        Ok(())
    }

    /// The angle φ_B (rad) of the bearing body of revolute joint `k` (0 on the ground) in the
    /// coordinates `q`, and the contact angle θ_e of `kinematics` in its frame
    /// ([`WornBearing::contact_angle`]): where the joint wears. `None` past the joints.
    pub fn contact_angle(
        &self,
        k: usize,
        q: &[f64],
        kinematics: &ContactKinematics,
    ) -> Option<f64> {
        let site = self.sites.get(k)?;
        Some(WornBearing::contact_angle(
            kinematics.normal,
            body_angle(site.bearing.frame, q),
        ))
    }

    /// Bearing and journal centres of joint `k` at (q, q̇), evaluating the sines and cosines of
    /// the joint's two bodies only (for a look at one joint in a large model).
    fn site_centres(&self, k: usize, q: &[f64], v: &[f64]) -> (PointState, PointState) {
        let site = &self.sites[k];
        let centre = |anchor: &Anchor| {
            let body_sin_cos = match anchor.frame {
                Frame::Body(id) => q[3 * id.0 + 2].sin_cos(),
                Frame::Ground => (0.0, 1.0),
            };
            point_state_with(anchor.frame, anchor.local, q, v, body_sin_cos)
        };
        (centre(&site.bearing), centre(&site.journal))
    }

    /// State of joint `k` at (q, q̇) and the relative acceleration ë = r̈_J − r̈_B of its centres
    /// (m/s²) for the body accelerations `acc` = q̈ (3 per body), with the stored impact
    /// velocity `stored` (0 = none): what the impact log's peak search reads at step ends
    /// (with [`ClearanceJoint::normal_force_rate`]). Only the joint's two bodies are evaluated.
    pub fn site_motion(
        &self,
        k: usize,
        q: &[f64],
        v: &[f64],
        acc: &[f64],
        stored: f64,
    ) -> (SiteState, [f64; 2]) {
        if let Some(c) = self.corner(k) {
            return c.motion(q, v, acc, stored);
        }
        let site = &self.sites[k];
        let state = self.site_state_alone(k, q, v, stored);
        let a_b = point_acceleration(site.bearing.frame, state.bearing, acc);
        let a_j = point_acceleration(site.journal.frame, state.journal, acc);
        (state, [a_j[0] - a_b[0], a_j[1] - a_b[1]])
    }

    /// State of joint `k` at (q, q̇) with the stored impact velocity `stored` (0 = none),
    /// evaluating only the joint's two bodies (see [`ContactSites::site_state`] for the form
    /// that reuses the right-hand side's sines and cosines of every body).
    pub fn site_state_alone(&self, k: usize, q: &[f64], v: &[f64], stored: f64) -> SiteState {
        if let Some(c) = self.corner(k) {
            return c.state_alone(q, v, stored);
        }
        let (bearing, journal) = self.site_centres(k, q, v);
        let site = &self.sites[k];
        let mut kinematics = site
            .contact
            .kinematics(&CentreMotion::from(bearing), &CentreMotion::from(journal));
        if let Some(worn) = &site.wear {
            worn_kinematics(worn, site, &mut kinematics, q, bearing.omega);
        }
        SiteState {
            bearing,
            journal,
            kinematics,
            forces: self.site_forces(k, &kinematics, stored),
            film: self.site_film(k, &kinematics, &bearing, &journal),
        }
    }

    /// The film's forces of joint `k` (zero for a dry joint).
    #[inline(always)]
    fn site_film(
        &self,
        k: usize,
        kinematics: &ContactKinematics,
        bearing: &PointState,
        journal: &PointState,
    ) -> ContactForces {
        match &self.sites[k].contact.lubrication {
            Some(film) => film.forces(kinematics, journal.omega, bearing.omega),
            None => ContactForces::default(),
        }
    }

    /// Forces of joint `k` for its kinematics (all zero while free).
    fn site_forces(&self, k: usize, kinematics: &ContactKinematics, stored: f64) -> ContactForces {
        // No contact work while free; a stage past a contact onset that is not yet located has
        // no stored δ̇⁽⁻⁾ and uses the current δ̇, its value at the onset to first order.
        if kinematics.delta > 0.0 {
            self.sites[k]
                .contact
                .forces(kinematics, impact_velocity(stored, kinematics.delta_dot))
        } else {
            ContactForces::default()
        }
    }

    /// State of joint `k` at (q, q̇) with the stored impact velocity `stored` (0 = none).
    pub fn site_state(
        &self,
        k: usize,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
        stored: f64,
    ) -> SiteState {
        if let Some(c) = self.corner(k) {
            return c.state(q, v, sin_cos, stored);
        }
        self.joint_state(k, q, v, sin_cos, stored)
    }

    /// [`ContactSites::site_state`] of a revolute joint `k` (< `sites().len()`): what the
    /// right-hand side's loop over the joints calls, without the corner dispatch.
    fn joint_state(
        &self,
        k: usize,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
        stored: f64,
    ) -> SiteState {
        let (bearing, journal, kinematics) = self.site_kinematics(k, q, v, sin_cos);
        SiteState {
            bearing,
            journal,
            kinematics,
            forces: self.site_forces(k, &kinematics, stored),
            film: self.site_film(k, &kinematics, &bearing, &journal),
        }
    }

    /// Adds every joint's contact forces and moments to Q (`out`, 3 per body), and the film's of
    /// the lubricated joints. Returns the rate at which the contacts dissipate energy (W, ≥ 0:
    /// hysteresis damping, friction and the films' viscous dissipation),
    /// computed only when `dissipation` is asked for (0 otherwise). Fails where a penetration
    /// exceeds [`ClearanceJoint::max_penetration`]; `joint_name` names joint k for that message.
    #[allow(clippy::too_many_arguments)] // one state, split the way the DAE stores it
    pub fn add_forces_into(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
        stored: &[f64],
        out: &mut [f64],
        dissipation: bool,
        joint_name: impl Fn(JointId) -> String,
    ) -> Result<f64, FormulationError> {
        let mut dissipated = 0.0;
        for k in 0..self.sites.len() {
            let site = &self.sites[k];
            let (bearing, journal, kinematics) = self.site_kinematics(k, q, v, sin_cos);
            if let Some(film) = &site.contact.lubrication {
                // The film acts at every eccentricity, through the two centres. (Apart from
                // the dry path: a dry joint's evaluation stays as it was, inlined.)
                let f = film.forces(&kinematics, journal.omega, bearing.omega);
                add(
                    site.journal.frame,
                    journal.arm,
                    f.on_journal,
                    f.journal_moment,
                    out,
                );
                add(
                    site.bearing.frame,
                    bearing.arm,
                    f.on_bearing,
                    f.bearing_moment,
                    out,
                );
                if dissipation {
                    dissipated -= f.power;
                }
            }
            if kinematics.delta <= 0.0 {
                continue;
            }
            let limit = site.contact.max_penetration();
            if kinematics.delta > limit {
                return Err(FormulationError::PenetrationTooDeep {
                    t,
                    joint: joint_name(site.joint),
                    penetration: kinematics.delta,
                    limit,
                });
            }
            let forces = self.site_forces(k, &kinematics, stored[k]);
            if dissipation {
                // Power of the contact forces −F_N δ̇ + F_T v_t minus its elastic part −F_e δ̇.
                let elastic = site.contact.law.elastic_force(kinematics.delta);
                dissipated -= forces.power + elastic * kinematics.delta_dot;
            }
            if forces.normal_force == 0.0 {
                continue;
            }
            // Force at the contact point = force at the centre + its moment about the centre.
            add(
                site.journal.frame,
                journal.arm,
                forces.on_journal,
                forces.journal_moment,
                out,
            );
            add(
                site.bearing.frame,
                bearing.arm,
                forces.on_bearing,
                forces.bearing_moment,
                out,
            );
        }
        if !self.corners.is_empty() {
            dissipated += self.add_corner_forces_into(
                t,
                q,
                v,
                sin_cos,
                stored,
                out,
                dissipation,
                &joint_name,
            )?;
        }
        Ok(dissipated)
    }

    /// [`ContactSites::add_forces_into`] for the corner sites: each corner's force at the
    /// corner on the slider and at the guide's material point under it (no moments about
    /// them). The power of the pair is −F_N δ̇ + F_T v_t, its elastic part −F_e δ̇.
    #[allow(clippy::too_many_arguments)] // as add_forces_into
    #[inline(never)] // out of the revolute joints' loop: a model without corners never calls it
    fn add_corner_forces_into(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
        stored: &[f64],
        out: &mut [f64],
        dissipation: bool,
        joint_name: &impl Fn(JointId) -> String,
    ) -> Result<f64, FormulationError> {
        let mut dissipated = 0.0;
        let first = self.sites.len();
        for (i, c) in self.corners.iter().enumerate() {
            let s = c.state(q, v, sin_cos, stored.get(first + i).copied().unwrap_or(0.0));
            if s.kinematics.delta <= 0.0 {
                continue;
            }
            if s.kinematics.delta > c.max_penetration {
                return Err(FormulationError::PenetrationTooDeep {
                    t,
                    joint: format!(
                        "{} ({} {})",
                        joint_name(c.joint),
                        if c.is_end_stop() {
                            "end stop"
                        } else {
                            "corner"
                        },
                        super::corner_contacts::SITE_NAMES
                            [c.corner.min(super::corner_contacts::SITE_NAMES.len() - 1)]
                    ),
                    penetration: s.kinematics.delta,
                    limit: c.max_penetration,
                });
            }
            if dissipation {
                let elastic = c.contact.law.elastic_force(s.kinematics.delta);
                dissipated -= s.forces.power + elastic * s.kinematics.delta_dot;
            }
            if s.forces.normal_force == 0.0 {
                continue;
            }
            add(c.slider, s.journal.arm, s.forces.on_journal, 0.0, out);
            add(c.guide, s.bearing.arm, s.forces.on_bearing, 0.0, out);
        }
        Ok(dissipated)
    }

    /// Adds the film's forces and moments of joint `k` to Q (`out`, 3 per body), evaluating
    /// only the joint's two bodies (nothing for a dry joint): what the Jacobians difference.
    pub fn add_film_into(&self, k: usize, q: &[f64], v: &[f64], out: &mut [f64]) {
        let site = &self.sites[k];
        if site.contact.lubrication.is_none() {
            return;
        }
        let (bearing, journal) = self.site_centres(k, q, v);
        let kinematics = site
            .contact
            .kinematics(&CentreMotion::from(bearing), &CentreMotion::from(journal));
        let film = self.site_film(k, &kinematics, &bearing, &journal);
        add(
            site.journal.frame,
            journal.arm,
            film.on_journal,
            film.journal_moment,
            out,
        );
        add(
            site.bearing.frame,
            bearing.arm,
            film.on_bearing,
            film.bearing_moment,
            out,
        );
    }

    /// Elastic energy stored in the contacts, Σ ∫₀^δ F_e dδ over the joints in contact (J); for
    /// the power laws K δⁿ⁺¹/(n + 1).
    pub fn elastic_energy(&self, q: &[f64], v: &[f64], sin_cos: &[(f64, f64)]) -> f64 {
        let mut energy = 0.0;
        for (k, site) in self.sites.iter().enumerate() {
            let delta = self.site_kinematics(k, q, v, sin_cos).2.delta;
            if delta > 0.0 {
                energy += site.contact.law.elastic_energy(delta);
            }
        }
        for c in &self.corners {
            let delta = c.state(q, v, sin_cos, 0.0).kinematics.delta;
            if delta > 0.0 {
                energy += c.contact.law.elastic_energy(delta);
            }
        }
        energy
    }

    /// Event functions ([`ContactSites::n_events`] of them): δ of every joint (m), then, for
    /// each joint with kink events, v_t ∓ v0, v_t ∓ v1 (m/s) while a contact with a stored
    /// impact velocity (`stored`, one per joint) is open, 1 otherwise (`contact/kinks.rs`).
    pub fn events_into(
        &self,
        q: &[f64],
        v: &[f64],
        sin_cos: &[(f64, f64)],
        stored: &[f64],
        g: &mut [f64],
    ) {
        let (deltas, rest) = g.split_at_mut(self.len().min(g.len()));
        let (joints, corners) = deltas.split_at_mut(self.sites.len().min(deltas.len()));
        for (k, gk) in joints.iter_mut().enumerate() {
            *gk = self.site_kinematics(k, q, v, sin_cos).2.delta;
        }
        for (c, gk) in self.corners.iter().zip(corners) {
            *gk = c.state(q, v, sin_cos, 0.0).kinematics.delta;
        }
        for (&(k, speeds), gk) in self
            .kinks
            .iter()
            .zip(rest.chunks_exact_mut(kinks::N_KINK_EVENTS))
        {
            let slip = match self.corner(k) {
                Some(c) => c.state(q, v, sin_cos, 0.0).kinematics.tangential_velocity,
                None => self.site_kinematics(k, q, v, sin_cos).2.tangential_velocity,
            };
            kinks::kink_events(speeds, stored[k], slip, gk);
        }
    }

    /// True when every joint is in contact ([`in_contact`]) at (q, q̇): the grazing guard then
    /// allows any step ([`ContactSites::max_step`] is ∞), and a caller can skip computing q̈
    /// for it. True for no joints.
    pub fn all_in_contact(&self, q: &[f64], v: &[f64], sin_cos: &[(f64, f64)]) -> bool {
        (0..self.sites.len()).all(|k| in_contact(&self.site_kinematics(k, q, v, sin_cos).2))
            && self
                .corners
                .iter()
                .all(|c| in_contact(&c.state(q, v, sin_cos, 0.0).kinematics))
    }

    /// The grazing guard: the largest step allowed from (q, q̇, q̈), the minimum over the free
    /// joints of [`free_flight_max_step`] (∞ when every joint is in contact).
    pub fn max_step(&self, q: &[f64], v: &[f64], acc: &[f64], sin_cos: &[(f64, f64)]) -> f64 {
        let mut h = f64::INFINITY;
        for (k, site) in self.sites.iter().enumerate() {
            let (bearing, journal, kinematics) = self.site_kinematics(k, q, v, sin_cos);
            if in_contact(&kinematics) {
                continue;
            }
            let a_j = point_acceleration(site.journal.frame, journal, acc);
            let a_b = point_acceleration(site.bearing.frame, bearing, acc);
            let rel = (a_j[0] - a_b[0]).hypot(a_j[1] - a_b[1]);
            h = h.min(free_flight_max_step(
                kinematics.delta,
                kinematics.relative_speed(),
                rel,
                site.contact.clearance,
            ));
        }
        for c in &self.corners {
            let s = c.state(q, v, sin_cos, 0.0);
            if in_contact(&s.kinematics) {
                continue;
            }
            // A flat surface: the gap closes at δ̇ alone, not at the slider's speed along the
            // guide, so V = |δ̇|; A bounds |δ̈| by |ë| plus the Coriolis term of a turning guide.
            let a_c = point_acceleration(c.slider, s.journal, acc);
            let a_q = point_acceleration(c.guide, s.bearing, acc);
            let rel = (a_c[0] - a_q[0]).hypot(a_c[1] - a_q[1])
                + (2.0 * s.bearing.omega * s.kinematics.tangential_velocity).abs();
            h = h.min(free_flight_max_step(
                s.kinematics.delta,
                s.kinematics.delta_dot.abs(),
                rel,
                c.contact.clearance,
            ));
        }
        h
    }
}

/// True while a joint is in contact for the grazing guard: δ > 0, or δ = 0 exactly and rising
/// (a restart at an impact). A restart at a separation has δ = 0 and δ̇ < 0: it is guarded.
pub fn in_contact(k: &ContactKinematics) -> bool {
    k.delta > 0.0 || (k.delta == 0.0 && k.delta_dot > 0.0)
}

/// Adds force `f` at the centre with arm `arm` from the centre of mass, plus the moment `m`
/// about that centre, to the generalised forces of `frame` (nothing for the ground).
fn add(frame: Frame, arm: [f64; 2], f: [f64; 2], m: f64, out: &mut [f64]) {
    if let Frame::Body(id) = frame {
        out[3 * id.0] += f[0];
        out[3 * id.0 + 1] += f[1];
        out[3 * id.0 + 2] += cross(arm, f) + m;
    }
}

/// Acceleration of a body point: a_cm + α perp(A s) − ω² A s (zero on the ground).
fn point_acceleration(frame: Frame, p: PointState, acc: &[f64]) -> [f64; 2] {
    match frame {
        Frame::Ground => [0.0, 0.0],
        Frame::Body(id) => {
            let k = 3 * id.0;
            let u = perp(p.arm);
            let w2 = p.omega * p.omega;
            [
                acc[k] + acc[k + 2] * u[0] - w2 * p.arm[0],
                acc[k + 1] + acc[k + 2] * u[1] - w2 * p.arm[1],
            ]
        }
    }
}

/// The angle φ (rad) of `frame` in the coordinates `q` (3 per body: x, y, φ); 0 on the ground.
fn body_angle(frame: Frame, q: &[f64]) -> f64 {
    match frame {
        Frame::Body(id) => q.get(3 * id.0 + 2).copied().unwrap_or(0.0),
        Frame::Ground => 0.0,
    }
}

/// The kinematics of a worn joint: the unworn `kinematics` deepened by the profile
/// ([`WornBearing::apply`]). Out of line: an unworn joint never calls it.
#[inline(never)]
fn worn_kinematics(
    worn: &WornBearing,
    site: &ContactSite,
    kinematics: &mut ContactKinematics,
    q: &[f64],
    bearing_omega: f64,
) {
    worn.apply(kinematics, body_angle(site.bearing.frame, q), bearing_omega);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::clearance_kinematics;

    /// A restart at a separation has δ = 0 exactly and δ̇ < 0: the grazing guard must apply
    /// there (it once skipped δ ≥ 0 and let DOP853 take a 5 rad step of free flight); a restart
    /// at an impact (δ = 0, δ̇ > 0) is contact.
    #[test]
    fn zero_penetration_counts_as_contact_only_while_rising() {
        let bearing = CentreMotion::default();
        let at = |vx: f64| {
            let journal = CentreMotion {
                position: [0.5e-3, 0.0],
                velocity: [vx, 0.0],
                omega: 0.0,
            };
            clearance_kinematics(&bearing, &journal, 0.01, 0.5e-3)
        };
        assert_eq!(at(-0.1).delta, 0.0);
        assert!(!in_contact(&at(-0.1)), "separating at δ = 0 is free");
        assert!(in_contact(&at(0.1)), "impacting at δ = 0 is contact");
        let inside = CentreMotion {
            position: [0.4e-3, 0.0],
            ..CentreMotion::default()
        };
        assert!(!in_contact(&clearance_kinematics(
            &bearing, &inside, 0.01, 0.5e-3
        )));
    }
}
