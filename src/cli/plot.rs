//! `linkdyn plot KIND FILE… --out F.png|F.svg`: a figure from linkdyn's CSV result files
//! (format from the extension). Reading, figure building and drawing are in
//! [`linkdyn::plot`]; this file only maps arguments onto it.

use super::{EXIT_BAD_INPUT, EXIT_OUTPUT, Failure};
use clap::{Args, Subcommand};
use linkdyn::plot::continuation::{Branch, continuation};
use linkdyn::plot::{Figure, PlotError, SpectrumOptions, Table, figures, render};
use std::path::{Path, PathBuf};

/// Arguments of `plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    #[command(subcommand)]
    kind: Kind,
}

/// Options every figure takes.
#[derive(Debug, Args)]
struct Common {
    /// Output figure: `.png` (1200×800 px by default) or `.svg`.
    #[arg(long)]
    out: PathBuf,
    /// Figure size in pixels, WIDTHxHEIGHT.
    #[arg(long, value_parser = parse_size, default_value = "1200x800")]
    size: (u32, u32),
    /// Title instead of the generated one.
    #[arg(long)]
    title: Option<String>,
    /// Horizontal axis range LOW,HIGH in the axis's units (e.g. `0,100`); data outside is cut.
    #[arg(long, value_name = "LOW,HIGH", allow_hyphen_values = true)]
    xlim: Option<String>,
    /// Vertical axis range LOW,HIGH in the axis's units (e.g. `-0.5,0.5`).
    #[arg(long, value_name = "LOW,HIGH", allow_hyphen_values = true)]
    ylim: Option<String>,
    /// Size of tick and legend text in points (1 pt = 1 px); axis labels are 1.2 and the title
    /// 1.5 times as large. Default 20.
    #[arg(long, value_name = "PT", allow_hyphen_values = true)]
    font_size: Option<f64>,
    /// Legend name of a file's data, one per file in order (FILE, then --compare); default:
    /// the model and its --set overrides from the file's provenance.
    #[arg(long, value_name = "NAME")]
    label: Vec<String>,
}

/// Smallest and largest accepted `--font-size` (pt): below, digits are unreadable at any
/// figure size; above, eight tick labels no longer fit a 1200 px axis.
const FONT_SIZE_PT: (f64, f64) = (6.0, 72.0);

/// Parses an axis range `LOW,HIGH` given to `option`, or says what was expected.
fn parse_limits(option: &str, text: &str) -> Result<(f64, f64), Failure> {
    let bad = |why: &str| Failure {
        code: EXIT_BAD_INPUT,
        message: format!(
            "{option}: expected two numbers LOW,HIGH with LOW < HIGH (e.g. {option} 0,100), got `{text}`{why}"
        ),
    };
    let Some((lo, hi)) = text.split_once(',') else {
        return Err(bad(""));
    };
    let (Ok(lo), Ok(hi)) = (lo.trim().parse::<f64>(), hi.trim().parse::<f64>()) else {
        return Err(bad(""));
    };
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(bad(": both must be finite"));
    }
    if lo >= hi {
        return Err(bad(": LOW is not below HIGH"));
    }
    Ok((lo, hi))
}

impl Common {
    /// Applies the options every figure takes (size, title, ranges, font size) to `fig`.
    fn apply(&self, fig: &mut Figure) -> Result<(), Failure> {
        fig.size = self.size;
        if let Some(t) = &self.title {
            fig.title.clone_from(t);
        }
        for (option, text, axis) in [
            ("--xlim", &self.xlim, &mut fig.x),
            ("--ylim", &self.ylim, &mut fig.y),
        ] {
            if let Some(text) = text {
                let (lo, hi) = parse_limits(option, text)?;
                if axis.log && lo <= 0.0 {
                    return Err(Failure {
                        code: EXIT_BAD_INPUT,
                        message: format!(
                            "{option}: expected a positive LOW on a logarithmic axis, got `{text}`"
                        ),
                    });
                }
                axis.range = Some((lo, hi));
            }
        }
        if let Some(pt) = self.font_size {
            let (min, max) = FONT_SIZE_PT;
            if !(min..=max).contains(&pt) {
                return Err(Failure {
                    code: EXIT_BAD_INPUT,
                    message: format!("--font-size: expected {min} to {max} pt, got {pt}"),
                });
            }
            fig.font_size = pt;
        }
        Ok(())
    }

    /// The single-file figures' `--label`: at most one, naming the data in a legend.
    fn label_one(&self, fig: &mut Figure, table: &Table) -> Result<(), Failure> {
        figures::check_labels(&self.label, &[table])?;
        if let Some(label) = self.label.first() {
            fig.label_data(label);
        }
        Ok(())
    }
}

#[derive(Debug, Subcommand)]
enum Kind {
    /// Time histories of columns of a run, optionally against a second run.
    Series {
        /// Result CSV of `linkdyn run`.
        file: PathBuf,
        /// Columns to draw, comma-separated (e.g. `motor.torque` or `B.ex,B.ey`).
        #[arg(long, value_delimiter = ',', required = true)]
        y: Vec<String>,
        /// A second run (e.g. the ideal mechanism with the same settings) drawn on the same axes.
        #[arg(long)]
        compare: Option<PathBuf>,
        #[command(flatten)]
        common: Common,
    },
    /// Journal-centre orbit of a clearance joint inside its clearance circle (mm, equal scales).
    Orbit {
        /// Result CSV of `linkdyn run` with the joint's `.ex` and `.ey` columns.
        file: PathBuf,
        /// The clearance joint.
        #[arg(long)]
        joint: String,
        /// Radial clearance (m); default: read from the model named in the file's provenance.
        #[arg(long)]
        clearance: Option<f64>,
        #[command(flatten)]
        common: Common,
    },
    /// Poincaré section (`turn,t,<columns>`): one dot per crossing.
    Poincare {
        /// Section CSV.
        file: PathBuf,
        /// Column on the horizontal axis.
        #[arg(long)]
        x: String,
        /// Column on the vertical axis.
        #[arg(long)]
        y: String,
        /// Radial clearance (m): the smallest span of length axes. Default: read from the
        /// model in the file's provenance for `<joint>.ex`/`.ey` columns, else a thousandth of
        /// the largest value.
        #[arg(long)]
        clearance: Option<f64>,
        #[command(flatten)]
        common: Common,
    },
    /// Bifurcation diagram (`index,<parameter>,turn,<column>`): observed value against parameter.
    Bifurcation {
        /// Sweep CSV.
        file: PathBuf,
        #[command(flatten)]
        common: Common,
    },
    /// Amplitude spectrum (`frequency_hz,amplitude`).
    Spectrum {
        /// Spectrum CSV.
        file: PathBuf,
        /// Logarithmic amplitude axis.
        #[arg(long)]
        log: bool,
        /// Driving frequency (Hz): its multiples are marked. Default: the file's
        /// `driving_frequency_hz` provenance line, if any.
        #[arg(long, allow_hyphen_values = true)]
        driving_hz: Option<f64>,
        /// Highest frequency drawn (Hz). Default: 25 × the driving frequency when known,
        /// otherwise every bin.
        #[arg(long, value_name = "HZ", allow_hyphen_values = true)]
        fmax: Option<f64>,
        #[command(flatten)]
        common: Common,
    },
    /// Phase portrait (`t,value,rate`): rate against value.
    Phase {
        /// Phase-portrait CSV.
        file: PathBuf,
        /// The output the file was made from (e.g. `B.ex`), for axis names and units.
        #[arg(long)]
        value_name: Option<String>,
        #[command(flatten)]
        common: Common,
    },
    /// The mechanism at one instant of a run (model from the file's provenance), clearances
    /// magnified: the frame `linkdyn animate` shows at that time.
    Mechanism {
        /// Result CSV of `linkdyn run` (with the `<body>.x`, `.y`, `.phi` columns).
        file: PathBuf,
        /// Time (s), interpolated between samples.
        #[arg(long, default_value_t = 0.0)]
        time: f64,
        /// Factor on clearance circles and journal offsets.
        #[arg(long, default_value_t = 100.0)]
        magnify: f64,
        #[command(flatten)]
        common: Common,
    },
    /// A branch of periodic orbits from `linkdyn continue` (stable solid, unstable dashed,
    /// special points marked), optionally over a `linkdyn bifurcation` diagram of the same
    /// parameter.
    Continuation {
        /// Branch CSV of `linkdyn continue`.
        file: PathBuf,
        /// Bifurcation-diagram CSV (`index,<parameter>,turn,<column>`) of the same parameter,
        /// drawn under the branch.
        #[arg(long, value_name = "BIFURCATION_CSV")]
        over: Option<PathBuf>,
        /// The branch's state column drawn (e.g. `rocker.phi`). Default: the diagram's
        /// column; required without --over.
        #[arg(long, value_name = "NAME")]
        coordinate: Option<String>,
        #[command(flatten)]
        common: Common,
    },
    /// Running estimate of the largest Lyapunov exponent (`t,lambda`) against time.
    Lyapunov {
        /// Lyapunov-history CSV.
        file: PathBuf,
        #[command(flatten)]
        common: Common,
    },
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("`{s}`: expected WIDTHxHEIGHT in pixels, e.g. 1200x800");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if !(200..=20_000).contains(&w) || !(150..=20_000).contains(&h) {
        return Err(format!("`{s}`: between 200x150 and 20000x20000 pixels"));
    }
    Ok((w, h))
}

impl From<PlotError> for Failure {
    fn from(e: PlotError) -> Self {
        Failure {
            code: if e.is_bad_input() {
                EXIT_BAD_INPUT
            } else {
                EXIT_OUTPUT
            },
            message: e.to_string(),
        }
    }
}

/// Runs `plot`.
pub fn run(args: &PlotArgs) -> Result<(), Failure> {
    let read = |p: &Path| super::read_result(p);
    let (mut fig, common): (Figure, &Common) = match &args.kind {
        Kind::Series {
            file,
            y,
            compare,
            common,
        } => {
            let run = read(file)?;
            let other = compare.as_deref().map(read).transpose()?;
            let mut tables = vec![&run];
            tables.extend(other.as_ref());
            (figures::series(&tables, y, &common.label)?, common)
        }
        Kind::Orbit {
            file,
            joint,
            clearance,
            common,
        } => {
            let run = read(file)?;
            let c = match clearance {
                Some(c) => *c,
                None => figures::clearance_from_provenance(&run, joint)?,
            };
            let mut fig = figures::orbit(&run, joint, c)?;
            common.label_one(&mut fig, &run)?;
            (fig, common)
        }
        Kind::Poincare {
            file,
            x,
            y,
            clearance,
            common,
        } => {
            let table = read(file)?;
            // A section of a clearance joint's eccentricities is shown at least as wide as
            // the clearance, when the model in the provenance says what it is.
            let joint = [x, y]
                .into_iter()
                .find_map(|c| c.strip_suffix(".ex").or_else(|| c.strip_suffix(".ey")));
            let c = clearance
                .or_else(|| joint.and_then(|j| figures::clearance_from_provenance(&table, j).ok()));
            let mut fig = figures::poincare(&table, x, y, c)?;
            common.label_one(&mut fig, &table)?;
            (fig, common)
        }
        Kind::Bifurcation { file, common } => {
            let table = read(file)?;
            let mut fig = figures::bifurcation(&table)?;
            common.label_one(&mut fig, &table)?;
            (fig, common)
        }
        Kind::Spectrum {
            file,
            log,
            driving_hz,
            fmax,
            common,
        } => {
            let table = read(file)?;
            let options = SpectrumOptions {
                log: *log,
                driving_hz: *driving_hz,
                f_max: *fmax,
            };
            let mut fig = figures::spectrum(&table, &options)?;
            common.label_one(&mut fig, &table)?;
            (fig, common)
        }
        Kind::Phase {
            file,
            value_name,
            common,
        } => {
            let table = read(file)?;
            let mut fig = figures::phase(&table, value_name.as_deref())?;
            common.label_one(&mut fig, &table)?;
            (fig, common)
        }
        Kind::Mechanism {
            file,
            time,
            magnify,
            common,
        } => {
            // A still frame of the animation, drawn by linkdyn::animate rather than plotters:
            // it has no axes, so of the common options only size and title apply.
            for (option, given) in [
                ("--xlim", common.xlim.is_some()),
                ("--ylim", common.ylim.is_some()),
                ("--font-size", common.font_size.is_some()),
                ("--label", !common.label.is_empty()),
            ] {
                if given {
                    return Err(Failure {
                        code: EXIT_BAD_INPUT,
                        message: format!(
                            "{option}: not available for `plot mechanism` (a drawing without axes or legend)"
                        ),
                    });
                }
            }
            let run = read(file)?;
            let (model, _) = figures::model_from_provenance(&run).map_err(|reason| Failure {
                code: EXIT_BAD_INPUT,
                message: format!("{}: {reason}", file.display()),
            })?;
            linkdyn::plot::Format::from_path(&common.out)?;
            let options = linkdyn::animate::AnimationOptions {
                size: common.size,
                magnify: *magnify,
                title: common.title.clone(),
                ..linkdyn::animate::AnimationOptions::default()
            };
            let picture = linkdyn::animate::still(&model, &run, *time, &options)?;
            linkdyn::animate::write_still(&picture, &common.out)?;
            eprintln!("{}", common.out.display());
            return Ok(());
        }
        Kind::Continuation {
            file,
            over,
            coordinate,
            common,
        } => {
            // The legend names stability and special points, not files.
            if !common.label.is_empty() {
                return Err(Failure {
                    code: EXIT_BAD_INPUT,
                    message: "--label: not available for `plot continuation` (its legend names stability and special points)".into(),
                });
            }
            let branch = Branch::read(file)?;
            let diagram = over.as_deref().map(read).transpose()?;
            let fig = continuation(&branch, diagram.as_ref(), coordinate.as_deref())?;
            (fig, common)
        }
        Kind::Lyapunov { file, common } => {
            let table = read(file)?;
            let mut fig = figures::lyapunov(&table)?;
            common.label_one(&mut fig, &table)?;
            (fig, common)
        }
    };
    let out = &common.out;
    // Refuse an unknown format before anything else is written.
    linkdyn::plot::Format::from_path(out)?;
    common.apply(&mut fig)?;
    render(&fig, out)?;
    eprintln!("{}", out.display());
    Ok(())
}
