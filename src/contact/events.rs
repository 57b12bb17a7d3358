//! Contact events of a clearance joint: what a formulation must remember between events
//! ([`ContactMemory`]) and the statistics an output stage may collect ([`ContactStats`]).
//!
//! The event function is the penetration δ (m). The integrator locates its zeros and reports
//! each one with its direction:
//!
//! - **Rising** (δ: − → +, free → contact): an impact, [`ContactMemory::on_impact`]. The penetration rate at that instant is the
//!   impact velocity δ̇⁽⁻⁾ (m/s) of the contact laws (paper eq. 7); it is stored and kept for the
//!   whole contact, and the impact time is recorded.
//! - **Falling** (δ: + → −, contact → free): a separation, [`ContactMemory::on_separation`]. The joint is marked free; δ̇⁽⁻⁾ keeps its
//!   last value but is not used while free.
//!
//! (The two methods take no `formulation::Crossing`: `contact` sits above `formulation` in the
//! module order and may not use it; the formulation matches on the crossing and calls one of them.)
//!
//! Locating the zero of δ with a root finder (rather than the paper's sign test between steps,
//! eq. 26) is what makes δ̇⁽⁻⁾ the rate *at* the impact, as the paper requires below eq. 7.
//!
//! Between a contact's start and the event that reports it (an integrator stage past the root,
//! evaluated before the root is located), the formulation sees δ > 0 while the memory still says
//! "free". [`ContactMemory::impact_velocity_for`] then uses the current δ̇ as the best estimate of
//! the impact velocity about to be recorded (it is exactly that at the root), so those trial
//! evaluations see a force close to the one the located contact will have.
//!
//! # References
//! 1. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, Dynamic behaviour of planar rigid
//!    multi-body systems including revolute joints with clearance, *Proc. IMechE Part K: Journal
//!    of Multi-body Dynamics* 221 (2007) 161–174.
//! 2. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eqs. 7 and 26, <https://tava.isav.ir/article_19881.html>.

/// The discrete state of one clearance joint, changed only at located events.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct ContactMemory {
    /// True between a Rising and the next Falling crossing of δ.
    pub in_contact: bool,
    /// δ̇⁽⁻⁾ (m/s): δ̇ at the last Rising crossing; 0 before the first impact.
    pub impact_velocity: f64,
    /// Times (s) of the Rising crossings (impacts), in order.
    pub impacts: Vec<f64>,
    /// Number of Falling crossings (separations).
    pub separations: usize,
    /// Largest impact velocity δ̇⁽⁻⁾ recorded (m/s).
    pub max_impact_velocity: f64,
}

impl ContactMemory {
    /// Memory at the start of a run: `in_contact` if the journal starts with δ > 0 (then there is
    /// no impact velocity: the contact laws switch their damping off until the next impact).
    pub fn new(in_contact: bool) -> Self {
        ContactMemory {
            in_contact,
            ..ContactMemory::default()
        }
    }

    /// A Rising zero of δ (an impact) located at time `t` (s) with penetration rate `delta_dot`
    /// (m/s): stores δ̇⁽⁻⁾ = `delta_dot` for the whole contact, records the impact time and marks
    /// the joint in contact. A formulation calls it for `Crossing::Rising` of its δ event.
    pub fn on_impact(&mut self, t: f64, delta_dot: f64) {
        self.in_contact = true;
        self.impact_velocity = delta_dot;
        self.impacts.push(t);
        if delta_dot > self.max_impact_velocity {
            self.max_impact_velocity = delta_dot;
        }
    }

    /// A Falling zero of δ (a separation): marks the joint free. A formulation calls it for
    /// `Crossing::Falling` of its δ event.
    pub fn on_separation(&mut self) {
        self.in_contact = false;
        self.separations += 1;
    }

    /// The impact velocity (m/s) the contact law should use when the current penetration rate is
    /// `delta_dot`: the stored δ̇⁽⁻⁾ while in contact, else `delta_dot` itself (a stage evaluated
    /// past a not yet located impact; see the module documentation).
    pub fn impact_velocity_for(&self, delta_dot: f64) -> f64 {
        if self.in_contact {
            self.impact_velocity
        } else {
            delta_dot
        }
    }

    /// Number of impacts recorded.
    pub fn n_impacts(&self) -> usize {
        self.impacts.len()
    }
}

/// Peak values of a clearance joint over the samples an output stage has seen (the values
/// between samples are not seen: these are sampled maxima).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct ContactStats {
    /// Samples recorded.
    pub samples: usize,
    /// Samples with δ > 0.
    pub samples_in_contact: usize,
    /// Largest penetration δ seen (m); 0 if never in contact.
    pub max_penetration: f64,
    /// Time of `max_penetration` (s).
    pub max_penetration_time: f64,
    /// Largest normal force F_N seen (N).
    pub peak_normal_force: f64,
    /// Time of `peak_normal_force` (s).
    pub peak_normal_force_time: f64,
}

impl ContactStats {
    /// Adds one sample at time `t` (s) with penetration `delta` (m) and normal force
    /// `normal_force` (N).
    pub fn record(&mut self, t: f64, delta: f64, normal_force: f64) {
        self.samples += 1;
        if delta > 0.0 {
            self.samples_in_contact += 1;
        }
        if delta > self.max_penetration {
            self.max_penetration = delta;
            self.max_penetration_time = t;
        }
        if normal_force > self.peak_normal_force {
            self.peak_normal_force = normal_force;
            self.peak_normal_force_time = t;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rising stores δ̇⁽⁻⁾ for the whole contact and records the time; Falling frees the joint;
    /// a second impact replaces δ̇⁽⁻⁾.
    #[test]
    fn crossings_update_the_memory() {
        let mut m = ContactMemory::new(false);
        assert_eq!(m.impact_velocity_for(0.3), 0.3, "free: current rate");
        m.on_impact(0.10, 0.25);
        assert!(m.in_contact);
        assert_eq!(m.impact_velocity, 0.25);
        assert_eq!(m.impact_velocity_for(-0.1), 0.25, "in contact: stored δ̇⁽⁻⁾");
        m.on_separation();
        assert!(!m.in_contact);
        assert_eq!(m.separations, 1);
        m.on_impact(0.20, 0.05);
        assert_eq!(m.impact_velocity, 0.05);
        assert_eq!(m.impacts, vec![0.10, 0.20]);
        assert_eq!(m.n_impacts(), 2);
        assert_eq!(m.max_impact_velocity, 0.25);
    }

    /// Starting in contact: no impact velocity (0, so the laws fall back to no damping).
    #[test]
    fn start_in_contact_has_no_impact_velocity() {
        let m = ContactMemory::new(true);
        assert_eq!(m.impact_velocity_for(0.4), 0.0);
        assert!(m.impacts.is_empty());
    }

    #[test]
    fn stats_keep_sampled_peaks() {
        let mut s = ContactStats::default();
        s.record(0.0, -1e-4, 0.0);
        s.record(0.1, 2e-6, 300.0);
        s.record(0.2, 1e-6, 500.0);
        assert_eq!(s.samples, 3);
        assert_eq!(s.samples_in_contact, 2);
        assert_eq!((s.max_penetration, s.max_penetration_time), (2e-6, 0.1));
        assert_eq!(
            (s.peak_normal_force, s.peak_normal_force_time),
            (500.0, 0.2)
        );
    }
}
