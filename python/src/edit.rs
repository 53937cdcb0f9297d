//! Scene edits beside the beam's (DESIGN §10, §4): the body at the end of the flexures
//! (`[tip]` or `[stage]` mass and inertia), the fit's settings (`[fit]`, its `modes` and
//! `frequency_weight` among them) and the targets (`[accuracy]`, `max_freq_err` among them).
//! Each takes keyword values and gives the edited scene, unchecked: the caller checks it by
//! the scene's rules, whose errors name the key (`tip.mass`, `fit.modes`).

use pyo3::prelude::*;
use pyo3::types::PyDict;

use prbfit::scene::{rules, Scene};

use crate::convert::{extract, finite, real, whole};
use crate::errors;

/// The keyword values of `kwargs` with their names and the scene key (`table.key`) each sets.
fn items<'py>(
    table: &str,
    kwargs: Option<&Bound<'py, PyDict>>,
) -> PyResult<Vec<(String, String, Bound<'py, PyAny>)>> {
    kwargs
        .into_iter()
        .flat_map(|d| d.iter())
        .map(|(k, v)| {
            let key: String = extract(&format!("{table} key"), &k, "a key name")?;
            let arg = format!("{table}.{key}");
            Ok((key, arg, v))
        })
        .collect()
}

/// A finite number for `arg` (not a bool: see [`real`]).
fn number(arg: &str, v: &Bound<'_, PyAny>) -> PyResult<f64> {
    match real(arg, Some(v))? {
        Some(x) => finite(arg, x),
        None => Err(errors::input(arg, "expected a number, got NoneType")),
    }
}

/// The scene with the body's `mass` (kg) and `inertia` (kg m^2, about its centre of mass)
/// of `kwargs` set.
pub fn body(scene: &Scene, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Scene> {
    let mut out = scene.clone();
    for (key, arg, v) in items(scene.body_table(), kwargs)? {
        match key.as_str() {
            "mass" => out.body.mass = number(&arg, &v)?,
            "inertia" => out.body.inertia = number(&arg, &v)?,
            _ => return Err(errors::input(&arg, "no such body value (mass, inertia)")),
        }
    }
    Ok(out)
}

/// The body as a dict: `mass`, `inertia`.
pub fn body_dict<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("mass", scene.body.mass)?;
    d.set_item("inertia", scene.body.inertia)?;
    Ok(d)
}

/// The scene with the fit settings of `kwargs` set.
pub fn fit(scene: &Scene, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Scene> {
    let mut out = scene.clone();
    let f = &mut out.fit;
    for (key, arg, v) in items("fit", kwargs)? {
        match key.as_str() {
            "angle_weight" => f.angle_weight = number(&arg, &v)?,
            "force_weight" => f.force_weight = number(&arg, &v)?,
            "frequency_weight" => f.frequency_weight = number(&arg, &v)?,
            "modes" => {
                let n = whole::<i64>(&arg, &v, i64::MIN, i64::MAX)?;
                f.modes = rules::modes(n).map_err(|e| errors::input(&arg, e))?;
            }
            _ => {
                return Err(errors::input(
                    &arg,
                    "no such fit setting (angle_weight, force_weight, modes, frequency_weight)",
                ))
            }
        }
    }
    Ok(out)
}

/// The fit settings as a dict.
pub fn fit_dict<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Bound<'py, PyDict>> {
    let f = &scene.fit;
    let d = PyDict::new(py);
    d.set_item("angle_weight", f.angle_weight)?;
    d.set_item("force_weight", f.force_weight)?;
    d.set_item("modes", f.modes)?;
    d.set_item("frequency_weight", f.frequency_weight)?;
    Ok(d)
}

/// The scene with the targets of `kwargs` set.
pub fn accuracy(scene: &Scene, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Scene> {
    let mut out = scene.clone();
    let a = &mut out.accuracy;
    for (key, arg, v) in items("accuracy", kwargs)? {
        let cell = match key.as_str() {
            "max_pos_err" => &mut a.max_pos_err,
            "max_ang_err" => &mut a.max_ang_err,
            "max_force_err" => &mut a.max_force_err,
            "max_freq_err" => &mut a.max_freq_err,
            _ => {
                return Err(errors::input(
                    &arg,
                    "no such target (max_pos_err, max_ang_err, max_force_err, max_freq_err)",
                ))
            }
        };
        *cell = number(&arg, &v)?;
    }
    Ok(out)
}

/// The targets as a dict.
pub fn accuracy_dict<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Bound<'py, PyDict>> {
    let a = &scene.accuracy;
    let d = PyDict::new(py);
    d.set_item("max_pos_err", a.max_pos_err)?;
    d.set_item("max_ang_err", a.max_ang_err)?;
    d.set_item("max_force_err", a.max_force_err)?;
    d.set_item("max_freq_err", a.max_freq_err)?;
    Ok(d)
}
