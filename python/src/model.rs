//! `linkdyn.Model`: a loaded, validated model; `run` integrates it and the analyses
//! (`poincare`, `bifurcation`, `spectrum`, `phase`, `lyapunov`) run on it, all with the GIL
//! released.

use crate::analyses::{self, LyapunovArgs, PoincareArgs, WindowArgs};
use crate::errors::{self, Failed};
use crate::orbit;
use crate::result::PyResult_;
use crate::settings::{Solve, columns};
use crate::sweep::{self, Progress, SweepArgs};
use linkdyn::Error;
use linkdyn::formulation::{Dae, DaeOptions};
use linkdyn::model::{JointKind, Model, ModelError};
use linkdyn::simulation::Simulation;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// A model read from a TOML file (SI units inside), ready to run any number of times.
#[pyclass(name = "Model", module = "linkdyn", frozen)]
pub struct PyModel {
    model: Model,
    /// The model file as given, or the name a model from text goes by in messages.
    path: String,
    /// The model's text (before the overrides) where it did not come from a file.
    text: Option<String>,
}

impl PyModel {
    /// Wraps a model loaded from a file; `path` is the file as the caller gave it.
    pub fn new(model: Model, path: String) -> Self {
        PyModel {
            model,
            path,
            text: None,
        }
    }

    /// Wraps a model loaded from `text` (`loads`, `from_dict`); `name` stands for the file in
    /// messages and provenance.
    pub fn from_text(model: Model, name: String, text: String) -> Self {
        PyModel {
            model,
            path: name,
            text: Some(text),
        }
    }

    /// The model's text before the overrides: the text given, or the file read again, which
    /// must be unchanged since it was loaded (its SHA-256 is in every result's provenance).
    fn source_text(&self) -> Result<String, ModelError> {
        if let Some(text) = &self.text {
            return Ok(text.clone());
        }
        let text = linkdyn::model::read(self.path.as_ref())?;
        if linkdyn::model::text_sha256(&text) != self.model.source.sha256 {
            return Err(ModelError::WholeFile {
                file: self.path.clone(),
                message: "the model file changed since it was loaded; load it again".into(),
            });
        }
        Ok(text)
    }

    /// The model file's text with the overrides applied: what `to_toml` returns.
    fn effective_text(&self) -> Result<String, ModelError> {
        let text = self.source_text()?;
        linkdyn::model::effective_text(&text, &self.path, &self.model.source.overrides)
    }
}

#[pymethods]
impl PyModel {
    /// Model name (`name` in the file).
    #[getter]
    fn name(&self) -> &str {
        &self.model.name
    }

    /// Model description (may be empty).
    #[getter]
    fn description(&self) -> &str {
        &self.model.description
    }

    /// The model file as given to `load`.
    #[getter]
    fn path(&self) -> &str {
        &self.path
    }

    /// The overrides applied at load time (`"KEY=VALUE"`, in order).
    #[getter]
    fn overrides(&self) -> Vec<String> {
        self.model.source.overrides.clone()
    }

    /// A copy of the model with more overrides applied after the load-time ones, as more
    /// `--set KEY=VALUE` would: `model.set("joints.B.clearance", 4e-4)`, or one dict
    /// `model.set({"joints.B.clearance": 4e-4, "drivers.motor.speed_rpm": 3500})` (values as
    /// `load`'s `set=`). The model itself is not changed. Raises `ModelError` as `load` does;
    /// a new warning is issued as a `UserWarning`.
    #[pyo3(signature = (key, value = None))]
    fn set(
        &self,
        py: Python<'_>,
        key: &Bound<'_, PyAny>,
        value: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyModel> {
        let given = match value {
            Some(v) => {
                let d = PyDict::new(py);
                d.set_item(key, v)?;
                d.into_any()
            }
            None => key.clone(),
        };
        // The package's own conversion of `set=` values, so both spell a value alike.
        let added: Vec<String> = py
            .import("linkdyn")?
            .getattr("_overrides")?
            .call1((given,))?
            .extract()?;
        let mut overrides = self.model.source.overrides.clone();
        overrides.extend(added);
        let loaded = py.detach(|| {
            let text = self.source_text()?;
            linkdyn::model::load_str(&text, &self.path, &overrides)
        });
        let model = loaded.map_err(|e| errors::to_py(py, Error::from(e), None))?;
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        for text in model
            .warnings
            .iter()
            .filter(|w| !self.model.warnings.contains(w))
        {
            let text = std::ffi::CString::new(text.as_str()).unwrap_or_default();
            PyErr::warn(py, &category, &text, 1)?;
        }
        Ok(PyModel {
            model,
            path: self.path.clone(),
            text: self.text.clone(),
        })
    }

    /// The model as TOML text that `linkdyn` (the command) and `linkdyn.loads` read to the
    /// same model, overrides included (`linkdyn run model.toml` then gives this model's
    /// numbers, bit for bit). Without overrides, the text as loaded, comments and all; with
    /// them, the document written anew without comments. A model from a file needs the file
    /// unchanged since it was loaded (else `ModelError`).
    fn to_toml(&self, py: Python<'_>) -> PyResult<String> {
        py.detach(|| self.effective_text())
            .map_err(|e| errors::to_py(py, Error::from(e), None))
    }

    /// The model file's tables as a dict (as `tomllib.loads(model.to_toml())` gives it): edit
    /// it and hand it to `linkdyn.from_dict` to build the edited model.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let text = py
            .detach(|| self.effective_text())
            .map_err(|e| errors::to_py(py, Error::from(e), None))?;
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            errors::to_py(
                py,
                Error::from(ModelError::WholeFile {
                    file: self.path.clone(),
                    message: e.message().trim().to_string(),
                }),
                None,
            )
        })?;
        crate::document::to_py(py, &table)
    }

    /// Things to know that are not errors, one sentence each (e.g. the fields a `set=` that
    /// switched a contact or friction law dropped); the command line prints them as `note:`.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.model.notes.clone()
    }

    /// Values that are valid but more likely a unit slip than meant (an angle field of more
    /// than a turn, a driver speed that no linkage of the model's size runs at), one sentence
    /// each; the command line prints them as `warning:`. Loading also issues each as a Python
    /// `UserWarning`.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.model.warnings.clone()
    }

    /// Parameters of the model file's `[parameters]` table as evaluated, after the load-time
    /// overrides (`set={"parameters.N": 5}`): name → value (SI, as the expressions use them).
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, value) in &self.model.parameters {
            d.set_item(name, value)?;
        }
        Ok(d)
    }

    /// Output points (`[[outputs]]`): their names, in order; each adds the result columns
    /// `P.x P.y P.vx P.vy P.ax P.ay` (m, m/s, m/s², global frame).
    #[getter]
    fn outputs(&self) -> Vec<String> {
        self.model.outputs.iter().map(|o| o.name.clone()).collect()
    }

    /// SHA-256 of the model file (hex), as recorded in every result's provenance.
    #[getter]
    fn sha256(&self) -> &str {
        &self.model.source.sha256
    }

    /// Bodies: one dict each with `name`, `mass` (kg), `inertia` (kg·m², about the centre of
    /// mass) and `points` (name → local [x, y] in m).
    #[getter]
    fn bodies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for b in &self.model.bodies {
            let d = PyDict::new(py);
            d.set_item("name", &b.name)?;
            d.set_item("mass", b.mass)?;
            d.set_item("inertia", b.inertia)?;
            let points = PyDict::new(py);
            for (n, p) in &b.points {
                points.set_item(n, p.to_vec())?;
            }
            d.set_item("points", points)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// Joints: one dict each with `name`, `type` (`revolute`, `clearance`, …), `a` and `b`
    /// (`"frame.point"`), and for a clearance joint `clearance` and `journal_radius` (m).
    #[getter]
    fn joints<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let m = &self.model;
        let list = PyList::empty(py);
        for j in &m.joints {
            let d = PyDict::new(py);
            d.set_item("name", &j.name)?;
            d.set_item("type", j.kind.type_name())?;
            d.set_item("a", format!("{}.{}", m.frame_name(j.a.frame), j.a.point))?;
            d.set_item("b", format!("{}.{}", m.frame_name(j.b.frame), j.b.point))?;
            if let JointKind::Clearance(c) = &j.kind {
                d.set_item("clearance", c.clearance)?;
                d.set_item("journal_radius", c.journal_radius)?;
            }
            list.append(d)?;
        }
        Ok(list)
    }

    /// Drivers: one dict each with `name`, `joint`, `speed` (rad/s), `speed_rpm` and
    /// `initial_angle` (rad).
    #[getter]
    fn drivers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for drv in &self.model.drivers {
            let d = PyDict::new(py);
            d.set_item("name", &drv.name)?;
            d.set_item("joint", &self.model.joint(drv.joint).name)?;
            d.set_item("speed", drv.speed)?;
            d.set_item("speed_rpm", drv.speed * 30.0 / std::f64::consts::PI)?;
            d.set_item("initial_angle", drv.initial_angle)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// Force elements: one dict each with `name` and `type` (`spring-damper`, `torque`,
    /// `force`).
    #[getter]
    fn forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        for f in &self.model.forces {
            let (name, kind) = (f.name(), f.type_name());
            let d = PyDict::new(py);
            d.set_item("name", name)?;
            d.set_item("type", kind)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// Names of the clearance joints, in model order (the order of their events).
    #[getter]
    fn clearance_joints(&self) -> Vec<String> {
        linkdyn::simulation::clearance_joint_names(&self.model)
    }

    /// What `linkdyn check` prints, as a dict: `coordinates`, `constraint_rows`, `rank`,
    /// `degrees_of_freedom`, `redundant_constraints` (row names), `assembly_iterations`,
    /// `assembly_residual` (max |Φ| after assembly) and `assembled` (body → [x, y, φ] in m,
    /// m, rad). Assembles the linkage; raises `ModelError` if it cannot.
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let model = &self.model;
        let dae = py
            .detach(|| Dae::new(model, &DaeOptions::default()))
            .map_err(|e| errors::to_py(py, e.into(), Some(&self.path)))?;
        let set = dae.constraints();
        let redundant: Vec<String> = dae
            .redundant_rows()
            .iter()
            .map(|&k| set.row_name(model, k))
            .collect();
        let rank = set.n_rows() - redundant.len();
        let a = dae.assembly();
        let d = PyDict::new(py);
        d.set_item("coordinates", dae.n_coordinates())?;
        d.set_item("constraint_rows", set.n_rows())?;
        d.set_item("rank", rank)?;
        d.set_item("degrees_of_freedom", dae.n_coordinates() - rank)?;
        d.set_item("redundant_constraints", redundant)?;
        d.set_item("assembly_iterations", a.iterations)?;
        d.set_item("assembly_residual", a.residual)?;
        let assembled = PyDict::new(py);
        for (b, q) in model.bodies.iter().zip(a.q.chunks_exact(3)) {
            assembled.set_item(&b.name, q.to_vec())?;
        }
        d.set_item("assembled", assembled)?;
        Ok(d)
    }

    /// Degrees of freedom of the assembled linkage (coordinates − rank of the constraints).
    #[getter]
    fn degrees_of_freedom(&self, py: Python<'_>) -> PyResult<usize> {
        match self.check(py)?.get_item("degrees_of_freedom")? {
            Some(v) => v.extract(),
            None => Ok(0),
        }
    }

    /// Integrates the model and keeps every sample in memory (`linkdyn run`): end time
    /// `t_end` (s) or `revs` driver turns (default 2), `energy` bookkeeping, and the solve
    /// settings ([`Solve::from_kwargs`]): samples every `dt` s, `formulation` "dae",
    /// "reduced" or "generalized", `method`, tolerances `rtol`/`atol`, at most `max_steps`
    /// step attempts and `max_wall` s. Returns a
    /// `linkdyn.Result`; the GIL is released for the whole run. Raises `SettingsError`,
    /// `ModelError`, `SolverError`.
    #[pyo3(signature = (*, t_end = None, revs = None, energy = false, **solve))]
    fn run(
        &self,
        py: Python<'_>,
        t_end: Option<f64>,
        revs: Option<f64>,
        energy: bool,
        solve: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<PyResult_> {
        let solve = Solve::from_kwargs("run", solve)?;
        let model = &self.model;
        // Everything from the settings check to the last sample runs without the GIL: other
        // Python threads (and other runs) go on meanwhile.
        let (run, clearance) = py
            .detach(|| -> Result<_, Failed> {
                // Checked in the command line's order: method, end time, then everything else
                // in `Simulation::new`.
                let options = solve.options()?.energy(energy);
                let options = match (t_end, revs) {
                    (Some(_), Some(_)) => {
                        return Err(
                            Error::settings("revs", "give `t_end` or `revs`, not both").into()
                        );
                    }
                    (Some(t), None) => options.t_end(t),
                    (None, Some(turns)) => options.revs(turns),
                    (None, None) => options,
                };
                let sim = Simulation::new(model, options).map_err(Failed::building)?;
                let run = sim.run_to_memory()?;
                Ok((run, sim.clearance_joints().to_vec()))
            })
            .map_err(|f| f.into_py(py, &self.path))?;
        PyResult_::new(py, run, clearance)
    }

    /// Poincaré section once per driver turn, with its period verdict (`linkdyn poincare`).
    ///
    /// Integrates `revs` turns (a whole number ≥ 1, default 2) and records, for turns
    /// k = `transient` … revs − 1, the `observe` columns (a list, or a string split at commas;
    /// default: every state, named `y[i]`) at the exact instants t_k = t0 + `phase`/|ω| + k·T
    /// (`phase` in rad, in [0, 2π); T = 2π/|ω| of the single driver), from the dense output.
    /// The verdict (period-k, no period, not settled) compares points within 1000 times the
    /// integration tolerance carried to each column. Solve settings as `run` (no `t_end`).
    /// Returns a `linkdyn.PoincareSection`; the GIL is released while Rust integrates.
    ///
    /// Raises `SettingsError`, `ModelError`, `SolverError` (with `time`).
    #[pyo3(signature = (*, revs = None, transient = 0, phase = 0.0, observe = None, **solve))]
    fn poincare<'py>(
        &self,
        py: Python<'py>,
        revs: Option<f64>,
        transient: i64,
        phase: f64,
        observe: Option<&Bound<'py, PyAny>>,
        solve: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let solve = Solve::from_kwargs("poincare", solve)?;
        let args = PoincareArgs {
            revs,
            transient,
            phase,
            observe: columns(observe)?,
        };
        analyses::poincare(py, &self.model, &self.path, &solve, args)
    }

    /// Bifurcation diagram (`linkdyn bifurcation`): the model field `param` (a `set=` path,
    /// e.g. `"joints.B.clearance"`, in the field's unit in the model file) takes each value
    /// of the grid `from_` … `to` in `steps` intervals (both ends included) or of the list
    /// `values`; each point reloads the model file with the load-time overrides and
    /// `param=value`, integrates `revs` turns (default 150) and records `observe` once per
    /// turn after `transient` turns (default 100) at `phase`, with the point's period verdict.
    ///
    /// Points run in parallel on `threads` rayon threads (default: one per core) without the
    /// GIL; `shard="i/n"` runs shard i of n (1-based). `progress`: True a tqdm bar (a line on
    /// stderr without tqdm), False/None nothing, or a callable `progress(done, total)`, called
    /// from the calling thread between points with the GIL taken briefly. Ctrl-C or an
    /// exception from the callback stops the sweep (points in flight finish first). A point
    /// that fails does not stop the others: its rows are NaN, its verdict `"failed"` with the
    /// error in `message` (`failures` maps index → message), and a `RuntimeWarning` names the
    /// failed points. Bad input (including a `to` the model refuses) raises before any point
    /// runs. Returns a `linkdyn.Bifurcation` (rows in index order).
    ///
    /// `settle=True` ends each point's transient once its section has settled (after at least
    /// `transient_min` turns, default 5, and at most `transient`); `warm_start=True` (reduced
    /// formulation) starts each point from the state the point before it ended in, the grid
    /// split into `chunks` contiguous chunks swept in `direction` (`"up"`, `"down"` or
    /// `"both"`): the command line's `--settle`, `--transient-min`, `--warm-start`, `--chunks`
    /// and `--direction`, with the same points.
    ///
    /// The model file must be unchanged since `load` and reachable by the path given to it.
    #[pyo3(signature = (param, observe, *, from_ = None, to = None, steps = None, values = None,
        revs = None, transient = 100, phase = 0.0, threads = None, shard = None,
        progress = Progress::Flag(true), settle = false, transient_min = None,
        warm_start = false, chunks = None, direction = None, **solve))]
    #[allow(clippy::too_many_arguments)]
    fn bifurcation<'py>(
        &self,
        py: Python<'py>,
        param: String,
        observe: String,
        from_: Option<f64>,
        to: Option<f64>,
        steps: Option<i64>,
        values: Option<Vec<f64>>,
        revs: Option<f64>,
        transient: i64,
        phase: f64,
        threads: Option<i64>,
        shard: Option<String>,
        progress: Progress,
        settle: bool,
        transient_min: Option<i64>,
        warm_start: bool,
        chunks: Option<i64>,
        direction: Option<String>,
        solve: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let solve = Solve::from_kwargs("bifurcation", solve)?;
        let args = SweepArgs {
            param,
            observe,
            from: from_,
            to,
            steps,
            values,
            revs,
            transient,
            phase,
            threads,
            shard,
            settle,
            transient_min,
            warm_start,
            chunks,
            direction,
            model_text: self.text.clone(),
        };
        sweep::bifurcation(py, &self.model, &self.path, &solve, args, progress)
    }

    /// One-sided amplitude spectrum of output column `observe` (`linkdyn spectrum`): `revs`
    /// turns (default transient + 10) sampled every `dt` s, the first `transient` turns
    /// dropped, Hann window, mean removed; the dominant peaks with their multiple of the
    /// driving frequency |ω|/2π. Returns a `linkdyn.Spectrum` (frequencies in Hz, amplitudes
    /// in the column's unit); the GIL is released while Rust integrates.
    ///
    /// Raises `SettingsError`, `ModelError`, `SolverError`, `AnalysisError` (too few samples).
    #[pyo3(signature = (observe, *, revs = None, transient = 0.0, **solve))]
    fn spectrum<'py>(
        &self,
        py: Python<'py>,
        observe: String,
        revs: Option<f64>,
        transient: f64,
        solve: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let solve = Solve::from_kwargs("spectrum", solve)?;
        let window = WindowArgs { revs, transient };
        analyses::spectrum(py, &self.model, &self.path, &solve, observe, window)
    }

    /// Phase-portrait data of output column `observe` (`linkdyn phase`): its samples after
    /// `transient` turns against its rate, taken from the rate column where the run has one
    /// (`B.phi` → `B.omega`, `B.x` → `B.vx`), else second-order differences. `revs` defaults
    /// to transient + 10. Returns a `linkdyn.PhasePortrait`; the GIL is released while Rust
    /// integrates.
    #[pyo3(signature = (observe, *, revs = None, transient = 0.0, **solve))]
    fn phase<'py>(
        &self,
        py: Python<'py>,
        observe: String,
        revs: Option<f64>,
        transient: f64,
        solve: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let solve = Solve::from_kwargs("phase", solve)?;
        let window = WindowArgs { revs, transient };
        analyses::phase(py, &self.model, &self.path, &solve, observe, window)
    }

    /// Largest Lyapunov exponent (`linkdyn lyapunov`, 1/s): a reference and a perturbed
    /// trajectory from turn `transient`, separated by `d0` in the scaled norm (angles in rad,
    /// positions in units of the longest body arm, velocities × 1/|ω|; bookkeeping states
    /// neither perturbed nor measured), renormalised every `renormalise_every_revs` turns up
    /// to `revs` (default transient + 10; at least 2 intervals). Returns a
    /// `linkdyn.LyapunovExponent` (λ, its batch-means uncertainty, the running estimate); the
    /// GIL is released while Rust integrates.
    #[pyo3(signature = (*, revs = None, transient = 0.0, d0 = 1e-7, renormalise_every_revs = 1.0,
        **solve))]
    fn lyapunov<'py>(
        &self,
        py: Python<'py>,
        revs: Option<f64>,
        transient: f64,
        d0: f64,
        renormalise_every_revs: f64,
        solve: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let solve = Solve::from_kwargs("lyapunov", solve)?;
        let window = WindowArgs { revs, transient };
        let args = LyapunovArgs {
            d0,
            renormalise_every_revs,
        };
        analyses::lyapunov(py, &self.model, &self.path, &solve, window, args)
    }

    /// A periodic orbit by shooting, with its Floquet multipliers (`linkdyn orbit`).
    ///
    /// Newton's method on P^K(x) − x = 0 over the period map of K = `period_turns` driver
    /// turns (default 1; or `period` seconds), from the state after `guess_from_turn` periods
    /// (default 3) of integration; the monodromy matrix from the variational equations with
    /// saltation matrices at the contact events. Solve settings as `run`, with the command's
    /// default `formulation="reduced"` (or `"dae"` for any linkage). Returns a
    /// `linkdyn.PeriodicOrbit` (the keys of the command's `F.json`, and one period of the
    /// orbit as its `F.csv`'s columns); the GIL is released while Rust integrates.
    ///
    /// Raises `SettingsError` (a bad period, the generalized formulation), `ModelError`,
    /// `SolverError` (no orbit found: the message and `residual_history` have the residual
    /// history; or a failed integration).
    #[pyo3(signature = (*, period_turns = None, period = None, guess_from_turn = 3, **solve))]
    fn orbit<'py>(
        &self,
        py: Python<'py>,
        period_turns: Option<i64>,
        period: Option<f64>,
        guess_from_turn: i64,
        solve: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let solve = Solve::from_kwargs_formulation("orbit", solve, "reduced")?;
        let args = orbit::OrbitArgs {
            period_turns,
            period,
            guess_from_turn,
        };
        orbit::periodic_orbit(py, &self.model, &self.path, &solve, args)
    }

    /// The periodic orbit continued in the model field `param` (a `set=` path, in the field's
    /// unit in the model file) from `from_` to `to` (`linkdyn continue`): pseudo-arclength
    /// continuation with steps of at most `step` (default |to − from_|/20), the orbit of
    /// `period_turns` driver turns (default 1) found first at `from_` from the state after
    /// `guess_from_turn` periods (default 3); folds, period doublings, Neimark–Sacker points
    /// and grazings located on the way; `follow_doublings` N (default 0) also continues the
    /// period-2K branch from each located period doubling, N doublings deep (the rows'
    /// `branch` and `turn`). Each point reloads the model with the load-time
    /// overrides and `param=value`. Solve settings as `orbit`. Returns a
    /// `linkdyn.Continuation` (the command's `F.csv` as arrays and its `F.json`'s keys); the
    /// GIL is released while Rust integrates.
    ///
    /// `progress`: True a line on stderr (points so far, the last parameter value, its
    /// branch), False/None nothing, or a callable `progress(point)` called after each point
    /// with a dict (`points`, `branch`, `parameter`, `stable`, `max_abs_mu`, `special`). An
    /// exception from it, or Ctrl-C, ends the branch after the current point and is raised.
    ///
    /// A branch that stops before `to` (no orbit beyond a point with the smallest step, or
    /// too many points) is returned, with a `RuntimeWarning` saying where and why (the
    /// command writes its files and exits 3). Raises `SettingsError` (`to == from_`, a bad
    /// `step` or period), `ModelError` (an unknown `param` or a value the model refuses,
    /// prefixed `param PATH: `), `SolverError` (no orbit at `from_`, or a failed integration).
    #[pyo3(signature = (param, from_, to, *, step = None, period_turns = 1, guess_from_turn = 3,
        follow_doublings = 0, progress = Progress::Flag(true), **solve))]
    #[allow(clippy::too_many_arguments)]
    fn continuation<'py>(
        &self,
        py: Python<'py>,
        param: String,
        from_: f64,
        to: f64,
        step: Option<f64>,
        period_turns: i64,
        guess_from_turn: i64,
        follow_doublings: i64,
        progress: Progress,
        solve: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let solve = Solve::from_kwargs_formulation("continuation", solve, "reduced")?;
        let text = py
            .detach(|| self.source_text())
            .map_err(|e| errors::to_py(py, Error::from(e), None))?;
        let args = orbit::ContinuationArgs {
            param,
            from: from_,
            to,
            step,
            period_turns,
            guess_from_turn,
            follow_doublings,
        };
        orbit::branch(py, &self.model, &self.path, &text, &solve, args, progress)
    }

    /// Archard wear of the model's worn clearance joint (the one with `[joints.wear]`) over
    /// `turns` driver turns, the bearing profile updated every `update_every` turns (default
    /// 1): `linkdyn wear`. DAE formulation only. Returns a `linkdyn.Wear` (the command's
    /// `wear.csv` as arrays, `depth_m` by update and bin, and its `wear.json`'s keys); the GIL
    /// is released while Rust integrates.
    ///
    /// Raises `SettingsError` (another formulation, zero turns, no worn joint or more than one,
    /// a model without one driver), `SolverError` (a failed integration).
    #[pyo3(signature = (turns, *, update_every = 1, **solve))]
    fn wear<'py>(
        &self,
        py: Python<'py>,
        turns: i64,
        update_every: i64,
        solve: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let solve = Solve::from_kwargs("wear", solve)?;
        crate::wear::wear_study(py, &self.model, &self.path, &solve, turns, update_every)
    }

    fn __repr__(&self) -> String {
        format!(
            "<linkdyn.Model {:?} from {:?}: {} bodies, {} joints, {} drivers>",
            self.model.name,
            self.path,
            self.model.bodies.len(),
            self.model.joints.len(),
            self.model.drivers.len()
        )
    }
}
