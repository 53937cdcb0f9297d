//! What a scene asks of a model (DESIGN §4, §8): the accuracy targets that say "good enough"
//! and the fit's weights, with their defaults and rules.

use serde::{Deserialize, Serialize};

use super::error::RuleError;
use super::rules;

/// What "good enough" means for a scene.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Accuracy {
    /// Units of L.
    pub max_pos_err: f64,
    /// Radians.
    pub max_ang_err: f64,
    /// Mechanism scenes: the largest reaction error of a prescribed stage coordinate, as a
    /// fraction of that coordinate's largest reaction over the scene (DESIGN §8).
    #[serde(default = "default_force_err")]
    pub max_force_err: f64,
    /// The largest relative error of a PRB model's first `[fit] modes` natural frequencies
    /// against the truth's, `|Omega_PRB,i / Omega_beam,i - 1|` (DESIGN §10).
    #[serde(default = "default_freq_err")]
    pub max_freq_err: f64,
}

fn default_freq_err() -> f64 {
    0.01
}

fn default_force_err() -> f64 {
    0.05
}

impl Default for Accuracy {
    fn default() -> Self {
        Accuracy {
            max_pos_err: 0.01,
            max_ang_err: 0.02,
            max_force_err: default_force_err(),
            max_freq_err: default_freq_err(),
        }
    }
}

impl Accuracy {
    /// Every target finite and `> 0`; a scene puts the keys under `accuracy`.
    pub fn validate(&self) -> Result<(), RuleError> {
        for (key, v) in [
            ("max_pos_err", self.max_pos_err),
            ("max_ang_err", self.max_ang_err),
            ("max_force_err", self.max_force_err),
            ("max_freq_err", self.max_freq_err),
        ] {
            rules::positive(v).map_err(|m| RuleError::new(key, m))?;
        }
        Ok(())
    }
}

/// A rigid body carried at the end of the flexures (DESIGN §10): a cantilever's `[tip]` body
/// (its centre of mass at the tip point) or a mechanism's `[stage]` (its centre of mass at the
/// stage point P). SI; absent = 0.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Body {
    /// kg.
    pub mass: f64,
    /// kg m^2, about the centre of mass.
    pub inertia: f64,
}

impl Body {
    /// Mass and inertia finite and `>= 0`; a scene puts the keys under `tip` or `stage`.
    pub fn validate(&self) -> Result<(), RuleError> {
        rules::non_negative(self.mass).map_err(|m| RuleError::new("mass", m))?;
        rules::non_negative(self.inertia).map_err(|m| RuleError::new("inertia", m))
    }

    /// Whether the body has neither mass nor inertia.
    pub fn is_none(&self) -> bool {
        self.mass == 0.0 && self.inertia == 0.0
    }
}

/// Settings of the fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FitSettings {
    /// `w` in `J = mean(e_pos^2 + w e_ang^2)`.
    pub angle_weight: f64,
    /// Mechanism scenes: `w_f` in `J = mean(e_pos^2 + w e_ang^2 + w_f e_force^2)`.
    #[serde(default = "default_force_weight")]
    pub force_weight: f64,
    /// How many of the first natural frequencies the fit matches beside the statics
    /// (DESIGN §10); 0 (the default): statics only.
    #[serde(default)]
    pub modes: u32,
    /// `w_omega` in `J += w_omega mean_i (Omega_PRB,i / Omega_beam,i - 1)^2`.
    #[serde(default = "default_force_weight")]
    pub frequency_weight: f64,
}

fn default_force_weight() -> f64 {
    1.0
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            angle_weight: 1.0,
            force_weight: default_force_weight(),
            modes: 0,
            frequency_weight: default_force_weight(),
        }
    }
}

impl FitSettings {
    /// Every weight finite and `>= 0`; a scene puts the keys under `fit`.
    pub fn validate(&self) -> Result<(), RuleError> {
        for (key, v) in [
            ("angle_weight", self.angle_weight),
            ("force_weight", self.force_weight),
            ("frequency_weight", self.frequency_weight),
        ] {
            rules::weight(v).map_err(|m| RuleError::new(key, m))?;
        }
        rules::modes(i64::from(self.modes)).map_err(|m| RuleError::new("modes", m))?;
        Ok(())
    }
}
