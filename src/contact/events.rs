//! Contact events of a clearance joint: the rule for the impact velocity δ̇⁽⁻⁾
//! ([`impact_velocity`]), an event log ([`ContactMemory`]) and the statistics an output stage may
//! collect ([`ContactStats`]).
//!
//! The event function is the penetration δ (m). The integrator locates its zeros and reports
//! each one with its direction:
//!
//! - **Rising** (δ: − → +, free → contact): an impact. The penetration rate at that instant is the
//!   impact velocity δ̇⁽⁻⁾ (m/s) of the contact laws (paper eq. 7); it is stored,
//!   as max(δ̇, 0), and kept for the whole contact.
//! - **Falling** (δ: + → −, contact → free): a separation; the stored value is cleared to 0.
//!
//! **Where δ̇⁽⁻⁾ lives.** Both formulations keep the stored δ̇⁽⁻⁾ of each clearance joint in their
//! state vector, as a component with zero derivative that only `apply_event` changes (0 = no
//! impact recorded). The equations, the outputs and every sample then stay pure functions of
//! (t, y): an output computed after the run from a stored sample sees the δ̇⁽⁻⁾ that was valid at
//! its time, not the last one recorded. [`ContactMemory`] is only a log (impact times, counts) and
//! never enters a force.
//!
//! **The rule** ([`impact_velocity`]): in contact, the law uses the stored δ̇⁽⁻⁾ if one is recorded
//! (> 0), else the current δ̇. The second case covers an integrator stage evaluated past a contact
//! onset that is not yet located (the current δ̇ is the value that will be recorded, to first order
//! in the distance from the root) and a contact present without a recorded impact; if that δ̇ is
//! not usable (≤ [`crate::contact::laws::MIN_IMPACT_VELOCITY`]) the laws switch their damping off.
//!
//! Locating the zero of δ with a root finder (rather than the paper's sign test between steps,
//! eq. 26) is what makes δ̇⁽⁻⁾ the rate *at* the impact, as the paper requires below eq. 7. An
//! integrator should not report the same root again right after the restart at it (δ is ~0
//! there); a duplicate Rising would replace δ̇⁽⁻⁾ by a rate taken after the impact began.
//!
//! (`ContactMemory` takes no `formulation::Crossing`: `contact` sits above `formulation` in the
//! module order and may not use it; the formulation matches on the crossing and calls
//! [`ContactMemory::on_impact`] or [`ContactMemory::on_separation`].)
//!
//! # References
//! 1. P. Flores, J. Ambrósio, J. C. P. Claro, H. M. Lankarani, Dynamic behaviour of planar rigid
//!    multi-body systems including revolute joints with clearance, *Proc. IMechE Part K: Journal
//!    of Multi-body Dynamics* 221 (2007) 161–174.
//! 2. S. B. Farahan, M. R. Ghazavi, S. Rahmanian, Nonlinear dynamic analysis of a four-bar
//!    mechanism having revolute joint with clearance, *Journal of Theoretical and Applied Vibration
//!    and Acoustics* (2016), eqs. 7 and 26, <https://tava.isav.ir/article_19881.html>.

/// The impact velocity (m/s) a contact law should use: the stored δ̇⁽⁻⁾ `stored` if one is
/// recorded (> 0), else the current penetration rate `delta_dot` (module documentation).
#[inline]
pub fn impact_velocity(stored: f64, delta_dot: f64) -> f64 {
    if stored > 0.0 { stored } else { delta_dot }
}

/// Event log of one clearance joint: impacts and separations as the formulation saw them at
/// located events. Bookkeeping only; no force depends on it.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct ContactMemory {
    /// True between a Rising and the next Falling crossing of δ.
    pub in_contact: bool,
    /// δ̇ (m/s) at the last Rising crossing; 0 before the first impact.
    pub impact_velocity: f64,
    /// Times (s) of the Rising crossings (impacts), in order.
    pub impacts: Vec<f64>,
    /// Number of Falling crossings (separations).
    pub separations: usize,
    /// Largest impact velocity δ̇⁽⁻⁾ recorded (m/s).
    pub max_impact_velocity: f64,
}

impl ContactMemory {
    /// Log at the start of a run: `in_contact` if the journal starts with δ > 0 (then no impact
    /// is recorded for that contact).
    pub fn new(in_contact: bool) -> Self {
        ContactMemory {
            in_contact,
            ..ContactMemory::default()
        }
    }

    /// A Rising zero of δ (an impact) located at time `t` (s) with impact velocity `delta_dot`
    /// (m/s): records the impact time and velocity and marks the joint in contact. A formulation
    /// calls it for `Crossing::Rising` of its δ event.
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

    /// The rule: a recorded impact velocity wins; without one, the current rate.
    #[test]
    fn impact_velocity_rule() {
        assert_eq!(impact_velocity(0.25, -0.1), 0.25, "recorded");
        assert_eq!(
            impact_velocity(0.0, 0.3),
            0.3,
            "none recorded: current rate"
        );
        assert_eq!(
            impact_velocity(0.0, -0.3),
            -0.3,
            "current rate, unusable: laws fall back"
        );
    }

    /// Rising records the time and velocity; Falling frees the joint; a second impact replaces
    /// the last velocity.
    #[test]
    fn crossings_update_the_log() {
        let mut m = ContactMemory::new(false);
        m.on_impact(0.10, 0.25);
        assert!(m.in_contact);
        assert_eq!(m.impact_velocity, 0.25);
        m.on_separation();
        assert!(!m.in_contact);
        assert_eq!(m.separations, 1);
        m.on_impact(0.20, 0.05);
        assert_eq!(m.impact_velocity, 0.05);
        assert_eq!(m.impacts, vec![0.10, 0.20]);
        assert_eq!(m.n_impacts(), 2);
        assert_eq!(m.max_impact_velocity, 0.25);
    }

    #[test]
    fn start_in_contact_has_no_impact() {
        let m = ContactMemory::new(true);
        assert!(m.in_contact);
        assert_eq!(m.impact_velocity, 0.0);
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
