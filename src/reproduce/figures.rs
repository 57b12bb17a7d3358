//! The reproduction's figures: in-memory tables in the layouts [`crate::plot::figures`] reads,
//! drawn by its builders and rendered as PNG. A figure that cannot be drawn is recorded with
//! its reason instead of stopping the reproduction.

use crate::analysis::{LyapunovEstimate, PhasePortrait, Spectrum};
use crate::plot::{Figure, PlotError, Table, figures, render};
use crate::simulation::Trajectory;
use crate::simulation::analyses::ModelSection;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// A figure file of the report.
#[derive(Debug, Clone, Serialize)]
pub struct FigureFile {
    /// Figure number of the paper ("fig3" … "fig7").
    pub figure: String,
    /// Panel letters of the paper's figure.
    pub panel: String,
    /// File name inside the output directory.
    pub file: String,
    /// Caption.
    pub caption: String,
    /// Why it could not be drawn, if so.
    pub error: Option<String>,
}

fn table(name: &str, names: &[&str], columns: Vec<Vec<f64>>) -> Table {
    Table {
        path: PathBuf::from(name),
        comments: Vec::new(),
        names: names.iter().map(|s| s.to_string()).collect(),
        columns,
    }
}

fn run_table(name: &str, t: &Trajectory) -> Table {
    let mut names = vec!["t".to_string()];
    names.extend(t.names.iter().cloned());
    let mut columns = vec![t.t.clone()];
    columns.extend(t.columns.iter().cloned());
    Table {
        path: PathBuf::from(name),
        comments: Vec::new(),
        names,
        columns,
    }
}

fn finish(
    dir: &Path,
    figure: &str,
    variant: &str,
    panel: &str,
    caption: &str,
    built: Result<Figure, PlotError>,
) -> FigureFile {
    let file = format!("{figure}{panel}_{variant}.png");
    let error = built
        .and_then(|mut fig| {
            fig.title = format!("{caption} [{variant}]");
            render(&fig, &dir.join(&file))
        })
        .err()
        .map(|e| e.to_string());
    FigureFile {
        figure: figure.into(),
        panel: panel.into(),
        file,
        caption: caption.into(),
        error,
    }
}

/// `column` of the clearance run against the ideal run.
#[allow(clippy::too_many_arguments)] // one figure's identity, data and caption
pub fn series(
    dir: &Path,
    figure: &str,
    variant: &str,
    panel: &str,
    run: &Trajectory,
    ideal: &Trajectory,
    column: &str,
    caption: &str,
) -> FigureFile {
    let a = run_table("clearance joint", run);
    let b = run_table("ideal joint", ideal);
    finish(
        dir,
        figure,
        variant,
        panel,
        caption,
        figures::series(&[&a, &b], &[column.to_string()], &[]),
    )
}

/// The journal orbit inside the clearance circle.
pub fn orbit(
    dir: &Path,
    figure: &str,
    variant: &str,
    panel: &str,
    run: &Trajectory,
    clearance: f64,
    caption: &str,
) -> FigureFile {
    let a = run_table("clearance joint", run);
    finish(
        dir,
        figure,
        variant,
        panel,
        caption,
        figures::orbit(&a, "B", clearance),
    )
}

/// The section's journal centre (B.ey against B.ex), on axes that span at least the radial
/// clearance `clearance` (m), as `linkdyn plot poincare` draws them: a converged section is
/// one point, which autoscaling would spread over its round-off.
pub fn poincare(
    dir: &Path,
    figure: &str,
    variant: &str,
    panel: &str,
    s: &ModelSection,
    clearance: f64,
    caption: &str,
) -> FigureFile {
    let mut names = vec!["turn", "t"];
    names.extend(s.section.names.iter().map(String::as_str));
    let mut columns = vec![
        s.turns.iter().map(|&k| k as f64).collect(),
        s.section.times.clone(),
    ];
    for j in 0..s.section.names.len() {
        columns.push(
            s.section
                .points
                .iter()
                .map(|p| p.get(j).copied().unwrap_or(f64::NAN))
                .collect(),
        );
    }
    let t = table("section", &names, columns);
    finish(
        dir,
        figure,
        variant,
        panel,
        caption,
        figures::poincare(&t, "B.ex", "B.ey", Some(clearance)),
    )
}

/// An amplitude spectrum with the driving frequency's multiples marked, log amplitude.
pub fn spectrum(
    dir: &Path,
    figure: &str,
    variant: &str,
    panel: &str,
    s: &Spectrum,
    driving_hz: f64,
    caption: &str,
) -> FigureFile {
    // Up to 25 driving multiples: the harmonics that carry the motion; beyond, numerical floor.
    let f_max = 25.0 * driving_hz;
    let (f, a): (Vec<f64>, Vec<f64>) = s
        .frequencies
        .iter()
        .zip(&s.amplitudes)
        .filter(|(f, a)| **f <= f_max && **a > 0.0)
        .map(|(f, a)| (*f, *a))
        .unzip();
    let t = table("spectrum", &["frequency_hz", "amplitude"], vec![f, a]);
    finish(
        dir,
        figure,
        variant,
        panel,
        caption,
        figures::spectrum(
            &t,
            &figures::SpectrumOptions {
                log: true,
                driving_hz: Some(driving_hz),
                f_max: None,
            },
        ),
    )
}

/// A phase portrait of the journal's x eccentricity.
pub fn phase(
    dir: &Path,
    figure: &str,
    variant: &str,
    panel: &str,
    t: &[f64],
    p: &PhasePortrait,
    caption: &str,
) -> FigureFile {
    let tab = table(
        "phase",
        &["t", "value", "rate"],
        vec![t.to_vec(), p.value.clone(), p.rate.clone()],
    );
    finish(
        dir,
        figure,
        variant,
        panel,
        caption,
        figures::phase(&tab, Some("B.ex")),
    )
}

/// The Lyapunov exponent's running estimate.
pub fn lyapunov(
    dir: &Path,
    figure: &str,
    variant: &str,
    panel: &str,
    e: &LyapunovEstimate,
    caption: &str,
) -> FigureFile {
    let (t, l): (Vec<f64>, Vec<f64>) = e.history.iter().copied().unzip();
    let tab = table("lyapunov", &["t", "lambda"], vec![t, l]);
    finish(
        dir,
        figure,
        variant,
        panel,
        caption,
        figures::lyapunov(&tab),
    )
}

/// The bifurcation diagram from rows (index, clearance (mm), turn, B.ex (m)).
pub fn bifurcation(dir: &Path, variant: &str, rows: &[[f64; 4]], caption: &str) -> FigureFile {
    let col = |j: usize| rows.iter().map(|r| r[j]).collect::<Vec<f64>>();
    let tab = table(
        "sweep",
        &["index", "clearance c (mm)", "turn", "B.ex"],
        vec![col(0), col(1), col(2), col(3)],
    );
    finish(
        dir,
        "fig6",
        variant,
        "a",
        caption,
        figures::bifurcation(&tab),
    )
}
