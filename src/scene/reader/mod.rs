//! The scene file reader (DESIGN §5, §8, §9): TOML text to a [`Scene`], with every error
//! naming the file, the line and the key.
//!
//! The reader does what only a file can get wrong: a key or table it does not know, a value
//! of the wrong type, a name that is no choice (`effects`, `attach`), tables that do not go
//! together (`[[drives]]` without `[[flexures]]`, `[[loads]]` beside `[truth]`), a matrix
//! that does not parse. It fills in the defaults and records where each key sits, then
//! checks the scene by its rules ([`Scene::check_rules`], the rules every editor applies)
//! and places a broken rule at the line of its key (or of the table holding a defaulted
//! key).
//!
//! `mech.rs` reads the mechanism tables, `spans.rs` keeps the keys' places; this file reads
//! the rest and puts the scene together.

mod mech;
mod spans;

use serde::Deserialize;
use toml::Spanned;

use crate::beam::{Effects, Load};
use crate::prb::PrbMatrix;

use super::beam::{BeamSpec, EffectsChoice};
use super::data;
use super::error::SceneError;
use super::load::LoadPath;
use super::rules;
use super::settings::{Accuracy, Body, FitSettings};
use super::{Scene, DEFAULT_SCENE_NAME, DEFAULT_SCENE_TOML};
use spans::{line_of, Spans};

impl Scene {
    /// The built-in scene.
    #[allow(clippy::expect_used)] // a compiled-in constant, checked by a test
    pub fn builtin() -> Scene {
        Scene::from_toml_str(DEFAULT_SCENE_TOML, DEFAULT_SCENE_NAME)
            .expect("the built-in scene is valid (checked by a test)")
    }

    /// Parses and validates a scene; `origin` names it in errors (a file path).
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Scene, SceneError> {
        let raw: RawScene = toml::from_str(text).map_err(|e| SceneError {
            origin: origin.to_string(),
            line: e.span().map(|s| line_of(text, s.start)),
            key: None,
            message: e.message().trim().to_string(),
        })?;
        let mut spans = Spans::new(text, origin);
        let scene = scene(&mut spans, raw)?;
        scene.check_rules().map_err(|e| spans.locate(e))?;
        Ok(scene)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    name: Option<Spanned<String>>,
    beam: Spanned<RawBeam>,
    #[serde(default)]
    loads: Vec<Spanned<RawLoad>>,
    accuracy: Option<Spanned<RawAccuracy>>,
    fit: Option<Spanned<RawFit>>,
    prb: Option<Spanned<RawPrb>>,
    tip: Option<Spanned<RawTip>>,
    truth: Option<Spanned<RawTruth>>,
    #[serde(default)]
    flexures: Vec<Spanned<mech::RawFlexure>>,
    stage: Option<Spanned<mech::RawStage>>,
    #[serde(default)]
    drives: Vec<Spanned<mech::RawDrive>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTruth {
    data: Spanned<String>,
}

/// `[tip]`: the body bolted to a cantilever's tip (DESIGN §10).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTip {
    mass: Option<Spanned<f64>>,
    inertia: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPrb {
    matrix: Spanned<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBeam {
    length: Spanned<f64>,
    width: Spanned<f64>,
    thickness: Spanned<f64>,
    youngs_modulus: Spanned<f64>,
    poisson_ratio: Spanned<f64>,
    shear_coefficient: Option<Spanned<f64>>,
    allowable_stress: Option<Spanned<f64>>,
    /// Any TOML value: checked by hand, so a wrong type gets a message that says what is
    /// expected (serde's untagged enums only say "did not match any variant").
    effects: Option<Spanned<toml::Value>>,
    density: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLoad {
    alpha_x: Option<Spanned<f64>>,
    alpha_y: Option<Spanned<f64>>,
    beta: Option<Spanned<f64>>,
    steps: Option<Spanned<i64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawAccuracy {
    max_pos_err: Option<Spanned<f64>>,
    max_ang_err: Option<Spanned<f64>>,
    max_force_err: Option<Spanned<f64>>,
    max_freq_err: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFit {
    angle_weight: Option<Spanned<f64>>,
    force_weight: Option<Spanned<f64>>,
    modes: Option<Spanned<i64>>,
    frequency_weight: Option<Spanned<f64>>,
}

/// The scene as the file writes it, defaults filled in, not yet checked by its rules.
fn scene(spans: &mut Spans<'_>, raw: RawScene) -> Result<Scene, SceneError> {
    let name = raw
        .name
        .map(|n| n.into_inner())
        .unwrap_or_else(|| "unnamed scene".to_string());
    let beam = beam(spans, &raw.beam)?;
    if let Some(first) = raw.loads.first() {
        spans.record("loads", first.span());
    }
    let mechanism = if raw.flexures.is_empty() {
        if let Some(first) = raw
            .drives
            .first()
            .map(|d| d.span())
            .or(raw.stage.as_ref().map(|s| s.span()))
        {
            return Err(spans.error(
                first,
                "flexures",
                "[stage] and [[drives]] describe a mechanism: add its [[flexures]] (or give \
                 [[loads]] for a plain cantilever)"
                    .into(),
            ));
        }
        None
    } else {
        Some(mech::mechanism(
            spans,
            &beam,
            &raw.flexures,
            raw.stage.as_ref(),
            &raw.drives,
            raw.truth.is_some(),
        )?)
    };
    let truth = match &raw.truth {
        None => None,
        Some(t) => {
            // Beside [[flexures]], [[loads]] break a mechanism scene's own rule, which the
            // scene's rules say; without, they would be a data scene's rows.
            if let (Some(first), None) = (raw.loads.first(), &mechanism) {
                return Err(spans.error(
                    first.span(),
                    "loads",
                    "a data scene's load cases are its data file's rows: remove the [[loads]] \
                     tables"
                        .into(),
                ));
            }
            Some(data::DataTruth {
                file: spans.take("truth.data", &t.get_ref().data),
                sha256: String::new(),
                units: data::Units::default(),
                paths: Vec::new(),
                stage: None,
            })
        }
    };
    let mut loads = Vec::with_capacity(raw.loads.len());
    for (i, load) in raw.loads.iter().enumerate() {
        loads.push(self::load(spans, load, i + 1)?);
    }
    let number = |spans: &mut Spans<'_>, v: Option<&Spanned<f64>>, key: &str, default: f64| {
        v.map_or(default, |v| spans.take(key, v))
    };
    let acc = raw.accuracy.as_ref().map(|a| a.get_ref());
    let default = Accuracy::default();
    let accuracy = Accuracy {
        max_pos_err: number(
            spans,
            acc.and_then(|a| a.max_pos_err.as_ref()),
            "accuracy.max_pos_err",
            default.max_pos_err,
        ),
        max_ang_err: number(
            spans,
            acc.and_then(|a| a.max_ang_err.as_ref()),
            "accuracy.max_ang_err",
            default.max_ang_err,
        ),
        max_force_err: number(
            spans,
            acc.and_then(|a| a.max_force_err.as_ref()),
            "accuracy.max_force_err",
            default.max_force_err,
        ),
        max_freq_err: number(
            spans,
            acc.and_then(|a| a.max_freq_err.as_ref()),
            "accuracy.max_freq_err",
            default.max_freq_err,
        ),
    };
    let fit_raw = raw.fit.as_ref().map(|f| f.get_ref());
    let defaults = FitSettings::default();
    let fit = FitSettings {
        angle_weight: number(
            spans,
            fit_raw.and_then(|f| f.angle_weight.as_ref()),
            "fit.angle_weight",
            defaults.angle_weight,
        ),
        force_weight: number(
            spans,
            fit_raw.and_then(|f| f.force_weight.as_ref()),
            "fit.force_weight",
            defaults.force_weight,
        ),
        modes: match fit_raw.and_then(|f| f.modes.as_ref()) {
            None => defaults.modes,
            Some(m) => {
                let v = spans.take("fit.modes", m);
                rules::modes(v).map_err(|e| spans.error(m.span(), "fit.modes", e))?
            }
        },
        frequency_weight: number(
            spans,
            fit_raw.and_then(|f| f.frequency_weight.as_ref()),
            "fit.frequency_weight",
            defaults.frequency_weight,
        ),
    };
    let body = body(
        spans,
        raw.tip.as_ref(),
        raw.stage.as_ref(),
        mechanism.is_some(),
    )?;
    let prb = match &raw.prb {
        None => None,
        Some(p) => {
            let m = &p.get_ref().matrix;
            spans.record("prb.matrix", m.span());
            Some(
                PrbMatrix::parse(m.get_ref())
                    .map_err(|e| spans.error(m.span(), "prb.matrix", e.to_string()))?,
            )
        }
    };
    Ok(Scene {
        name,
        beam,
        loads,
        accuracy,
        fit,
        body,
        prb,
        mechanism,
        truth,
    })
}

/// The body at the end of the flexures: `[tip]` of a cantilever, the mass and inertia of a
/// mechanism's `[stage]`; each table only in its kind of scene.
fn body(
    spans: &mut Spans<'_>,
    tip: Option<&Spanned<RawTip>>,
    stage: Option<&Spanned<mech::RawStage>>,
    mechanism: bool,
) -> Result<Body, SceneError> {
    let (table, mass, inertia) = match (tip, mechanism) {
        (Some(t), true) => {
            return Err(spans.error(
                t.span(),
                "tip",
                "a mechanism's flexures end on its stage: give the body's mass and inertia \
                 under [stage]"
                    .into(),
            ))
        }
        (Some(t), false) => {
            spans.record("tip", t.span());
            let t = t.get_ref();
            ("tip", t.mass.as_ref(), t.inertia.as_ref())
        }
        (None, false) => return Ok(Body::default()),
        (None, true) => match stage {
            None => return Ok(Body::default()),
            Some(s) => {
                spans.record("stage", s.span());
                let s = s.get_ref();
                ("stage", s.mass.as_ref(), s.inertia.as_ref())
            }
        },
    };
    let mut value = |v: Option<&Spanned<f64>>, key: &str| {
        v.map_or(0.0, |v| spans.take(format!("{table}.{key}"), v))
    };
    Ok(Body {
        mass: value(mass, "mass"),
        inertia: value(inertia, "inertia"),
    })
}

fn beam(spans: &mut Spans<'_>, raw: &Spanned<RawBeam>) -> Result<BeamSpec, SceneError> {
    spans.record("beam", raw.span());
    let raw = raw.get_ref();
    let effects = match &raw.effects {
        None => EffectsChoice::Auto,
        Some(spanned) => {
            spans.record("beam.effects", spanned.span());
            effects(spans, spanned)?
        }
    };
    Ok(BeamSpec {
        length: spans.take("beam.length", &raw.length),
        width: spans.take("beam.width", &raw.width),
        thickness: spans.take("beam.thickness", &raw.thickness),
        youngs_modulus: spans.take("beam.youngs_modulus", &raw.youngs_modulus),
        poisson_ratio: spans.take("beam.poisson_ratio", &raw.poisson_ratio),
        shear_coefficient: raw
            .shear_coefficient
            .as_ref()
            .map(|k| spans.take("beam.shear_coefficient", k)),
        effects,
        density: raw.density.as_ref().map(|d| spans.take("beam.density", d)),
        allowable_stress: raw
            .allowable_stress
            .as_ref()
            .map(|s| spans.take("beam.allowable_stress", s)),
    })
}

/// `effects`: `"auto"`, `"none"`, `"all"` or a list of names. Whether the named effects go
/// together is the beam's rule ([`BeamSpec::validate`]).
fn effects(spans: &Spans<'_>, spanned: &Spanned<toml::Value>) -> Result<EffectsChoice, SceneError> {
    let fail = |message: String| spans.error(spanned.span(), "beam.effects", message);
    let expected = "expected \"auto\", \"none\", \"all\" or a list such as \
                    [\"shear\", \"extension\"] (names: shear, extension, poisson, plane_strain)";
    match spanned.get_ref() {
        toml::Value::String(w) if w == "auto" => Ok(EffectsChoice::Auto),
        toml::Value::String(w) if w == "none" => Ok(EffectsChoice::Fixed(Effects::NONE)),
        toml::Value::String(w) if w == "all" => Ok(EffectsChoice::Fixed(Effects::ALL)),
        toml::Value::String(w) => Err(fail(format!("{expected}, got \"{w}\""))),
        toml::Value::Array(list) => {
            let mut effects = Effects::NONE;
            for item in list {
                let name = item.as_str().ok_or_else(|| {
                    fail(format!(
                        "{expected}; the list holds {} `{item}`, not a name",
                        item.type_str()
                    ))
                })?;
                // `none` and `all` stand alone, as strings, not in a list.
                if matches!(name, "none" | "all") {
                    return Err(fail(format!(
                        "`{name}` stands alone (effects = \"{name}\"): it cannot be listed \
                         with other effects"
                    )));
                }
                effects.set(name).map_err(|e| fail(e.to_string()))?;
            }
            Ok(EffectsChoice::Fixed(effects))
        }
        other => Err(fail(format!(
            "{expected}, got the {} `{other}`",
            other.type_str()
        ))),
    }
}

fn load(
    spans: &mut Spans<'_>,
    raw: &Spanned<RawLoad>,
    index: usize,
) -> Result<LoadPath, SceneError> {
    let key = |field: &str| format!("loads[{index}].{field}");
    spans.record(format!("loads[{index}]"), raw.span());
    let r = raw.get_ref();
    let mut component = |value: &Option<Spanned<f64>>, field: &str| {
        value.as_ref().map_or(0.0, |v| spans.take(key(field), v))
    };
    let end = Load::new(
        component(&r.alpha_x, "alpha_x"),
        component(&r.alpha_y, "alpha_y"),
        component(&r.beta, "beta"),
    );
    let steps = spans.steps(&r.steps, &key("steps"))?;
    Ok(LoadPath { end, steps })
}

#[cfg(test)]
mod tests;
