//! The scene's natural frequencies (DESIGN §10): the truth's and PRB models' small free
//! vibration about the same equilibria, for every kind of scene in one form.
//!
//! The scene is the study's mechanism (a cantilever is the one-flexure mechanism of §8, its
//! `[tip]` body the stage's mass and inertia about the stage point, the tip), so one path
//! serves both:
//! - the truth: the beam mechanism's modes ([`crate::mech::modes::mech_modes`], each
//!   flexure the §2 beam with its distributed mass, the stage rigid) about each equilibrium;
//! - a PRB model: the PRB mechanism's ([`crate::mech::prb_modes::prb_modes`]) about its own
//!   equilibrium under the same load (the model's statics followed along the same drive).
//!
//! The equilibria ([`Equilibria`]): the unloaded one (the first drive's prescribed
//! coordinates held, as the PRB side holds them; on measured data the data's prescribed
//! columns, [`Study::unloaded_held`]), one tip load of a cantilever (the beam's
//! statics first: a load past buckling gets their own message), or every case of the
//! scene's paths. Measured data are not dynamic: a data scene's modes are its nominal
//! beam's, and its cases the nominal beam's equilibria under the measured loads.
//!
//! Frequencies are flexure 1's `Omega = omega sqrt(rho A0 L^4 / (E I0))` and in Hz with the
//! scene's `[beam] density` (required: without it there is no mass).

use serde::Serialize;

use crate::beam::modes::{FrequencyScale, ModeSettings, ModesError, MAX_MODES};
use crate::beam::{BeamSolver, Load};
use crate::cancel::CancelToken;
use crate::mech::modes::{held_by, mech_modes, MechMass};
use crate::mech::prb_modes::prb_modes;
use crate::mech::{exact, prb, MechCase, MechError};
use crate::prb::{PrbMatrix, TipBody};
use crate::scene::{Coordinate, Drive, Mechanism};
use crate::si::load_si;

use super::dynamics::frequency_scale;
use super::{truth, Study, PRB_TOL};

/// About which equilibria the modes are found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Equilibria {
    /// The unloaded scene.
    Unloaded,
    /// One tip load of a cantilever (nondimensional).
    Load(Load),
    /// Every case of every load path or drive.
    Cases,
}

/// One set of frequencies: nondimensional and in Hz.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Frequencies {
    /// Flexure 1's `Omega`, ascending.
    pub omega: Vec<f64>,
    /// The same in Hz.
    pub hz: Vec<f64>,
}

/// One PRB model's frequencies at an equilibrium, against the truth's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelModes {
    /// `Omega`, ascending: the first `count`, or as many as the model has.
    pub omega: Vec<f64>,
    /// The same in Hz.
    pub hz: Vec<f64>,
    /// Per frequency, `Omega_PRB / Omega_beam - 1`.
    pub freq_err: Vec<f64>,
}

impl ModelModes {
    /// The largest `|freq_err|`.
    pub fn worst(&self) -> f64 {
        self.freq_err.iter().fold(0.0, |a, e| a.max(e.abs()))
    }
}

/// The modes about one equilibrium.
#[derive(Debug, Clone, PartialEq)]
pub struct EquilibriumModes {
    /// The path or drive (from 1), `None` for the unloaded scene or a given load.
    pub path: Option<usize>,
    /// The fraction of the path.
    pub fraction: f64,
    /// The stage (a cantilever's tip) load, flexure 1's units.
    pub load: [f64; 3],
    /// The truth's frequencies.
    pub beam: Frequencies,
    /// Per model asked, its frequencies or why it has none here.
    pub models: Vec<Result<ModelModes, String>>,
}

/// Why the modes could not be had.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StudyModesError {
    /// The scene has no `[beam] density`.
    #[error(
        "beam.density: the modes need the beam's density (kg/m^3); add it to the scene's \
         [beam] table, e.g. density = 7850.0"
    )]
    NoDensity,
    /// No mode asked for.
    #[error("the number of modes must be at least 1")]
    NoModes,
    /// More modes asked for than the beam's discretisation resolves.
    #[error(
        "--count {0}: at most {MAX_MODES} modes (the beam's discretisation resolves no more to \
         its accuracy)"
    )]
    TooManyModes(usize),
    /// A tip load given to a mechanism scene (its loads are its drives).
    #[error(
        "a mechanism's loads are its [[drives]]: its modes are the unloaded ones or every case's"
    )]
    LoadOnMechanism,
    /// The beam's statics failed (their own message).
    #[error(transparent)]
    Statics(#[from] crate::beam::SolveError),
    /// The beam mechanism's statics failed (their own message).
    #[error(transparent)]
    Mechanism(#[from] MechError),
    /// The truth's modes failed.
    #[error(transparent)]
    Modes(#[from] ModesError),
    /// Cancelled before every equilibrium's modes were found.
    #[error("cancelled")]
    Cancelled,
}

impl StudyModesError {
    /// Whether this is bad input (a missing key, a bad count, a flag that does not apply)
    /// rather than a failed computation.
    pub fn is_input(&self) -> bool {
        matches!(
            self,
            StudyModesError::NoDensity
                | StudyModesError::NoModes
                | StudyModesError::TooManyModes(_)
                | StudyModesError::LoadOnMechanism
                | StudyModesError::Modes(ModesError::BadInput(_))
        )
    }
}

impl Study {
    /// The density the modes use: the scene's `[beam] density`.
    pub fn density(&self) -> Result<f64, StudyModesError> {
        self.scene.beam.density.ok_or(StudyModesError::NoDensity)
    }

    /// Flexure 1's frequency scale (rad/s per unit `Omega`) at the scene's density.
    pub fn frequency_scale(&self) -> Result<FrequencyScale, StudyModesError> {
        Ok(frequency_scale(
            &self.scene,
            &self.mechanism,
            self.density()?,
        )?)
    }

    /// The first `count` natural frequencies of the truth and of each of `models` about the
    /// equilibria `at` (module docs).
    ///
    /// Stops with [`StudyModesError::Cancelled`] soon after `cancel` is cancelled (between
    /// equilibria: each costs one eigenproblem per model and the truth's).
    pub fn modes(
        &self,
        models: &[PrbMatrix],
        at: Equilibria,
        count: usize,
        cancel: &CancelToken,
    ) -> Result<Vec<EquilibriumModes>, StudyModesError> {
        if count == 0 {
            return Err(StudyModesError::NoModes);
        }
        if count > MAX_MODES {
            return Err(StudyModesError::TooManyModes(count));
        }
        let density = self.density()?;
        let scale = self.frequency_scale()?;
        let body = self.scene.body;
        let mass = MechMass::from_si(&self.mechanism, density, body.mass, body.inertia)?;
        let stage = TipBody {
            mass: mass.stage_mass,
            inertia: mass.stage_inertia,
        };
        let settings = ModeSettings::frequencies(count);
        let hz = |omega: &[f64]| omega.iter().map(|&w| scale.hz(w)).collect::<Vec<f64>>();
        let row = |omega: Vec<f64>| Frequencies {
            hz: hz(&omega),
            omega,
        };
        let compare = |beam: &[f64], omega: Result<Vec<f64>, String>| {
            omega.map(|mut w| {
                w.truncate(count);
                let freq_err = w.iter().zip(beam).map(|(p, b)| p / b - 1.0).collect();
                ModelModes {
                    hz: hz(&w),
                    omega: w,
                    freq_err,
                }
            })
        };
        match at {
            Equilibria::Unloaded => {
                // The study's own unloaded frequencies (those judge and fit use) when it has
                // as many as asked; the same solve for more.
                let beam = match self.truth_modes() {
                    Some(t) if t.omega.len() >= count => t.omega[..count].to_vec(),
                    _ => {
                        let held = self.unloaded_held();
                        mech_modes(&self.mechanism, &mass, held, None, &settings)?.omega
                    }
                };
                let models = models
                    .iter()
                    .map(|m| {
                        let w = self.prb_frequencies(m, stage).map_err(|e| e.to_string());
                        compare(&beam, w)
                    })
                    .collect();
                Ok(vec![EquilibriumModes {
                    path: None,
                    fraction: 0.0,
                    load: [0.0; 3],
                    beam: row(beam),
                    models,
                }])
            }
            Equilibria::Load(load) => {
                if self.scene.mechanism.is_some() {
                    return Err(StudyModesError::LoadOnMechanism);
                }
                // The beam's own statics (their message past buckling), in the stage form.
                let solver = BeamSolver::new(self.scene.beam.model(), self.resolution)?;
                let sol = solver.solve(load)?;
                let case = truth::tip_case(1.0, load, sol.tip, sol.iterations, sol.stress);
                // The same load as the only drive of the one-flexure mechanism, for the
                // models' statics.
                let mut mech = self.mechanism.clone();
                mech.drives = vec![Drive::proportional(
                    load_si(&self.scene.beam, &load).map(Coordinate::Loaded),
                    self.scene.loads.first().map_or(8, |p| p.steps.max(1)),
                )];
                let beam = mech_modes(&mech, &mass, [false; 3], Some(&case), &settings)?.omega;
                let models = models
                    .iter()
                    .map(|m| compare(&beam, last_case_modes(&mech, m, stage, cancel)))
                    .collect();
                Ok(vec![EquilibriumModes {
                    path: None,
                    fraction: 1.0,
                    load: [load.alpha_x, load.alpha_y, load.beta],
                    beam: row(beam),
                    models,
                }])
            }
            Equilibria::Cases => {
                // Measured data are not dynamic: the nominal beam's equilibria under the
                // measured loads.
                let nominal;
                let truth: &[Vec<MechCase>] = if self.is_measured() {
                    nominal = exact::solve(&self.mechanism, self.resolution)?;
                    &nominal
                } else {
                    &self.truth
                };
                let followed: Vec<prb::Followed> = models
                    .iter()
                    .map(|m| prb::follow(&self.mechanism, m, PRB_TOL, cancel))
                    .collect();
                let mut out = Vec::new();
                for (d, (drive, cases)) in self.mechanism.drives.iter().zip(truth).enumerate() {
                    let held = held_by(drive);
                    for (k, case) in cases.iter().enumerate() {
                        if cancel.is_cancelled() {
                            return Err(StudyModesError::Cancelled);
                        }
                        let beam =
                            mech_modes(&self.mechanism, &mass, held, Some(case), &settings)?.omega;
                        let models = models
                            .iter()
                            .zip(&followed)
                            .map(|(m, f)| {
                                compare(&beam, case_modes(&self.mechanism, m, f, d, k, stage))
                            })
                            .collect();
                        out.push(EquilibriumModes {
                            path: Some(d + 1),
                            fraction: case.fraction,
                            load: case.stage_load,
                            beam: row(beam),
                            models,
                        });
                    }
                }
                Ok(out)
            }
        }
    }
}

/// A model's frequencies at case `k` of drive `d` as it followed the drives.
fn case_modes(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    followed: &prb::Followed,
    d: usize,
    k: usize,
    stage: TipBody,
) -> Result<Vec<f64>, String> {
    match followed.drives.get(d).and_then(|cases| cases.get(k)) {
        Some(case) => {
            let state = case
                .state
                .as_ref()
                .ok_or_else(|| "no solver state at this case".to_string())?;
            prb_modes(mechanism, matrix, state, stage).map_err(|e| e.to_string())
        }
        None => Err(match followed.failures.get(d) {
            Some(Some(e)) => format!("the model does not reach this case: {e}"),
            _ => "the model does not reach this case".to_string(),
        }),
    }
}

/// A model's frequencies at the end of `mechanism`'s only drive (its last case; a model
/// that stops short of it has none, and says why).
fn last_case_modes(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    stage: TipBody,
    cancel: &CancelToken,
) -> Result<Vec<f64>, String> {
    let followed = prb::follow(mechanism, matrix, PRB_TOL, cancel);
    let steps = mechanism
        .drives
        .first()
        .map_or(1, |d| d.steps.max(1) as usize);
    case_modes(mechanism, matrix, &followed, 0, steps - 1, stage)
}
