//! `prbfit.Scene`: a scene (DESIGN §5, §8, §9) read from a file or text, edited from Python
//! by the scene's own rules, and the commands run on it.

use std::path::PathBuf;
use std::str::FromStr;

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};

use prbfit::beam::{Effects, Load};
use prbfit::fea::{Section, Taper};
use prbfit::fidelity::Fidelity;
use prbfit::format::Format;
use prbfit::prb::PrbMatrix;
use prbfit::report::{self, Control, ReportError};
use prbfit::scene::{EffectsChoice, LoadPath};

use crate::convert::{extract, finite, flag, path, real, text, whole};
use crate::edit;
use crate::errors;
use crate::matrix::Matrix;
use crate::results::{
    Calibration, Evaluation, Export, Fea, Fit, Modes, Report, Selection, Solution,
};
use crate::run::run;

/// A scene: the beam (or a mechanism's flexures, or measured data), its load paths, targets
/// and model. Edits are checked by the scene's rules: a broken one raises `InputError`
/// naming the key and leaves the scene as it was.
#[pyclass(module = "prbfit")]
#[derive(Clone)]
pub struct Scene {
    pub inner: prbfit::scene::Scene,
}

/// The report of `work`, as JSON and text, computed on the worker thread.
fn report_of<R: serde::Serialize + std::fmt::Display>(r: &R) -> report::Result<Report> {
    let value = serde_json::to_value(r)
        .map_err(|e| ReportError::solve(format!("internal error: the report: {e}")))?;
    // As the CLI's --json: a NaN or infinity (which serde_json writes as null, and the
    // results would hand out as None) is refused, never returned.
    if !report::all_finite(&value) {
        return Err(ReportError::solve(
            "internal error: a result is not a finite number",
        ));
    }
    Ok(Report {
        value,
        text: r.to_string(),
    })
}

/// A result of class `C`.
macro_rules! result {
    ($py:expr, $report:expr, $class:expr) => {{
        let init = pyo3::PyClassInitializer::from($report).add_subclass($class);
        Ok(Py::new($py, init)?.into_any())
    }};
}

/// The `fidelity` keyword: a preset's name, `normal` when not given.
fn fidelity_arg(value: Option<&Bound<'_, PyAny>>) -> PyResult<Fidelity> {
    let name = text("fidelity", value)?.unwrap_or_else(|| "normal".into());
    Fidelity::from_str(&name).map_err(|e| errors::input("fidelity", e))
}

fn load_arg(value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Load>> {
    let Some(v) = value else { return Ok(None) };
    let [alpha_x, alpha_y, beta]: [f64; 3] = extract("load", v, "(alpha_x, alpha_y, beta)")?;
    for x in [alpha_x, alpha_y, beta] {
        finite("load", x)?;
    }
    let load = Load {
        alpha_x,
        alpha_y,
        beta,
    };
    // The CLI's `--load` rule: each component within the scene rules' reach.
    prbfit::scene::rules::single_load(&load).map_err(|m| errors::input("load", m))?;
    Ok(Some(load))
}

/// A model argument: a `Matrix` or matrix text goes as a matrix (`--prb`), any other text
/// as a published name or model file (`--model`).
enum ModelArg {
    Matrix(String),
    Named(String),
}

fn model_arg(argument: &str, v: &Bound<'_, PyAny>) -> PyResult<ModelArg> {
    if let Ok(text) = v.extract::<String>() {
        return Ok(match PrbMatrix::parse(&text) {
            Ok(_) => ModelArg::Matrix(text),
            // Matrix text with a mistake in it (no published name has a comma, and no file
            // of that name exists): the matrix's own message, not a missing file's.
            Err(_) if text.contains(',') && !std::path::Path::new(&text).exists() => {
                ModelArg::Matrix(text)
            }
            Err(_) => ModelArg::Named(text),
        });
    }
    // A model file as a path object (`pathlib.Path`, anything `os.fspath` takes).
    if !v.is_instance_of::<PyString>() && v.hasattr("__fspath__")? {
        let path: PathBuf = extract(argument, v, "a model file's path")?;
        return Ok(ModelArg::Named(path.display().to_string()));
    }
    Ok(ModelArg::Matrix(Matrix::from_any(argument, v)?.to_text()))
}

/// The scene a command runs on: a copy, so that the borrow of the Python object ends before
/// the work starts, and the scene can be edited (by another thread, or from a fit's progress
/// callback) while the command runs on the scene as it was.
fn snapshot(slf: PyRef<'_, Scene>) -> prbfit::scene::Scene {
    slf.inner.clone()
}

impl Scene {
    /// `scene` checked by its rules: bad input with the rule's message if broken.
    fn checked(scene: prbfit::scene::Scene) -> PyResult<Scene> {
        scene
            .validate()
            .map_err(|e| errors::report_error(ReportError::from(e)))?;
        Ok(Scene { inner: scene })
    }

    /// The scene with the beam values of `kwargs` set.
    fn edited_beam(&self, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Scene> {
        let mut scene = self.inner.clone();
        let b = &mut scene.beam;
        for (k, v) in kwargs.into_iter().flat_map(|d| d.iter()) {
            let key: String = extract("beam key", &k, "a key name")?;
            let arg = format!("beam.{key}");
            let number = |v: &Bound<'_, PyAny>| -> PyResult<f64> {
                finite(&arg, extract(&arg, v, "a number")?)
            };
            match key.as_str() {
                "length" => b.length = number(&v)?,
                "width" => b.width = number(&v)?,
                "thickness" => b.thickness = number(&v)?,
                "youngs_modulus" => b.youngs_modulus = number(&v)?,
                "poisson_ratio" => b.poisson_ratio = number(&v)?,
                "shear_coefficient" => {
                    b.shear_coefficient = if v.is_none() { None } else { Some(number(&v)?) }
                }
                "density" => b.density = if v.is_none() { None } else { Some(number(&v)?) },
                "allowable_stress" => {
                    b.allowable_stress = if v.is_none() { None } else { Some(number(&v)?) }
                }
                "effects" => {
                    let text: String = extract(&arg, &v, "a string (auto, none, all or a list)")?;
                    b.effects = if text.trim() == "auto" {
                        EffectsChoice::Auto
                    } else {
                        EffectsChoice::Fixed(
                            Effects::parse_list(&text).map_err(|e| errors::input(&arg, e))?,
                        )
                    };
                }
                _ => {
                    return Err(errors::input(
                        &arg,
                        "no such beam value (length, width, thickness, youngs_modulus, \
                         poisson_ratio, shear_coefficient, effects, density, allowable_stress)",
                    ))
                }
            }
        }
        let scene = scene
            .rebased(&self.inner.beam)
            .map_err(|e| errors::input("beam", e))?;
        Scene::checked(scene)
    }
}

#[pymethods]
impl Scene {
    /// Reads a scene file (TOML; a data scene's CSV beside it).
    #[staticmethod]
    fn load(path: &Bound<'_, PyAny>) -> PyResult<Scene> {
        let path = self::path("path", Some(path))?
            .ok_or_else(|| errors::input("path", "give the scene file to read"))?;
        prbfit::scene::Scene::from_file(&path)
            .map(|inner| Scene { inner })
            .map_err(|e| errors::report_error(ReportError::from(e)))
    }

    /// Parses a scene from TOML text; `origin` names it in errors. A data scene (`[truth]`)
    /// is refused: its measurements are a file beside the scene, read by `Scene.load`.
    #[staticmethod]
    #[pyo3(
        signature = (text, origin = None),
        text_signature = "(text, origin='<string>')"
    )]
    fn from_toml(text: &Bound<'_, PyAny>, origin: Option<&Bound<'_, PyAny>>) -> PyResult<Scene> {
        let text = self::text("text", Some(text))?
            .ok_or_else(|| errors::input("text", "give the scene's TOML text"))?;
        let origin = self::text("origin", origin)?.unwrap_or_else(|| "<string>".into());
        let scene = prbfit::scene::Scene::from_toml_str(&text, &origin)
            .map_err(|e| errors::report_error(ReportError::from(e)))?;
        if let Some(t) = &scene.truth {
            return Err(errors::input(
                "text",
                format!(
                    "{origin} is a data scene: its measurements ({}) are read beside the scene \
                     file; use Scene.load(path)",
                    t.file
                ),
            ));
        }
        Ok(Scene { inner: scene })
    }

    /// The built-in scene (what `prbfit` runs on without `--scene`).
    #[staticmethod]
    fn builtin() -> Scene {
        Scene {
            inner: prbfit::scene::Scene::builtin(),
        }
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    #[setter]
    fn set_name(&mut self, name: &Bound<'_, PyAny>) -> PyResult<()> {
        self.inner.name =
            text("name", Some(name))?.ok_or_else(|| errors::input("name", "give a name"))?;
        Ok(())
    }

    /// `cantilever`, `mechanism`, `data` (a cantilever's measured data) or `mechanism data`.
    #[getter]
    fn kind(&self) -> &'static str {
        match (&self.inner.mechanism, &self.inner.truth) {
            (None, None) => "cantilever",
            (Some(_), None) => "mechanism",
            (None, Some(_)) => "data",
            (Some(_), Some(_)) => "mechanism data",
        }
    }

    /// The beam (SI): length, width, thickness, youngs_modulus, poisson_ratio,
    /// shear_coefficient (None: Cowper's), effects, density (kg/m^3; None: the scene gives
    /// none, and `modes` asks for it), allowable_stress (Pa, or None); and its slenderness
    /// L/t0.
    #[getter]
    fn beam<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let b = &self.inner.beam;
        let d = PyDict::new(py);
        d.set_item("length", b.length)?;
        d.set_item("width", b.width)?;
        d.set_item("thickness", b.thickness)?;
        d.set_item("youngs_modulus", b.youngs_modulus)?;
        d.set_item("poisson_ratio", b.poisson_ratio)?;
        d.set_item("shear_coefficient", b.shear_coefficient)?;
        d.set_item("effects", b.effects.to_string())?;
        d.set_item("density", b.density)?;
        d.set_item("allowable_stress", b.allowable_stress)?;
        d.set_item("slenderness", b.slenderness())?;
        Ok(d)
    }

    /// Sets beam values (`length`, `width`, `thickness`, `youngs_modulus`, `poisson_ratio`,
    /// `shear_coefficient`, `effects`, `density`, `allowable_stress`; None clears the
    /// shear coefficient, density and allowable stress), checked by the scene's rules; a
    /// mechanism's flexures and a data scene's rows follow the beam as in the UI.
    #[pyo3(signature = (**values))]
    fn set_beam(&mut self, values: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        *self = self.edited_beam(values)?;
        Ok(())
    }

    /// A copy with these beam values (see `set_beam`).
    #[pyo3(signature = (**values))]
    fn with_beam(&self, values: Option<&Bound<'_, PyDict>>) -> PyResult<Scene> {
        self.edited_beam(values)
    }

    /// The rigid body at the end of the flexures: a cantilever's `[tip]` body (its centre of
    /// mass at the tip), a mechanism's `[stage]` (at the stage point): `mass` (kg) and
    /// `inertia` (kg m^2 about its centre of mass); 0 when the scene gives none.
    #[getter]
    fn body<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        edit::body_dict(py, &self.inner)
    }

    /// Sets the body's `mass` and `inertia`, checked by the scene's rules (errors name
    /// `tip.mass` or `stage.mass`).
    #[pyo3(signature = (**values))]
    fn set_body(&mut self, values: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        *self = Scene::checked(edit::body(&self.inner, values)?)?;
        Ok(())
    }

    /// The fit's settings (`[fit]`): `angle_weight`, `force_weight`, `modes` (how many
    /// natural frequencies the fit matches beside the statics; 0: statics only),
    /// `frequency_weight`.
    #[getter]
    fn fit_settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        edit::fit_dict(py, &self.inner)
    }

    /// Sets fit settings (see `fit_settings`), checked by the scene's rules.
    #[pyo3(signature = (**values))]
    fn set_fit_settings(&mut self, values: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        *self = Scene::checked(edit::fit(&self.inner, values)?)?;
        Ok(())
    }

    /// The targets (`[accuracy]`): `max_pos_err`, `max_ang_err`, `max_force_err`,
    /// `max_freq_err`.
    #[getter]
    fn accuracy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        edit::accuracy_dict(py, &self.inner)
    }

    /// Sets targets (see `accuracy`), checked by the scene's rules.
    #[pyo3(signature = (**values))]
    fn set_accuracy(&mut self, values: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        *self = Scene::checked(edit::accuracy(&self.inner, values)?)?;
        Ok(())
    }

    /// The load paths: `(alpha_x, alpha_y, beta, steps)` each, from zero to that end load.
    #[getter]
    fn loads<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let items: Vec<Bound<'py, PyTuple>> = self
            .inner
            .loads
            .iter()
            .map(|p| {
                PyTuple::new(
                    py,
                    [
                        p.end.alpha_x.into_pyobject(py)?.into_any(),
                        p.end.alpha_y.into_pyobject(py)?.into_any(),
                        p.end.beta.into_pyobject(py)?.into_any(),
                        p.steps.into_pyobject(py)?.into_any(),
                    ],
                )
            })
            .collect::<PyResult<_>>()?;
        PyList::new(py, items)
    }

    #[setter]
    fn set_loads(&mut self, paths: &Bound<'_, PyAny>) -> PyResult<()> {
        if self.inner.truth.is_some() {
            return Err(errors::input(
                "loads",
                "a data scene's load paths are its data file's rows",
            ));
        }
        let items: Vec<Bound<'_, PyAny>> =
            extract("loads", paths, "a list of (alpha_x, alpha_y, beta, steps)")?;
        let mut loads = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            let arg = format!("loads[{}]", i + 1);
            // A tuple, a list or an array row of four.
            let parts: Vec<Bound<'_, PyAny>> =
                extract(&arg, item, "(alpha_x, alpha_y, beta, steps)")?;
            let [x, y, b, n] = parts.as_slice() else {
                return Err(errors::input(
                    &arg,
                    format!(
                        "expected (alpha_x, alpha_y, beta, steps), got {} items",
                        parts.len()
                    ),
                ));
            };
            let number = |key: &str, v: &Bound<'_, PyAny>| {
                let at = format!("{arg}.{key}");
                finite(&at, extract::<f64>(&at, v, "a number")?)
            };
            let (alpha_x, alpha_y, beta) = (
                number("alpha_x", x)?,
                number("alpha_y", y)?,
                number("beta", b)?,
            );
            let steps = whole::<u32>(&format!("{arg}.steps"), n, 1, u32::MAX)?;
            loads.push(LoadPath {
                end: Load {
                    alpha_x,
                    alpha_y,
                    beta,
                },
                steps,
            });
        }
        let mut scene = self.inner.clone();
        scene.loads = loads;
        *self = Scene::checked(scene)?;
        Ok(())
    }

    /// The scene's model (`[prb] matrix`), or None.
    #[getter]
    fn matrix(&self) -> Option<Matrix> {
        self.inner.prb.clone().map(|inner| Matrix { inner })
    }

    #[setter]
    fn set_matrix(&mut self, value: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let mut scene = self.inner.clone();
        scene.prb = match value {
            Some(v) if !v.is_none() => Some(Matrix::from_any("matrix", v)?),
            _ => None,
        };
        *self = Scene::checked(scene)?;
        Ok(())
    }

    /// Checks the scene by its rules (every edit already is).
    fn validate(&self) -> PyResult<()> {
        Scene::checked(self.inner.clone()).map(|_| ())
    }

    /// The scene as TOML (a scene file).
    fn to_toml(&self) -> String {
        self.inner.to_toml()
    }

    /// A copy.
    fn copy(&self) -> Scene {
        self.clone()
    }

    fn __copy__(&self) -> Scene {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Scene {
        self.clone()
    }

    fn __repr__(&self) -> String {
        format!("<prbfit.Scene {:?} ({})>", self.inner.name, self.kind())
    }

    /// `prbfit solve`: the baseline beam over the scene's cases, or at one `load`
    /// `(alpha_x, alpha_y, beta)`; a mechanism's beam mechanism along its drives.
    #[pyo3(
        signature = (load = None, *, effects = None, slenderness = None, nu = None, kappa = None, tol = None, shape = None),
        text_signature = "($self, load=None, *, effects=None, slenderness=None, nu=None, kappa=None, tol=None, shape=False)"
    )]
    #[allow(clippy::too_many_arguments)]
    fn solve(
        slf: PyRef<'_, Self>,
        py: Python<'_>,
        load: Option<&Bound<'_, PyAny>>,
        effects: Option<&Bound<'_, PyAny>>,
        slenderness: Option<&Bound<'_, PyAny>>,
        nu: Option<&Bound<'_, PyAny>>,
        kappa: Option<&Bound<'_, PyAny>>,
        tol: Option<&Bound<'_, PyAny>>,
        shape: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let args = report::solve::SolveArgs {
            load: load_arg(load)?,
            effects: text("effects", effects)?,
            slenderness: real("slenderness", slenderness)?,
            nu: real("nu", nu)?,
            kappa: real("kappa", kappa)?,
            tol: real("tol", tol)?.unwrap_or(report::solve::SolveArgs::default().tol),
            shape: flag("shape", shape, false)?,
        };
        let scene = &snapshot(slf);
        let r = run(py, None, |ctl: &mut Control<'_>| {
            report_of(&report::solve::solve(scene, &args, ctl)?)
        })?;
        result!(py, r, Solution)
    }

    /// `prbfit eval`: models (published names, model files, matrix text or `Matrix`es; the
    /// scene's own with none) judged against the truth, over the scene or at one `load`.
    /// Named models and files are judged first, then matrices, as the CLI orders `--model`
    /// and `--prb`.
    #[pyo3(signature = (*models, load = None, tol = None))]
    fn eval(
        slf: PyRef<'_, Self>,
        py: Python<'_>,
        models: &Bound<'_, PyTuple>,
        load: Option<&Bound<'_, PyAny>>,
        tol: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let mut args = report::eval::EvalArgs {
            load: load_arg(load)?,
            ..Default::default()
        };
        if let Some(t) = real("tol", tol)? {
            args.tol = t;
        }
        for (i, m) in models.iter().enumerate() {
            match model_arg(&format!("models[{i}]"), &m)? {
                ModelArg::Matrix(t) => args.prb.push(t),
                ModelArg::Named(n) => args.model.push(n),
            }
        }
        let scene = &snapshot(slf);
        let r = run(py, None, |ctl: &mut Control<'_>| {
            report_of(&report::eval::eval(scene, &args, ctl)?)
        })?;
        result!(py, r, Evaluation)
    }

    /// `prbfit modes`: the natural frequencies of the scene's truth and of models (published
    /// names, model files, matrix text or `Matrix`es; the scene's own with none, else the
    /// beam alone) about the same equilibria: the unloaded scene, one tip `load`
    /// `(alpha_x, alpha_y, beta)` of a cantilever, or every case (`cases=True`). Needs the
    /// scene's `[beam] density`. Named models and files come first, then matrices, as the
    /// CLI orders `--model` and `--prb`.
    #[pyo3(
        signature = (*models, count = None, load = None, cases = None, tol = None),
        text_signature = "($self, *models, count=3, load=None, cases=False, tol=None)"
    )]
    fn modes(
        slf: PyRef<'_, Self>,
        py: Python<'_>,
        models: &Bound<'_, PyTuple>,
        count: Option<&Bound<'_, PyAny>>,
        load: Option<&Bound<'_, PyAny>>,
        cases: Option<&Bound<'_, PyAny>>,
        tol: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let mut args = report::modes::ModesArgs {
            count: match count {
                Some(v) => whole::<u32>("count", v, 1, u32::MAX)? as usize,
                None => 3,
            },
            load: load_arg(load)?,
            cases: flag("cases", cases, false)?,
            ..Default::default()
        };
        if let Some(t) = real("tol", tol)? {
            args.tol = t;
        }
        for (i, m) in models.iter().enumerate() {
            match model_arg(&format!("models[{i}]"), &m)? {
                ModelArg::Matrix(t) => args.prb.push(t),
                ModelArg::Named(n) => args.model.push(n),
            }
        }
        let scene = &snapshot(slf);
        let r = run(py, None, |ctl: &mut Control<'_>| {
            report_of(&report::modes::modes(scene, &args, ctl)?)
        })?;
        result!(py, r, Modes)
    }

    /// `prbfit fit`: the free cells of a matrix (`topology`'s start, or `matrix` with its
    /// fixed cells, or the scene's own) fitted to the truth. `progress(dict)` is called as
    /// the search goes (phase, iteration, evaluations, best_objective, best, seconds);
    /// `output` saves the model file (.toml or .json).
    #[pyo3(
        signature = (topology = None, *, matrix = None, fidelity = None, seed = None, output = None, force = None, progress = None),
        text_signature = "($self, topology=None, *, matrix=None, fidelity='normal', seed=1, output=None, force=False, progress=None)"
    )]
    #[allow(clippy::too_many_arguments)]
    fn fit(
        slf: PyRef<'_, Self>,
        py: Python<'_>,
        topology: Option<&Bound<'_, PyAny>>,
        matrix: Option<&Bound<'_, PyAny>>,
        fidelity: Option<&Bound<'_, PyAny>>,
        seed: Option<&Bound<'_, PyAny>>,
        output: Option<&Bound<'_, PyAny>>,
        force: Option<&Bound<'_, PyAny>>,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let seed = match seed {
            Some(v) => whole::<u64>("seed", v, 0, u64::MAX)?,
            None => 1,
        };
        let topology = text("topology", topology)?;
        if topology.is_some() && matrix.is_some() {
            return Err(errors::input(
                "topology",
                "give a topology or a matrix to start from, not both",
            ));
        }
        if let Some(cb) = progress {
            if !cb.is_callable() {
                return Err(errors::input("progress", "expected a callable"));
            }
        }
        let args = report::fit::FitArgs {
            topology,
            prb: matrix
                .map(|m| Matrix::from_any("matrix", m).map(|m| m.to_text()))
                .transpose()?,
            fidelity: fidelity_arg(fidelity)?,
            seed,
            output: path("output", output)?,
            force: flag("force", force, false)?,
        };
        let scene = &snapshot(slf);
        let r = run(py, progress, |ctl: &mut Control<'_>| {
            report_of(&report::fit::fit(scene, &args, ctl)?)
        })?;
        result!(py, r, Fit)
    }

    /// `prbfit select`: the topology ladder fitted, the simplest model that meets the
    /// targets chosen; `within_stroke` judges only the cases up to each path's stroke limit
    /// (where the stress first reaches the scene's allowable stress).
    #[pyo3(
        signature = (fidelity = None, *, within_stroke = None),
        text_signature = "($self, fidelity='normal', *, within_stroke=False)"
    )]
    fn select(
        slf: PyRef<'_, Self>,
        py: Python<'_>,
        fidelity: Option<&Bound<'_, PyAny>>,
        within_stroke: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let args = report::select::SelectArgs {
            fidelity: fidelity_arg(fidelity)?,
            within_stroke: flag("within_stroke", within_stroke, false)?,
        };
        let scene = &snapshot(slf);
        let r = run(py, None, |ctl: &mut Control<'_>| {
            report_of(&report::select::select(scene, &args, ctl)?)
        })?;
        result!(py, r, Selection)
    }

    /// `prbfit calibrate`: one beam parameter (`youngs_modulus` or `thickness`) fitted to a
    /// data scene's measurements.
    #[pyo3(signature = (param = None), text_signature = "($self, param='youngs_modulus')")]
    fn calibrate(
        slf: PyRef<'_, Self>,
        py: Python<'_>,
        param: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let args = report::calibrate::CalibrateArgs {
            param: text("param", param)?.unwrap_or_else(|| "youngs_modulus".into()),
        };
        let scene = &snapshot(slf);
        let r = run(py, None, |ctl: &mut Control<'_>| {
            report_of(&report::calibrate::calibrate_scene(scene, &args, ctl)?)
        })?;
        result!(py, r, Calibration)
    }

    /// `prbfit export`: writes `model` (a published name, a model file, matrix text or a
    /// `Matrix`; the scene's own with None) to `output` as prbfit's model file, MuJoCo,
    /// URDF, SDF or CSV (`format`, or from the extension). `density` (kg/m^3) for the
    /// masses: None takes the scene's `[beam] density`, else 1000.
    #[pyo3(
        signature = (model = None, output = None, *, format = None, force = None, density = None, fidelity = None),
        text_signature = "($self, model=None, output=None, *, format=None, force=False, density=None, fidelity='normal')"
    )]
    #[allow(clippy::too_many_arguments)]
    fn export(
        slf: PyRef<'_, Self>,
        py: Python<'_>,
        model: Option<&Bound<'_, PyAny>>,
        output: Option<&Bound<'_, PyAny>>,
        format: Option<&Bound<'_, PyAny>>,
        force: Option<&Bound<'_, PyAny>>,
        density: Option<&Bound<'_, PyAny>>,
        fidelity: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let Some(output) = path("output", output)? else {
            return Err(errors::input("output", "give the file to write"));
        };
        let mut args = report::export::ExportArgs::new(output);
        match model.filter(|m| !m.is_none()) {
            None => {}
            Some(m) => match model_arg("model", m)? {
                ModelArg::Matrix(t) => args.prb = Some(t),
                ModelArg::Named(n) => args.model = Some(n),
            },
        }
        args.format = text("format", format)?
            .map(|f| Format::from_str(&f).map_err(|e| errors::input("format", e)))
            .transpose()?;
        args.force = flag("force", force, false)?;
        args.density = real("density", density)?;
        args.fidelity = fidelity_arg(fidelity)?;
        let scene = &snapshot(slf);
        let r = run(py, None, |ctl: &mut Control<'_>| {
            report_of(&report::export::export(scene, &args, ctl)?)
        })?;
        result!(py, r, Export)
    }

    /// `prbfit fea`: the scene's beam in CalculiX (`ccx`) along its load paths, written to
    /// `output` as measured-data CSV, the beam beside it; a mechanism scene's whole
    /// mechanism (every flexure, the stage a rigid body) along its drives, the beam mechanism
    /// beside it. A drive path CalculiX cannot finish raises `SolveError` (its solved cases
    /// are in the CSV, marked), as the CLI exits 1. `section` (`plane-stress`,
    /// `plane-strain`, `solid`): None takes the scene's (solid when its beam keeps plane
    /// strain, else plane-stress).
    #[pyo3(
        signature = (output, *, mesh = None, section = None, taper = None, deck = None, force = None, timeout = None),
        text_signature = "($self, output, *, mesh=40, section=None, taper=1.0, deck=None, force=False, timeout=900)"
    )]
    #[allow(clippy::too_many_arguments)]
    fn fea(
        slf: PyRef<'_, Self>,
        py: Python<'_>,
        output: &Bound<'_, PyAny>,
        mesh: Option<&Bound<'_, PyAny>>,
        section: Option<&Bound<'_, PyAny>>,
        taper: Option<&Bound<'_, PyAny>>,
        deck: Option<&Bound<'_, PyAny>>,
        force: Option<&Bound<'_, PyAny>>,
        timeout: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let output = path("output", Some(output))?
            .ok_or_else(|| errors::input("output", "give the file to write"))?;
        let mut args = report::fea::FeaArgs::new(output);
        if let Some(v) = mesh {
            args.mesh = whole::<u32>("mesh", v, 1, u32::MAX)?;
        }
        args.section = text("section", section)?
            .map(|s| Section::from_str(&s).map_err(|e| errors::input("section", e)))
            .transpose()?;
        let taper = real("taper", taper)?.unwrap_or(1.0);
        args.taper = Taper::from_str(&format!("{taper}")).map_err(|e| errors::input("taper", e))?;
        args.deck = path("deck", deck)?;
        args.force = flag("force", force, false)?;
        if let Some(v) = timeout {
            args.timeout = whole::<u64>("timeout", v, 1, u64::MAX)?;
        }
        let scene = &snapshot(slf);
        let r = run(py, None, |ctl: &mut Control<'_>| {
            if scene.mechanism.is_none() {
                return report_of(&report::fea::fea(scene, &args, ctl)?);
            }
            // A mechanism: a drive path CalculiX could not finish is the CLI's exit status 1
            // after its report (the solved cases are in the CSV, the path marked).
            let r = report::fea_mech::fea_mechanism(scene, &args, ctl)?;
            match r.incomplete() {
                Some(m) => Err(ReportError::solve(m)),
                None => report_of(&r),
            }
        })?;
        result!(py, r, Fea)
    }

    /// For the overhead benchmark: the mean seconds of `n` `solve(load)` reports built in
    /// Rust alone, on this thread (the Rust call the module's calls wrap).
    #[pyo3(signature = (load, n = 100))]
    fn _rust_solve_seconds(&self, load: &Bound<'_, PyAny>, n: u32) -> PyResult<f64> {
        let args = report::solve::SolveArgs {
            load: load_arg(Some(load))?,
            ..Default::default()
        };
        let mut quiet = |_: &report::Progress<'_>| {};
        let t0 = std::time::Instant::now();
        for _ in 0..n {
            let mut ctl = Control {
                cancel: prbfit::cancel::CancelToken::new(),
                progress: &mut quiet,
            };
            report_of(
                &report::solve::solve(&self.inner, &args, &mut ctl)
                    .map_err(errors::report_error)?,
            )
            .map_err(errors::report_error)?;
        }
        Ok(t0.elapsed().as_secs_f64() / f64::from(n.max(1)))
    }
}
