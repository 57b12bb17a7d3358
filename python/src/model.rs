//! `linkdyn.Model`: a loaded, validated model; `run` integrates it with the GIL released.

use crate::errors;
use crate::result::PyResult_;
use linkdyn::Error;
use linkdyn::formulation::{Dae, DaeOptions};
use linkdyn::model::{JointKind, Model};
use linkdyn::simulation::{FormulationKind, Simulation, SimulationOptions};
use linkdyn::solve::{Method, SolveError, SolverOptions};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// A model read from a TOML file (SI units inside), ready to run any number of times.
#[pyclass(name = "Model", module = "linkdyn", frozen)]
pub struct PyModel {
    model: Model,
    path: String,
}

impl PyModel {
    /// Wraps a loaded model; `path` is the file as the caller gave it (for messages).
    pub fn new(model: Model, path: String) -> Self {
        PyModel { model, path }
    }
}

/// Settings of one run, as given from Python.
struct RunSettings {
    t_end: Option<f64>,
    revs: Option<f64>,
    dt: f64,
    formulation: String,
    method: String,
    rtol: f64,
    atol: f64,
    energy: bool,
    max_steps: u64,
}

impl RunSettings {
    /// The library's options, checked in the command line's order (method, end time, then
    /// everything else in `Simulation::new`).
    fn options(&self) -> Result<SimulationOptions, Error> {
        let method: Method = self.method.parse().map_err(|e| match e {
            SolveError::InvalidOption { option, reason } => Error::Settings { option, reason },
            other => Error::Solve(other),
        })?;
        let formulation: FormulationKind = self.formulation.parse()?;
        let solver = SolverOptions::default()
            .method(method)
            .rtol(self.rtol)
            .atol(self.atol)
            .max_steps(self.max_steps);
        let options = SimulationOptions::default()
            .dt(self.dt)
            .solver(solver)
            .formulation(formulation)
            .energy(self.energy);
        match (self.t_end, self.revs) {
            (Some(_), Some(_)) => Err(Error::settings("revs", "give `t_end` or `revs`, not both")),
            (Some(t), None) => Ok(options.t_end(t)),
            (None, Some(turns)) => Ok(options.revs(turns)),
            (None, None) => Ok(options),
        }
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

    /// Things to know that are not errors, one sentence each (e.g. the fields a `set=` that
    /// switched a contact or friction law dropped); the command line prints them as `note:`.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.model.notes.clone()
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

    /// Integrates the model and keeps every sample in memory (see `linkdyn.Model.run`).
    #[pyo3(signature = (*, t_end = None, revs = None, dt = 1e-4, formulation = "dae".to_string(),
        method = "dop853".to_string(), rtol = 1e-8, atol = 1e-10, energy = false,
        max_steps = 10_000_000))]
    #[allow(clippy::too_many_arguments)]
    fn run(
        &self,
        py: Python<'_>,
        t_end: Option<f64>,
        revs: Option<f64>,
        dt: f64,
        formulation: String,
        method: String,
        rtol: f64,
        atol: f64,
        energy: bool,
        max_steps: u64,
    ) -> PyResult<PyResult_> {
        let settings = RunSettings {
            t_end,
            revs,
            dt,
            formulation,
            method,
            rtol,
            atol,
            energy,
            max_steps,
        };
        let model = &self.model;
        // Everything from the settings check to the last sample runs without the GIL: other
        // Python threads (and other runs) go on meanwhile.
        let (run, clearance) = py
            // The error is boxed: `linkdyn::Error` is large and the Ok path should not pay for it.
            .detach(|| -> Result<_, Box<(Error, bool)>> {
                let options = settings.options().map_err(|e| Box::new((e, false)))?;
                let sim = Simulation::new(model, options).map_err(|e| Box::new((e, true)))?;
                let run = sim.run_to_memory().map_err(|e| Box::new((e, false)))?;
                Ok((run, sim.clearance_joints().to_vec()))
            })
            .map_err(|failure| {
                let (e, building) = *failure;
                errors::to_py(py, e, building.then_some(self.path.as_str()))
            })?;
        PyResult_::new(py, run, clearance)
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
