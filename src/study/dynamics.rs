//! A study's dynamics (DESIGN §10): the truth's natural frequencies about its unloaded
//! equilibrium, the PRB model's about the same, and how they compare.
//!
//! When the scene gives `[beam] density`, [`Study`] computes the truth's first frequencies
//! once ([`TruthModes`]): a cantilever's beam with its `[tip]` body
//! ([`crate::beam::modes::unloaded_modes`]), a mechanism's beam mechanism with its `[stage]`
//! mass and inertia and the first drive's prescribed coordinates held
//! ([`crate::mech::modes::mech_modes`]). A measured-data scene has no dynamics of its own: its
//! frequencies are the nominal beam's (or beam mechanism's, with the coordinates the data's
//! drive prescribes held: [`Study::unloaded_held`]), and [`TruthModes::nominal`] says so.
//! The first mode shapes ([`Study::mode_shapes`]) pair the truth's and a PRB model's, every
//! kind of scene in the beam mechanism's form. A PRB model's frequencies ([`Study::prb_frequencies`]) come from its chain's
//! `K q = omega^2 M q` with the tip body (a cantilever) or from the whole PRB mechanism
//! ([`crate::mech::prb_modes`]), both about the unloaded equilibrium, in flexure 1's
//! `Omega = omega sqrt(rho A0 L^4 / (E I0))`.
//!
//! The unloaded equilibrium is the one the dynamic fit matches (`[fit] modes`): the
//! frequencies a simulator's model rings at about its rest pose, which the exports carry.

use serde::Serialize;

use crate::beam::modes::{
    unloaded_modes, FrequencyScale, ModePoint, ModeSettings, ModesError, TipBody as BeamTip,
};
use crate::beam::Load;
use crate::mech::figures::Frequencies;
use crate::mech::modes::{held_by, mech_modes, MechMass, MechModeShape};
use crate::mech::prb_modes::{prb_mode_shapes, unloaded_prb_modes, unloaded_state_held};
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
    /// The first [`SHOWN_MODES`] mode shapes for drawing, every kind of scene in the
    /// mechanism's form (a cantilever is its one-flexure mechanism, its tip the stage):
    /// global frame, flexure 1's units, the largest motion 1.
    pub shapes: Vec<MechModeShape>,
}

/// Stations per flexure of a drawn beam mode shape.
const SHAPE_POINTS: usize = 41;

/// One mode, the truth's and the PRB model's about the unloaded equilibrium, for drawing
/// over each other: a cantilever's (its one-flexure mechanism, the tip its stage) or a
/// mechanism's, in one form.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeShapePair {
    /// The beam's (beam mechanism's) frequency, Hz.
    pub beam_hz: f64,
    /// The model's, Hz.
    pub model_hz: f64,
    /// The beam's shape: its flexures' centre lines at 41 stations each and their motion,
    /// the stage's motion of `P` (global frame, flexure 1's units), the largest motion 1.
    pub beam: MechModeShape,
    /// The PRB model's: each chain's root, joints and tip and their motion, the stage's,
    /// the largest motion 1, its sign the one that correlates positively with the beam's.
    pub model: MechModeShape,
    /// The truth is measured data, which have no dynamics: the beam is the nominal one.
    pub nominal: bool,
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
    let (omega, shapes) = if scene.mechanism.is_none() {
        let settings = ModeSettings {
            shape_points: SHAPE_POINTS,
            ..ModeSettings::frequencies(count)
        };
        let modes = unloaded_modes(&scene.beam.model(), b, &settings)?;
        // The beam along +x from the origin is its one-flexure mechanism's flexure in the
        // global frame; the tip is the stage point.
        let shapes = modes
            .shapes
            .into_iter()
            .take(SHOWN_MODES)
            .map(|shape| MechModeShape {
                omega: shape.omega,
                stage: shape
                    .points
                    .last()
                    .map_or([0.0; 3], |p| [p.dx, p.dy, p.dpsi]),
                flexures: vec![shape.points],
            })
            .collect();
        (modes.omega, shapes)
    } else {
        let settings = ModeSettings {
            shape_points: SHAPE_POINTS,
            ..ModeSettings::frequencies(count)
        };
        let mass = MechMass::from_si(mechanism, density, scene.body.mass, scene.body.inertia)?;
        let held = unloaded_held(scene, mechanism);
        let modes = mech_modes(mechanism, &mass, held, None, &settings)?;
        let shapes = modes.shapes.into_iter().take(SHOWN_MODES).collect();
        (modes.omega, shapes)
    };
    Ok(TruthModes {
        omega,
        scale,
        body,
        nominal: scene.truth.is_some(),
        shapes,
    })
}

/// The stage coordinates held while the unloaded mechanism rings: its first drive's
/// prescribed ones, or on measured data (whose drives are the file's, not the mechanism's)
/// the data's prescribed columns; none for a cantilever.
fn unloaded_held(scene: &Scene, mechanism: &crate::scene::Mechanism) -> [bool; 3] {
    match mechanism.drives.first() {
        Some(drive) => held_by(drive),
        None => scene
            .truth
            .as_ref()
            .and_then(|t| t.stage.as_ref())
            .map_or([false; 3], |s| s.prescribed),
    }
}

impl Study {
    /// The stage coordinates held while the unloaded scene rings (`[x, y, phi]`): the first
    /// drive's prescribed ones, or a mechanism's measured data's.
    pub fn unloaded_held(&self) -> [bool; 3] {
        unloaded_held(self.scene(), self.mechanism())
    }

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
            None => unloaded_prb_modes(self.mechanism(), matrix, self.unloaded_held(), body),
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

    /// The first mode shapes about the unloaded equilibrium, the truth's and `matrix`'s
    /// over each other, paired lowest first (as many as both have, at most
    /// [`SHOWN_MODES`]): a cantilever's (its one-flexure mechanism) or a mechanism's, one
    /// path. Each model shape's sign is the one that correlates positively with the
    /// beam's. Empty without `[beam] density` or when the model has no modes.
    pub fn mode_shapes(&self, matrix: &PrbMatrix) -> Vec<ModeShapePair> {
        let Some(truth) = self.modes.as_ref() else {
            return Vec::new();
        };
        let mechanism = self.mechanism();
        let state = unloaded_state_held(mechanism, matrix, self.unloaded_held());
        let model =
            prb_mode_shapes(mechanism, matrix, &state, truth.body, SHOWN_MODES).unwrap_or_default();
        truth
            .shapes
            .iter()
            .zip(model)
            .map(|(beam, mut model)| {
                if correlation(beam, &model) < 0.0 {
                    flip(&mut model);
                }
                ModeShapePair {
                    beam_hz: truth.scale.hz(beam.omega),
                    model_hz: truth.scale.hz(model.omega),
                    beam: beam.clone(),
                    model,
                    nominal: truth.nominal,
                }
            })
            .collect()
    }
}

/// How `model`'s motion agrees with `beam`'s: the stage's `(dx, dy)` products and, at every
/// station of each of the model's flexures, its motion dotted with the beam's at the same
/// arc length (interpolated between the beam's stations).
fn correlation(beam: &MechModeShape, model: &MechModeShape) -> f64 {
    let mut sum = beam.stage[0] * model.stage[0] + beam.stage[1] * model.stage[1];
    for (line, points) in beam.flexures.iter().zip(&model.flexures) {
        for p in points {
            let [dx, dy] = motion_at(line, p.s);
            sum += dx * p.dx + dy * p.dy;
        }
    }
    sum
}

/// The motion of the centre line `line` (stations by arc length, ascending) at arc length
/// `s`, linear between stations.
fn motion_at(line: &[ModePoint], s: f64) -> [f64; 2] {
    let k = line.partition_point(|p| p.s < s);
    match (k.checked_sub(1).and_then(|i| line.get(i)), line.get(k)) {
        (Some(a), Some(b)) if b.s > a.s => {
            let t = (s - a.s) / (b.s - a.s);
            [a.dx + t * (b.dx - a.dx), a.dy + t * (b.dy - a.dy)]
        }
        (_, Some(b)) => [b.dx, b.dy],
        (Some(a), None) => [a.dx, a.dy],
        (None, None) => [0.0, 0.0],
    }
}

/// The same mode with its motion's sign turned.
fn flip(shape: &mut MechModeShape) {
    for v in &mut shape.stage {
        *v = -*v;
    }
    for p in shape.flexures.iter_mut().flatten() {
        p.dx = -p.dx;
        p.dy = -p.dy;
        p.dpsi = -p.dpsi;
    }
}
