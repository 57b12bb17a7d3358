//! The impact log file `F.impacts.csv`: one row per impact of every clearance joint.

use super::format_number;
use crate::simulation::{Provenance, RunSummary};

/// The header row of the impact log.
pub const IMPACTS_HEADER: &str =
    "joint,index,t,driver_angle,impact_velocity,peak_normal_force,peak_penetration,duration";

/// The impact log of a run as CSV text: the header
/// `joint,index,t,driver_angle,impact_velocity,peak_normal_force,peak_penetration,duration`,
/// the `#` provenance lines, then one row per impact, joints in model order and impacts in time order (SI units: s, rad,
/// m/s, N, m; see [`Impact`](crate::simulation::Impact)). An empty `duration` marks a contact
/// still open at the end of the run, an empty `driver_angle` a model without exactly one
/// driver. A run without impacts has the header and the provenance only.
pub fn impacts_csv(provenance: &Provenance, summary: &RunSummary) -> String {
    // The header first, then the provenance, as in every CSV linkdyn writes: readers that
    // take names from the first line and skip `#` lines (NumPy, pandas) read it as it is.
    let mut text = String::from(IMPACTS_HEADER);
    text.push('\n');
    for line in provenance.lines() {
        text.push_str("# ");
        text.push_str(&line);
        text.push('\n');
    }
    let opt = |v: Option<f64>| v.map(format_number).unwrap_or_default();
    for joint in &summary.clearance_joints {
        let name = if joint.joint.contains([',', '"', '\n', '\r']) {
            format!("\"{}\"", joint.joint.replace('"', "\"\""))
        } else {
            joint.joint.clone()
        };
        for i in &joint.impacts {
            text.push_str(&format!(
                "{name},{},{},{},{},{},{},{}\n",
                i.index,
                format_number(i.t),
                opt(i.driver_angle),
                format_number(i.impact_velocity),
                format_number(i.peak_normal_force),
                format_number(i.peak_penetration),
                opt(i.duration),
            ));
        }
    }
    text
}
