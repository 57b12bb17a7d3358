//! A run's samples as [`Instant`]s at any time: body poses, contact forces and journal paths
//! interpolated linearly between the samples of a result table.

use super::scene::{Instant, global, slide};
use crate::model::{JointKind, Model};
use crate::plot::{PlotError, Table};

/// Most points kept of a journal-centre path: every k-th sample beyond that (a path of 4000
/// points is smooth at any picture size and keeps an HTML file small).
const MAX_PATH_POINTS: usize = 4000;

/// A run of a model, ready to be drawn at any time within it.
#[derive(Debug)]
pub struct Recording<'a> {
    model: &'a Model,
    t: &'a [f64],
    poses: Vec<[&'a [f64]; 3]>,
    contact: Vec<Option<[&'a [f64]; 2]>>,
    /// Per joint: (t, e) at the kept samples (empty for joints without clearance).
    paths: Vec<Vec<(f64, [f64; 2])>>,
    /// Per joint: the least and greatest slide of a prismatic joint over every sample.
    travel: Vec<Option<[f64; 2]>>,
}

impl<'a> Recording<'a> {
    /// The run `run` of `model`: its `t`, `<body>.x`, `.y`, `.phi` columns (and the `<joint>.fn`,
    /// `.ft` columns of clearance joints, where present). Refuses a table without rows or whose
    /// times are not finite and non-decreasing.
    pub fn new(model: &'a Model, run: &'a Table) -> Result<Self, PlotError> {
        let t = run.column("t")?;
        let no_data = |reason: String| PlotError::NoData {
            path: run.path.display().to_string(),
            reason,
        };
        if t.is_empty() {
            return Err(no_data("no data rows".into()));
        }
        if let Some(k) = t
            .windows(2)
            .position(|w| !(w[0].is_finite() && w[1].is_finite() && w[1] >= w[0]))
        {
            return Err(no_data(format!(
                "t is not finite and non-decreasing at data rows {} and {}",
                k + 1,
                k + 2
            )));
        }
        let mut poses = Vec::with_capacity(model.bodies.len());
        for b in &model.bodies {
            poses.push([
                run.column(&format!("{}.x", b.name))?,
                run.column(&format!("{}.y", b.name))?,
                run.column(&format!("{}.phi", b.name))?,
            ]);
        }
        let contact = model
            .joints
            .iter()
            .map(|j| match j.kind {
                JointKind::Clearance(_) => run
                    .column(&format!("{}.fn", j.name))
                    .ok()
                    .zip(run.column(&format!("{}.ft", j.name)).ok())
                    .map(|(a, b)| [a, b]),
                _ => None,
            })
            .collect();
        let mut rec = Recording {
            model,
            t,
            poses,
            contact,
            paths: Vec::new(),
            travel: Vec::new(),
        };
        let stride = t.len().div_ceil(MAX_PATH_POINTS).max(1);
        rec.paths = model
            .joints
            .iter()
            .map(|j| match j.kind {
                JointKind::Clearance(_) => (0..t.len())
                    .step_by(stride)
                    .filter_map(|i| {
                        let poses = rec.poses_at_row(i);
                        let (a, b) = (global(&j.a, &poses)?, global(&j.b, &poses)?);
                        Some((t[i], [b[0] - a[0], b[1] - a[1]]))
                    })
                    .collect(),
                _ => Vec::new(),
            })
            .collect();
        rec.travel = model
            .joints
            .iter()
            .map(|j| {
                if !matches!(
                    j.kind,
                    JointKind::Prismatic { .. } | JointKind::PrismaticClearance(_)
                ) {
                    return None;
                }
                (0..t.len())
                    .filter_map(|i| slide(j, &rec.poses_at_row(i)))
                    .filter(|s| s.is_finite())
                    .fold(None, |range: Option<[f64; 2]>, s| {
                        Some(range.map_or([s, s], |[lo, hi]| [lo.min(s), hi.max(s)]))
                    })
            })
            .collect();
        Ok(rec)
    }

    /// First and last sample time (s).
    pub fn span(&self) -> (f64, f64) {
        (
            self.t.first().copied().unwrap_or(0.0),
            self.t.last().copied().unwrap_or(0.0),
        )
    }

    /// The model.
    pub fn model(&self) -> &'a Model {
        self.model
    }

    fn poses_at_row(&self, i: usize) -> Vec<[f64; 3]> {
        self.poses
            .iter()
            .map(|c| c.map(|col| col.get(i).copied().unwrap_or(f64::NAN)))
            .collect()
    }

    /// The state at time `t` (s), clamped to the run: each column interpolated linearly between
    /// the two samples around `t`; the journal paths are the kept samples up to `t` and the
    /// interpolated eccentricity at `t`.
    pub fn at(&self, t: f64) -> Instant {
        let (t0, t1) = self.span();
        let t = t.clamp(t0, t1);
        // Samples i and i + 1 bracket t; w is the weight of i + 1.
        let i = self.t.partition_point(|&s| s <= t).saturating_sub(1);
        let j = (i + 1).min(self.t.len() - 1);
        let (ti, tj) = (self.t[i], self.t[j]);
        let w = if tj > ti { (t - ti) / (tj - ti) } else { 0.0 };
        let lerp = |col: &[f64]| {
            let a = col.get(i).copied().unwrap_or(f64::NAN);
            let b = col.get(j).copied().unwrap_or(a);
            if w == 0.0 { a } else { a + w * (b - a) }
        };
        let poses: Vec<[f64; 3]> = self.poses.iter().map(|c| c.map(lerp)).collect();
        let contact = self
            .contact
            .iter()
            .map(|c| c.map(|cols| cols.map(lerp)))
            .collect();
        let history = self
            .model
            .joints
            .iter()
            .zip(&self.paths)
            .map(|(joint, path)| {
                if !matches!(joint.kind, JointKind::Clearance(_)) {
                    return Vec::new();
                }
                let n = path.partition_point(|(s, _)| *s <= t);
                let mut h: Vec<[f64; 2]> = path.iter().take(n).map(|(_, e)| *e).collect();
                if let (Some(a), Some(b)) = (global(&joint.a, &poses), global(&joint.b, &poses)) {
                    h.push([b[0] - a[0], b[1] - a[1]]);
                }
                h
            })
            .collect();
        Instant {
            t,
            poses,
            contact,
            history,
            travel: self.travel.clone(),
        }
    }

    /// The contact-force magnitudes |F_J| = √(F_N² + F_T²) (N) of every clearance joint at
    /// every sample where it is positive.
    pub fn contact_forces(&self) -> Vec<f64> {
        let mut out = Vec::new();
        for [f_n, f_t] in self.contact.iter().flatten() {
            for (a, b) in f_n.iter().zip(f_t.iter()) {
                let f = a.hypot(*b);
                if f.is_finite() && f > 0.0 {
                    out.push(f);
                }
            }
        }
        out
    }
}
