//! Calibration (DESIGN §9): one beam parameter of a data scene fitted to its measurements,
//! on every kind of scene: a cantilever's beam, or every flexure of a mechanism scaled by one
//! ratio (one material, one sheet: a rig's `E` or thickness differs from the catalogue's
//! alike in every flexure), judged as the beam (or beam mechanism) against the data by §4's
//! (or §8's) `J`.

use serde::Serialize;

use crate::beam::Resolution;
use crate::eval::{beam_against_rows, BaselineError};
use crate::mech::measured::{beam_against_data, BesideError};
use crate::scene::Scene;

use crate::mech::figures::Figures;

/// A beam parameter [`calibrate`] can fit to measured data.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BeamParam {
    /// `E`, Pa: scales the bending stiffness (a rig's `E` is never the catalogue's).
    YoungsModulus,
    /// `t0`, m: scales the bending stiffness as its cube and the slenderness.
    Thickness,
}

impl BeamParam {
    /// The scene key's name.
    pub fn name(self) -> &'static str {
        match self {
            BeamParam::YoungsModulus => "youngs_modulus",
            BeamParam::Thickness => "thickness",
        }
    }

    /// From the scene key's name.
    pub fn from_name(name: &str) -> Option<BeamParam> {
        match name {
            "youngs_modulus" | "E" => Some(BeamParam::YoungsModulus),
            "thickness" => Some(BeamParam::Thickness),
            _ => None,
        }
    }

    fn get(self, beam: &crate::scene::BeamSpec) -> f64 {
        match self {
            BeamParam::YoungsModulus => beam.youngs_modulus,
            BeamParam::Thickness => beam.thickness,
        }
    }

    fn set(self, beam: &mut crate::scene::BeamSpec, v: f64) {
        match self {
            BeamParam::YoungsModulus => beam.youngs_modulus = v,
            BeamParam::Thickness => beam.thickness = v,
        }
    }
}

/// One beam parameter fitted to a data scene's measurements.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    /// Which parameter.
    pub param: BeamParam,
    /// The scene's value (SI; a mechanism's flexure 1's, every flexure's scaled alike).
    pub nominal: f64,
    /// The fitted value (SI).
    pub value: f64,
    /// The beam against the data with the nominal value.
    pub nominal_figures: Figures,
    /// The beam against the data with the fitted value: the residual.
    pub figures: Figures,
    /// The fit ended at the edge of the searched range (a factor of [`CALIBRATION_RANGE`]
    /// either way of the nominal value): the data wants a value further out, or the beam
    /// cannot explain it.
    pub at_edge: bool,
    /// Beam solves of every row (evaluations of `J`).
    pub evaluations: u32,
}

/// [`calibrate`] searches within this factor of the nominal value, either way.
pub const CALIBRATION_RANGE: f64 = 4.0;

/// Fits `param` of the scene's beam (a mechanism's flexures, each scaled by one ratio) to
/// its measured data: the value that minimises the beam's (beam mechanism's) `J` against the
/// data (golden-section search on the logarithm of the value, within [`CALIBRATION_RANGE`]
/// of the nominal one, to a relative 1e-9; the nominal value is kept if nothing searched
/// does better). Trial values whose beam cannot reach every row count as worse than any
/// that can.
///
/// A cantilever's rows keep their physical loads: each trial beam takes them as its own
/// nondimensional loads (scaled by the nominal `E I0` over the trial's). A mechanism's data
/// stays in newtons and metres: each trial converts it with its own flexure 1 (the position
/// and angle errors are in units of `L`, which neither parameter changes, and the reaction
/// errors are fractions of the data's own reactions, so the trials' `J` compare).
///
/// # Errors
/// The scene has no data, or the beam with the nominal value cannot reach its rows.
pub fn calibrate(
    scene: &Scene,
    param: BeamParam,
    resolution: Resolution,
) -> Result<Calibration, CalibrateError> {
    let truth = scene.truth.as_ref().ok_or(CalibrateError::NoData)?;
    let mut evaluations = 0u32;
    let mut c = match &scene.mechanism {
        None => {
            let nominal_beam = scene.beam;
            let nominal = param.get(&nominal_beam);
            let ei0 = nominal_beam.youngs_modulus * nominal_beam.second_moment();
            let w = scene.fit.angle_weight;
            search(param, nominal, |v| {
                evaluations += 1;
                let mut beam = nominal_beam;
                param.set(&mut beam, v);
                let scale = ei0 / (beam.youngs_modulus * beam.second_moment());
                beam_against_rows(&beam, truth, scale, resolution, w)
                    .map(|e| e.figures)
                    .map_err(CalibrateError::Beam)
            })?
        }
        Some(mechanism) => {
            if truth.stage.is_none() {
                return Err(CalibrateError::NoData);
            }
            let nominal = mechanism
                .flexures
                .first()
                .map_or(1.0, |f| param.get(&f.beam));
            search(param, nominal, |v| {
                evaluations += 1;
                let mut trial = scene.clone();
                let mut m = mechanism.clone();
                for f in &mut m.flexures {
                    let mine = param.get(&f.beam);
                    param.set(&mut f.beam, mine * v / nominal);
                }
                trial.mechanism = Some(m.clone());
                beam_against_data(&trial, &m, resolution)?
                    .map(|e| e.figures)
                    .ok_or(CalibrateError::NoData)
            })?
        }
    };
    c.evaluations = evaluations;
    Ok(c)
}

/// The calibration of `param` around `nominal`: `judge(value)` gives the beam's figures
/// against the data; golden-section search on the logarithm
/// ([`golden_log`]), keeping the nominal value unless the search does better. A value whose
/// judging fails counts as worse than any that does not; the nominal one must not fail.
/// (`evaluations` is left 0 for the caller, who counts `judge`'s calls.)
fn search<E>(
    param: BeamParam,
    nominal: f64,
    mut judge: impl FnMut(f64) -> Result<Figures, E>,
) -> Result<Calibration, E> {
    let nominal_figures = judge(nominal)?;
    let best = golden_log(nominal, |log_v| {
        judge(log_v.exp()).map_or(f64::INFINITY, |f| f.objective)
    });
    let mut figures = judge(best.exp())?;
    let (value, at_edge) = if nominal_figures.objective <= figures.objective {
        figures = nominal_figures;
        (nominal, false)
    } else {
        (best.exp(), at_edge(nominal, best))
    };
    Ok(Calibration {
        param,
        nominal,
        value,
        nominal_figures,
        figures,
        at_edge,
        evaluations: 0,
    })
}

/// Golden-section search of `cost` over the logarithm of the value, within
/// [`CALIBRATION_RANGE`] of `nominal` either way, to a relative 1e-9: the best logarithm.
fn golden_log(nominal: f64, mut cost: impl FnMut(f64) -> f64) -> f64 {
    let (mut lo, mut hi) = (
        (nominal / CALIBRATION_RANGE).ln(),
        (nominal * CALIBRATION_RANGE).ln(),
    );
    let g = (5.0_f64.sqrt() - 1.0) / 2.0;
    let mut x1 = hi - g * (hi - lo);
    let mut x2 = lo + g * (hi - lo);
    let (mut f1, mut f2) = (cost(x1), cost(x2));
    while hi - lo > 1e-9 {
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = cost(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = cost(x2);
        }
    }
    0.5 * (lo + hi)
}

/// Whether the logarithm `best` is at the edge of the searched range around `nominal`.
fn at_edge(nominal: f64, best: f64) -> bool {
    (best - nominal.ln()).abs() > CALIBRATION_RANGE.ln() - 1e-3
}

/// Why a calibration has no answer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CalibrateError {
    /// The scene's truth is the beam itself.
    #[error(
        "the scene has no measured data to calibrate against (add [truth] data = \"file.csv\")"
    )]
    NoData,
    /// The beam cannot reach the data's loads.
    #[error("the beam cannot reach the measured loads: {0}")]
    Beam(BaselineError),
    /// The beam mechanism cannot follow the data's drives.
    #[error("the beam mechanism cannot follow the measured drives: {0}")]
    Mechanism(#[from] BesideError),
}
