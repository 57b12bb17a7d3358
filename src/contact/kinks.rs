//! Event functions at the kinks of the friction law, so that implicit steps end at them.
//!
//! Ambrósio's law ([`crate::contact::friction::ambrosio`]) is continuous in the slip velocity
//! v_t but its slope jumps at |v_t| = v0 and |v_t| = v1 (the printed variant jumps in value
//! there). A Radau5 step across such a point integrates one polynomial over two laws; the error
//! estimate, made for smooth solutions, does not see it. On farahan2016 (250 rpm, rtol 1e-9)
//! such steps had true local errors of up to 1.2e-6 rad/s in the rates, and the next impacts
//! amplify that (docs/numerics.md, "The reduced formulation meets the target"). As event functions the
//! kinks are cut by Radau5 like an impact (`Radau5Settings::cut_at_events`): the step ends
//! just past the kink. The response is [`EventResponse::Continue`](crate::formulation::EventResponse::Continue):
//! nothing in the state changes.
//!
//! The explicit pairs cut their steps at them the same way (`ExplicitRkSettings::cut_at_events`).
//!
//! Shared by the reduced formulation (events 1–4 of its one joint), the DAE (four per
//! clearance joint after the δ events) and the generalised formulation (the DAE's, at the
//! projected state), each switched on by [`crate::simulation::Simulation`] for Radau5, and for
//! DOPRI5 and DOP853 at rtol ≤ [`crate::simulation::EXPLICIT_CUT_MAX_RTOL`].
//!
//! The four functions are v_t − v0, v_t + v0, v_t − v1, v_t + v1 (each crossed once when v_t
//! sweeps through the ramp; |v_t| − v0 would miss a pass through zero inside one step). They are
//! active only while a contact with a stored impact velocity δ̇⁽⁻⁾ > 0 is open (the stored state of the joint): the
//! friction force is zero in free flight, and the gate is constant between events, so the
//! functions are continuous inside every step. A contact entered with δ̇⁽⁻⁾ = 0 (grazing) has no
//! kink events; its steps are then what they were before.

use crate::model::FrictionSpec;

/// Number of kink event functions when the friction law has kinks.
pub const N_KINK_EVENTS: usize = 4;

/// The slip speeds (v0, v1) of the kinks of `friction` (m/s), or `None` for a law without
/// (no friction).
pub fn friction_kinks(friction: &FrictionSpec) -> Option<[f64; 2]> {
    match *friction {
        FrictionSpec::Ambrosio { v0, v1, .. } | FrictionSpec::AmbrosioAsPrinted { v0, v1, .. } => {
            Some([v0, v1])
        }
        FrictionSpec::None => None,
    }
}

/// Whether `friction` is continuous in the slip velocity, its kinks changing only its slope.
/// The printed variant of Ambrósio's law jumps in value at v0 and v1: where the slip settles at
/// a jump (a sliding mode), kink events would be crossed at every step, and an explicit pair
/// that cuts its steps at them stalls (`tests/friction_as_printed.rs`).
pub fn continuous(friction: &FrictionSpec) -> bool {
    !matches!(friction, FrictionSpec::AmbrosioAsPrinted { .. })
}

/// Writes the kink event functions (m/s) into `g` (length [`N_KINK_EVENTS`]) for the slip
/// velocity `slip` and the stored impact velocity `stored`: v_t ∓ v0, v_t ∓ v1 in contact, 1
/// (no sign change possible) otherwise.
pub fn kink_events(kinks: [f64; 2], stored: f64, slip: f64, g: &mut [f64]) {
    let [v0, v1] = kinks;
    let in_contact = stored > 0.0;
    for (gk, v) in g.iter_mut().zip([v0, -v0, v1, -v1]) {
        *gk = if in_contact { slip - v } else { 1.0 };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinks_of_each_friction_law() {
        let ambrosio = FrictionSpec::Ambrosio {
            coefficient: 0.1,
            v0: 1e-4,
            v1: 1e-3,
        };
        let printed = FrictionSpec::AmbrosioAsPrinted {
            coefficient: 0.1,
            v0: 2e-4,
            v1: 3e-3,
        };
        assert_eq!(friction_kinks(&ambrosio), Some([1e-4, 1e-3]));
        assert_eq!(friction_kinks(&printed), Some([2e-4, 3e-3]));
        assert_eq!(friction_kinks(&FrictionSpec::None), None);
    }

    /// In contact each function changes sign exactly where the law's slope (or value) changes:
    /// v_t = ±v0, ±v1; a sweep of v_t across the ramp crosses each once. Free: no sign changes.
    #[test]
    fn functions_vanish_at_the_kinks_and_only_in_contact() {
        let kinks = [1e-4, 1e-3];
        let mut g = [0.0; N_KINK_EVENTS];
        for (k, v) in [1e-4, -1e-4, 1e-3, -1e-3].into_iter().enumerate() {
            kink_events(kinks, 0.05, v, &mut g);
            assert_eq!(g[k], 0.0, "function {k} at v_t = {v}");
        }
        let signs = |slip: f64| {
            let mut g = [0.0; N_KINK_EVENTS];
            kink_events(kinks, 0.05, slip, &mut g);
            g.map(f64::signum)
        };
        // From above the ramp to below −v1: every function goes from + to −, once.
        let (start, end) = (signs(2e-3), signs(-2e-3));
        assert_eq!(start, [1.0; 4]);
        assert_eq!(end, [-1.0; 4]);
        // From +5e-4 to −5e-4 (through the dead band): v_t ∓ v0 change sign, v_t ∓ v1 do
        // not (|v_t| − v0 would be positive at both ends and miss the two kinks).
        assert_eq!(signs(5e-4), [1.0, 1.0, -1.0, 1.0]);
        assert_eq!(signs(-5e-4), [-1.0, -1.0, -1.0, 1.0]);
        for slip in [-2e-3, -5e-4, 0.0, 5e-4, 2e-3] {
            kink_events(kinks, 0.0, slip, &mut g);
            assert_eq!(g, [1.0; 4], "free, v_t = {slip}");
        }
    }
}
