//! The scene's beam in SI units (DESIGN §1, §5): its size, material and effects, the
//! nondimensional [`BeamModel`] the solver works on, and the rules a beam obeys
//! ([`BeamSpec::validate`]).
//!
//! `effects = "auto"` is decided from the beam, the loads and the targets by
//! [`crate::select::decide_effects`]; code that has not decided it (a scene just read)
//! treats it as every effect on, the safe superset.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::beam::{cowper_kappa, BeamModel, Effects};

use super::error::RuleError;
use super::rules;

/// Which beam effects the scene asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum EffectsChoice {
    /// Decide from the beam and loads (for now: all effects on).
    Auto,
    /// Exactly these effects.
    Fixed(Effects),
}

impl EffectsChoice {
    /// The effects the baseline uses.
    pub fn resolve(&self) -> Effects {
        match self {
            EffectsChoice::Auto => Effects::ALL,
            EffectsChoice::Fixed(e) => *e,
        }
    }
}

impl fmt::Display for EffectsChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EffectsChoice::Auto => write!(f, "auto"),
            EffectsChoice::Fixed(e) => write!(f, "{e}"),
        }
    }
}

/// The beam in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BeamSpec {
    /// m
    pub length: f64,
    /// m
    pub width: f64,
    /// m
    pub thickness: f64,
    /// Pa
    pub youngs_modulus: f64,
    /// `nu`, in `[0, 0.5)`.
    pub poisson_ratio: f64,
    /// `None`: Cowper's rectangle value.
    pub shear_coefficient: Option<f64>,
    /// Which effects of DESIGN §2 the beam models.
    pub effects: EffectsChoice,
    /// kg/m^3: the beam's mass for its natural frequencies and the exports (DESIGN §10);
    /// `None` when the scene gives none (`modes` then asks for it, exports prompt).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Pa: the largest fibre stress the designer allows (yield or fatigue limit over a safety
    /// factor), which sets each path's stroke limit (DESIGN §11); `None`: no limit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub allowable_stress: Option<f64>,
}

impl BeamSpec {
    /// For the crate's tests: a beam of unit length and width (`E = 12e6`, so
    /// `E I0 = 1e6 thickness^3`), the plain elastica.
    #[cfg(test)]
    pub(crate) fn unit_elastica(thickness: f64) -> BeamSpec {
        BeamSpec {
            length: 1.0,
            width: 1.0,
            thickness,
            youngs_modulus: 12e6,
            poisson_ratio: 0.3,
            shear_coefficient: None,
            density: None,
            effects: EffectsChoice::Fixed(crate::beam::Effects::NONE),
            allowable_stress: None,
        }
    }

    /// `L / t0`.
    pub fn slenderness(&self) -> f64 {
        rules::slenderness_of(self.length, self.thickness)
    }

    /// `kappa` in use: the given one or Cowper's.
    pub fn kappa(&self) -> f64 {
        self.shear_coefficient
            .unwrap_or_else(|| cowper_kappa(self.poisson_ratio))
    }

    /// `A0 = w0 t0`.
    pub fn area(&self) -> f64 {
        self.width * self.thickness
    }

    /// `I0 = w0 t0^3 / 12`.
    pub fn second_moment(&self) -> f64 {
        self.width * self.thickness.powi(3) / 12.0
    }

    /// The nondimensional beam the solver works on.
    ///
    /// # Panics
    /// On a beam that breaks the scene's rules: every scene is validated where it is made (a
    /// file by its reader, an edit by [`Scene::validate`](super::Scene::validate)), so that
    /// is a bug, never input.
    #[allow(clippy::expect_used)]
    pub fn model(&self) -> BeamModel {
        BeamModel::new(
            self.slenderness(),
            self.poisson_ratio,
            self.shear_coefficient,
            self.effects.resolve(),
        )
        .expect("a validated scene describes a valid beam")
        .with_width_ratio(self.width / self.thickness)
    }

    /// Checks the beam's rules: sizes from [`MIN_SIZE`](super::rules::MIN_SIZE) to
    /// [`MAX_SIZE`](super::rules::MAX_SIZE), a modulus and an allowable stress finite, `> 0`
    /// and at most [`MAX_MODULUS`](super::MAX_MODULUS), `1 <= L/t0 <=`
    /// [`MAX_SLENDERNESS`](crate::beam::MAX_SLENDERNESS) (named by `thickness`), `nu` in
    /// `[0, 0.5)`, a given shear coefficient `> 0` and at most
    /// [`MAX_KAPPA`](crate::beam::MAX_KAPPA), a given density from
    /// [`MIN_DENSITY`](super::rules::MIN_DENSITY) to [`MAX_DENSITY`](super::rules::MAX_DENSITY),
    /// effects that go together. Keys are the
    /// beam's own (`thickness`); a scene puts them under `beam`, a flexure under its table.
    pub fn validate(&self) -> Result<(), RuleError> {
        let check = |key: &str, r: Result<(), String>| r.map_err(|m| RuleError::new(key, m));
        check("length", rules::size(self.length))?;
        check("width", rules::size(self.width))?;
        check("thickness", rules::size(self.thickness))?;
        check("thickness", rules::slenderness(self.thickness, self.length))?;
        check("youngs_modulus", rules::modulus(self.youngs_modulus))?;
        check("poisson_ratio", rules::poisson_ratio(self.poisson_ratio))?;
        if let Some(k) = self.shear_coefficient {
            check("shear_coefficient", rules::shear_coefficient(k))?;
        }
        if let Some(rho) = self.density {
            check("density", rules::density(rho))?;
        }
        if let Some(s) = self.allowable_stress {
            check("allowable_stress", rules::allowable_stress(s))?;
        }
        if let EffectsChoice::Fixed(e) = self.effects {
            e.validate()
                .map_err(|e| RuleError::new("effects", e.to_string()))?;
        }
        Ok(())
    }
}
