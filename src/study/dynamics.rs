//! A study's dynamics (DESIGN §10): the truth's natural frequencies about its unloaded
//! equilibrium, the PRB model's about the same, and how they compare.
//!
//! When the scene gives `[beam] density`, [`Study`] computes the truth's first frequencies
//! once ([`TruthModes`]): a cantilever's beam with its `[tip]` body
//! ([`crate::beam::modes::unloaded_modes`]), a mechanism's beam mechanism with its `[stage]`
//! mass and inertia and the first drive's prescribed coordinates held
//! ([`crate::mech::modes::mech_modes`]). A measured-data scene has no dynamics of its own: its
//! frequencies are the nominal beam's (or beam mechanism's), and [`TruthModes::nominal`] says
//! so. A PRB model's frequencies ([`Study::prb_frequencies`]) come from its chain's
//! `K q = omega^2 M q` with the tip body (a cantilever) or from the whole PRB mechanism
//! ([`crate::mech::prb_modes`]), both about the unloaded equilibrium, in flexure 1's
//! `Omega = omega sqrt(rho A0 L^4 / (E I0))`.
//!
//! The unloaded equilibrium is the one the dynamic fit matches (`[fit] modes`): the
//! frequencies a simulator's model rings at about its rest pose, which the exports carry.

use serde::Serialize;

use crate::beam::modes::{
    unloaded_modes, FrequencyScale, ModeSettings, ModesError, TipBody as BeamTip,
};
use crate::beam::Load;
use crate::mech::figures::Frequencies;
use crate::mech::modes::{held_by, mech_modes, MechMass};
use crate::mech::prb_modes::{prb_modes, unloaded_state};
use crate::prb::{PrbMatrix, PrbSolver, TipBody};
use crate::scene::Scene;

use super::Study;

/// How many of the truth's frequencies a study keeps when the scene asks for fewer (what
/// the UI and reports show).
pub const SHOWN_MODES: usize = 3;

/// The truth's natural frequencies about its unloaded equilibrium.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TruthModes {
    /// `Omega` (flexure 1's), lowest first: `max([fit] modes, SHOWN_MODES)` of them.
    pub omega: Vec<f64>,
    /// rad/s per unit of `Omega` (flexure 1's section, `[beam] density`).
    pub scale: FrequencyScale,
    /// The tip body (a mechanism's stage) in flexure 1's `rho A0 L` and `rho A0 L^3`.
    pub body: TipBody,
    /// The truth is measured data, which has no dynamics: these are the nominal beam's.
    pub nominal: bool,
    /// A cantilever's mode shapes for drawing: per mode, `(s, dy)` along the unloaded beam,
    /// the tip's motion 1 (empty for a mechanism).
    pub shapes: Vec<Vec<[f64; 2]>>,
}

/// Stations per drawn beam mode shape.
const SHAPE_POINTS: usize = 41;

/// One mode of a cantilever, the beam's and the PRB model's, for drawing over each other.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeShapePair {
    /// The beam's frequency, Hz.
    pub beam_hz: f64,
    /// The model's, Hz.
    pub model_hz: f64,
    /// The beam's transverse motion `(s, dy)` along the unloaded beam (units of L), the
    /// tip's 1.
    pub beam: Vec<[f64; 2]>,
    /// The PRB chain's at its root, joints and tip, the tip's 1.
    pub model: Vec<[f64; 2]>,
}

impl TruthModes {
    /// The truth's frequencies for `scene` as `mechanism` (its one-flexure mechanism for a
    /// cantilever); `None` without `[beam] density`.
    pub(super) fn of(
        scene: &Scene,
        mechanism: &crate::scene::Mechanism,
    ) -> Option<Result<TruthModes, ModesError>> {
        let density = scene.beam.density?;
        let count = (scene.fit.modes as usize).max(SHOWN_MODES);
        Some(truth_modes(scene, mechanism, density, count))
    }
}

/// Flexure 1's frequency scale (rad/s per unit `Omega`) at `density`: the scale of every
/// `Omega` of the scene, the truth's and the models'.
pub(super) fn frequency_scale(
    scene: &Scene,
    mechanism: &crate::scene::Mechanism,
    density: f64,
) -> Result<FrequencyScale, ModesError> {
    let first = mechanism.flexures.first().map_or(scene.beam, |f| f.beam);
    FrequencyScale::rectangle(first.youngs_modulus, density, first.length, first.thickness)
}

fn truth_modes(
    scene: &Scene,
    mechanism: &crate::scene::Mechanism,
    density: f64,
    count: usize,
) -> Result<TruthModes, ModesError> {
    let first = mechanism.flexures.first().map_or(scene.beam, |f| f.beam);
    let scale = frequency_scale(scene, mechanism, density)?;
    let b = BeamTip::from_si(
        scene.body.mass,
        scene.body.inertia,
        density,
        first.width,
        first.thickness,
        first.length,
    )?;
    let body = TipBody {
        mass: b.mass,
        inertia: b.inertia,
    };
    let mut shapes = Vec::new();
    let omega = if scene.mechanism.is_none() {
        let settings = ModeSettings {
            shape_points: SHAPE_POINTS,
            ..ModeSettings::frequencies(count)
        };
        let modes = unloaded_modes(&scene.beam.model(), b, &settings)?;
        shapes = modes
            .shapes
            .iter()
            .map(|shape| {
                let tip = shape.points.last().map_or(1.0, |p| p.dy);
                let scale = if tip == 0.0 { 1.0 } else { 1.0 / tip };
                shape.points.iter().map(|p| [p.s, scale * p.dy]).collect()
            })
            .collect();
        modes.omega
    } else {
        let settings = ModeSettings::frequencies(count);
        let mass = MechMass::from_si(mechanism, density, scene.body.mass, scene.body.inertia)?;
        let held = mechanism.drives.first().map_or([false; 3], held_by);
        mech_modes(mechanism, &mass, held, None, &settings)?.omega
    };
    Ok(TruthModes {
        omega,
        scale,
        body,
        nominal: scene.truth.is_some(),
        shapes,
    })
}

impl Study {
    /// The truth's natural frequencies, when the scene gives `[beam] density`.
    pub fn truth_modes(&self) -> Option<&TruthModes> {
        self.modes.as_ref()
    }

    /// The PRB model `matrix`'s natural frequencies `Omega` (flexure 1's) about its
    /// unloaded equilibrium, lowest first, with the scene's tip body or stage (nondimensional
    /// `body`).
    pub fn prb_frequencies(
        &self,
        matrix: &PrbMatrix,
        body: TipBody,
    ) -> Result<Vec<f64>, crate::prb::ModesError> {
        match self.baseline() {
            Some(baseline) => {
                let chain = PrbSolver::new(matrix, baseline.model.axial_compliance());
                let q = vec![0.0; chain.dof_count()];
                chain.modes(Load::new(0.0, 0.0, 0.0), &q, body)
            }
            None => {
                let state = unloaded_state(self.mechanism(), matrix);
                prb_modes(self.mechanism(), matrix, &state, body)
            }
        }
    }

    /// `matrix`'s frequencies against the truth's; `None` without `[beam] density`. A model
    /// that is unstable unloaded (it never is with positive springs) has none.
    pub fn frequencies(&self, matrix: &PrbMatrix) -> Option<Frequencies> {
        let truth = self.modes.as_ref()?;
        let model = self.prb_frequencies(matrix, truth.body).unwrap_or_default();
        let model: Vec<f64> = model.into_iter().take(truth.omega.len()).collect();
        let hz = |v: &[f64]| v.iter().map(|&w| truth.scale.hz(w)).collect();
        Some(Frequencies {
            beam_hz: hz(&truth.omega),
            model_hz: hz(&model),
            freq_err: model
                .iter()
                .zip(&truth.omega)
                .map(|(m, b)| m / b - 1.0)
                .collect(),
            beam: truth.omega.clone(),
            model,
            judged: self.scene().fit.modes as usize,
            nominal: truth.nominal,
        })
    }

    /// A cantilever's first mode shapes, the beam's and `matrix`'s over each other (as many
    /// as both have, at most [`SHOWN_MODES`]); empty for a mechanism or without `[beam]
    /// density`.
    pub fn mode_shapes(&self, matrix: &PrbMatrix) -> Vec<ModeShapePair> {
        let (Some(truth), Some(baseline)) = (self.modes.as_ref(), self.baseline()) else {
            return Vec::new();
        };
        let chain = PrbSolver::new(matrix, baseline.model.axial_compliance());
        let model = chain
            .unloaded_shapes(truth.body, SHOWN_MODES)
            .unwrap_or_default();
        truth
            .shapes
            .iter()
            .zip(&truth.omega)
            .zip(model)
            .map(|((beam, &w), (wm, shape))| ModeShapePair {
                beam_hz: truth.scale.hz(w),
                model_hz: truth.scale.hz(wm),
                beam: beam.clone(),
                model: shape,
            })
            .collect()
    }
}
