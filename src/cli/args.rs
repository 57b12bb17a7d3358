//! Arguments shared by `run`, `compare` and the analyses, turned into [`SimulationOptions`]
//! (and, for `--set` and `--ideal`, into the model: [`super::load_model`]).

use super::Failure;
use clap::Args;
use linkdyn::Error;
use linkdyn::simulation::SimulationOptions;
use linkdyn::solve::radau5::LinearSolver;
use linkdyn::solve::{IdaSettings, Method, SolveError, SolverOptions};

/// Time span, sampling and solver settings shared by `run` and `compare`.
#[derive(Debug, Args)]
pub struct SolveArgs {
    /// End time (s).
    #[arg(long, conflicts_with = "revs", allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Number of turns of the (single) driver; default 2.
    #[arg(long, allow_negative_numbers = true)]
    pub revs: Option<f64>,
    /// Output sample interval (s); samples come from the dense output, not from solver steps.
    #[arg(long, default_value_t = 1e-4, allow_negative_numbers = true)]
    pub dt: f64,
    /// Relative tolerance.
    #[arg(long, default_value_t = 1e-8, allow_negative_numbers = true)]
    pub rtol: f64,
    /// Absolute tolerance.
    #[arg(long, default_value_t = 1e-10, allow_negative_numbers = true)]
    pub atol: f64,
    /// Integration method (see the list in `--help`).
    #[arg(long, default_value = "dop853", long_help = method_help())]
    pub method: String,
    /// How the implicit methods factor their Newton matrices: auto (a sparse LU from 40 states
    /// for radau5 and from 60 unknowns for ida, measured; dense below), dense or sparse.
    /// Recorded in the result file's solver settings.
    #[arg(long, value_name = "auto|dense|sparse", default_value = "auto", value_parser = ["auto", "dense", "sparse"])]
    pub linear_solver: String,
    /// Wall-clock budget of the integration (s): a run that takes longer stops with exit 3,
    /// the time it reached and its rate. Default: no limit.
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub max_wall: Option<f64>,
    /// Most step attempts before the solver gives up (with the time it reached).
    #[arg(long, default_value_t = 10_000_000, allow_negative_numbers = true)]
    pub max_steps: u64,
    /// Override a model field: dotted path, array entries by name (repeatable), e.g.
    /// `--set drivers.motor.speed_rpm=3500`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Run this clearance joint as its ideal joint (repeatable): a revolute clearance joint as
    /// an ideal revolute joint, a prismatic-clearance joint as an ideal prismatic one; the ideal
    /// reference from the same model file. Recorded as `joints.NAME.ideal=true` in the provenance.
    #[arg(long, value_name = "JOINT")]
    pub ideal: Vec<String>,
}

/// The `--method` help: every integrator with its one-line description.
fn method_help() -> String {
    let mut text = String::from("Integration method:");
    for m in Method::ALL {
        text.push_str(&format!("\n  {m}: {}", m.description()));
    }
    text.push_str(&format!(
        "\n  ida: {}",
        linkdyn::solve::options::IDA_DESCRIPTION
    ));
    text
}

impl SolveArgs {
    /// The options these arguments ask for (checked against the model by `Simulation::new`).
    pub fn options(&self) -> Result<SimulationOptions, Failure> {
        let method: Method = self.method.parse().map_err(|e| match e {
            SolveError::InvalidOption { option, reason } => Error::Settings { option, reason },
            other => Error::Solve(other),
        })?;
        let linear_solver = match self.linear_solver.as_str() {
            "dense" => LinearSolver::Dense,
            "sparse" => LinearSolver::Sparse,
            _ => LinearSolver::Auto,
        };
        let solver = SolverOptions::default()
            .method(method)
            .rtol(self.rtol)
            .atol(self.atol)
            .max_steps(self.max_steps);
        let solver = SolverOptions {
            radau5: solver.radau5.clone().linear_solver(linear_solver),
            ida: IdaSettings { linear_solver },
            ..solver
        };
        let solver = match self.max_wall {
            Some(seconds) => solver.max_wall(seconds),
            None => solver,
        };
        let options = SimulationOptions::default().dt(self.dt).solver(solver);
        Ok(match (self.t_end, self.revs) {
            (Some(t), _) => options.t_end(t),
            (None, Some(turns)) => options.revs(turns),
            (None, None) => options,
        })
    }
}
