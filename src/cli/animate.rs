//! `linkdyn animate MODEL|RESULT --out F.html|F.svg|F.gif`: the mechanism in motion. A model
//! file (`.toml`) is run first with the usual run options, in memory; a result CSV of
//! `linkdyn run` is drawn with the model its provenance names. Frames, drawing and files are in
//! [`linkdyn::animate`]; this file only maps arguments onto it.

use super::args::SolveArgs;
use super::{EXIT_BAD_INPUT, Failure, in_model};
use clap::Args;
use linkdyn::animate::{Animation, AnimationOptions, Format};
use linkdyn::plot::{Table, figures};
use linkdyn::simulation::{FormulationKind, Simulation};
use std::path::{Path, PathBuf};

/// Arguments of `animate`.
#[derive(Debug, Args)]
pub struct AnimateArgs {
    /// A model file (`.toml`, run first) or a result CSV of `linkdyn run`.
    input: PathBuf,
    /// Output: `.html` (one self-contained page with player controls), `.svg` (animated SVG)
    /// or `.gif`.
    #[arg(long)]
    out: PathBuf,
    /// Frames per second of playback; default 30, for a GIF 20 (a GIF frame lasts a whole
    /// number of centiseconds: the rate is rounded to fit).
    #[arg(long)]
    fps: Option<f64>,
    /// Playback length at 1× (s); default 4 s per driver turn, 2 to 120 s.
    #[arg(long)]
    duration: Option<f64>,
    /// Most frames (the frame rate is lowered to fit); default 600, for a GIF 300.
    #[arg(long)]
    max_frames: Option<usize>,
    /// Factor on clearance circles, journal offsets and journal paths.
    #[arg(long, default_value_t = 100.0)]
    magnify: f64,
    /// Contact-force arrows in metres of arrow per newton; default: the 90th percentile of the
    /// run's contact forces spans 15 % of the mechanism.
    #[arg(long, value_name = "M_PER_N")]
    force_scale: Option<f64>,
    /// Picture size WIDTHxHEIGHT in pixels; default 800x600, for a GIF 640x480.
    #[arg(long, value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// Title instead of the model name.
    #[arg(long)]
    title: Option<String>,
    #[command(flatten)]
    solve: SolveArgs,
    /// Equations of motion (model files only): `dae`, `reduced` (the four-bar with one
    /// clearance joint) or `generalized`.
    #[arg(long, value_parser = super::run::parse_formulation, default_value = "dae")]
    formulation: FormulationKind,
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("`{s}`: expected WIDTHxHEIGHT in pixels, e.g. 800x600");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    Ok((w, h))
}

fn is_model(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case("toml"))
}

/// Runs the model file `path` in memory; the result as a table named after the model file.
fn run_model(args: &AnimateArgs) -> Result<(linkdyn::model::Model, Table), Failure> {
    let model = super::load_model(&args.input, &args.solve.set, &args.solve.ideal)?;
    let options = args.solve.options()?.formulation(args.formulation);
    let sim = Simulation::new(&model, options).map_err(|e| in_model(&args.input, e))?;
    let run = sim.run_to_memory().map_err(Failure::from)?;
    let mut names = vec!["t".to_string()];
    names.extend(run.names.iter().cloned());
    let mut columns = vec![run.t];
    columns.extend(run.columns);
    let table = Table {
        path: args.input.clone(),
        comments: Vec::new(),
        names,
        columns,
    };
    Ok((model, table))
}

/// Reads a result file and the model its provenance names. Run options are refused: the run
/// is already made.
fn read_result(args: &AnimateArgs) -> Result<(linkdyn::model::Model, Table), Failure> {
    let s = &args.solve;
    if s.t_end.is_some() || s.revs.is_some() || !s.set.is_empty() || !s.ideal.is_empty() {
        return Err(Failure {
            code: EXIT_BAD_INPUT,
            message: format!(
                "{}: --t-end, --revs, --set and --ideal apply to a model file (.toml), not to a result file",
                args.input.display()
            ),
        });
    }
    let table = super::read_result(&args.input)?;
    let (model, _) = figures::model_from_provenance(&table).map_err(|reason| Failure {
        code: EXIT_BAD_INPUT,
        message: format!("{}: {reason}", args.input.display()),
    })?;
    Ok((model, table))
}

/// Runs `animate`.
pub fn run(args: &AnimateArgs) -> Result<(), Failure> {
    // Refuse an unknown format before running anything.
    let format = Format::from_path(&args.out)?;
    linkdyn::output::check_output_file(&args.out, Some(&args.input))?;
    let gif = format == Format::Gif;
    let mut fps = args.fps.unwrap_or(if gif { 20.0 } else { 30.0 });
    if gif && fps.is_finite() && fps > 0.0 {
        // A GIF frame lasts a whole number of centiseconds.
        fps = 100.0 / (100.0 / fps).round().max(2.0);
    }
    let options = AnimationOptions {
        size: args
            .size
            .unwrap_or(if gif { (640, 480) } else { (800, 600) }),
        fps,
        duration: args.duration,
        max_frames: args.max_frames.unwrap_or(if gif { 300 } else { 600 }),
        magnify: args.magnify,
        force_scale: args.force_scale,
        title: args.title.clone(),
    };
    let (model, table) = if is_model(&args.input) {
        run_model(args)?
    } else {
        read_result(args)?
    };
    let movie = Animation::build(&model, &table, &options)?;
    linkdyn::animate::write(&movie, &args.out)?;
    let (t0, t1) = (
        movie.frames.first().map_or(0.0, |f| f.t),
        movie.frames.last().map_or(0.0, |f| f.t),
    );
    eprintln!(
        "{}: {} frames of t = {} to {} s, {:.1} s at {:.1} fps (1×)",
        args.out.display(),
        movie.frames.len(),
        linkdyn::animate::seconds(t0),
        linkdyn::animate::seconds(t1),
        movie.duration(),
        movie.fps
    );
    Ok(())
}
