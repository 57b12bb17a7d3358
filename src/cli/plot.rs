//! `linkdyn plot KIND FILE… --out F.png|F.svg`: a figure from linkdyn's CSV result files
//! (format from the extension). Reading, figure building and drawing are in
//! [`linkdyn::plot`]; this file only maps arguments onto it.

use super::{EXIT_BAD_INPUT, EXIT_OUTPUT, Failure};
use clap::{Args, Subcommand};
use linkdyn::plot::{Figure, PlotError, figures, render};
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
        /// Driving frequency (Hz): its multiples are marked.
        #[arg(long)]
        driving_hz: Option<f64>,
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
            (figures::series(&run, y, other.as_ref())?, common)
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
            (figures::orbit(&run, joint, c)?, common)
        }
        Kind::Poincare { file, x, y, common } => (figures::poincare(&read(file)?, x, y)?, common),
        Kind::Bifurcation { file, common } => (figures::bifurcation(&read(file)?)?, common),
        Kind::Spectrum {
            file,
            log,
            driving_hz,
            common,
        } => (figures::spectrum(&read(file)?, *log, *driving_hz)?, common),
        Kind::Phase {
            file,
            value_name,
            common,
        } => (figures::phase(&read(file)?, value_name.as_deref())?, common),
        Kind::Mechanism {
            file,
            time,
            magnify,
            common,
        } => {
            // A still frame of the animation, drawn by linkdyn::animate rather than plotters.
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
        Kind::Lyapunov { file, common } => (figures::lyapunov(&read(file)?)?, common),
    };
    let out = &common.out;
    // Refuse an unknown format before anything else is written.
    linkdyn::plot::Format::from_path(out)?;
    fig.size = common.size;
    if let Some(t) = &common.title {
        fig.title.clone_from(t);
    }
    render(&fig, out)?;
    eprintln!("{}", out.display());
    Ok(())
}
