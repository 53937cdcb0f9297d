//! The beam's cross-section and constitutive law, nondimensional (L = 1, E I0 = 1).
//!
//! DESIGN §2: with the section rotated by `psi`, the tip load `(alpha_x, alpha_y)` splits into
//! the axial force `N = alpha_x cos psi + alpha_y sin psi` and the shear force
//! `Q = -alpha_x sin psi + alpha_y cos psi`. The strains are
//!
//! ```text
//! eps   = N / (E A)          with  E A  = E A0 (1 - nu eps)^2     [extension, poisson]
//! gamma = Q / (kappa G A)                                        [shear]
//! ```
//!
//! In units of `E I0 / L^2` for forces, `E A0 = 1 / c_e` with `c_e = I0 / (A0 L^2) =
//! 1 / (12 (L/t0)^2)` and `kappa G A0 = 1 / c_s` with `c_s = c_e 2 (1 + nu) / kappa`.
//!
//! With plane strain on (a wide section, see [`Effects::plane_strain`]) the bending and axial
//! stiffnesses take the modulus `E / (1 - nu^2 phi)`, `phi` the section's plate fraction
//! (1: the plate modulus `E / (1 - nu^2)`; see [`crate::beam::plate`]): the curvature
//! `M / (E I)` and the axial strain are multiplied by `1 - nu^2 phi`; the shear modulus `G`
//! is unchanged, and so is
//! the Poisson shrink law below (an approximation: in plane strain only the thickness
//! shrinks, by `nu / (1 - nu)` of the strain; the shrink is a second-order effect either way).
//! The PRB matrix keeps the nominal scale `E I0 / L`, `E A0 / L`.
//!
//! With Poisson on, `eps (1 - nu eps)^2 = c_e N` is solved for `eps` by a bracketed Newton
//! iteration. The left side peaks at `eps = 1 / (3 nu)` (value `4 / (27 nu)`): a tension above
//! that has no equilibrium in this material law (the section necks), and a compression that
//! drives `1 + eps` to zero crushes the beam. Both are reported, never papered over.

use std::fmt;

use serde::{Deserialize, Serialize};

/// Which of the modified-Timoshenko effects the beam model includes (DESIGN §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
pub struct Effects {
    /// Shear strain `gamma = Q / (kappa G A)`.
    pub shear: bool,
    /// Axial strain `eps = N / (E A)`.
    pub extension: bool,
    /// The section shrinks with the axial strain (needs `extension`).
    pub poisson: bool,
    /// Plane strain: the plate stiffening of a wide section, the modulus `E / (1 - nu^2 phi)`
    /// in bending and stretching. `phi`, the plate fraction, is 1 for a section so wide it
    /// cannot curl across (no anticlastic curvature: the plate modulus `E / (1 - nu^2)`), 0
    /// for the narrow beam, and in between for a strip: the ends' share from `w0 / t0` and
    /// `w0 / L`, raised case by case by the anticlastic share of its curvature
    /// ([`crate::beam::plate`], checked against 3D FEA).
    #[serde(default)]
    pub plane_strain: bool,
}

impl Effects {
    /// The inextensible Euler-Bernoulli elastica.
    pub const NONE: Effects = Effects {
        shear: false,
        extension: false,
        poisson: false,
        plane_strain: false,
    };
    /// Every refinement of the narrow beam on: shear, extension and Poisson. Plane strain is
    /// not one (it is the wide section's limit, named on its own), so it stays off.
    pub const ALL: Effects = Effects {
        shear: true,
        extension: true,
        poisson: true,
        plane_strain: false,
    };

    /// These effects with plane strain switched to `on`.
    pub const fn with_plane_strain(self, on: bool) -> Effects {
        Effects {
            plane_strain: on,
            ..self
        }
    }

    /// Parses `none`, `all` (shear, extension and Poisson) or a comma-separated list such as
    /// `shear,extension` or `all,plane_strain`.
    pub fn parse_list(text: &str) -> Result<Effects, ModelError> {
        let trimmed = text.trim();
        match trimmed {
            "none" | "" => return Ok(Effects::NONE),
            "all" => return Ok(Effects::ALL),
            _ => {}
        }
        let mut effects = Effects::NONE;
        for word in trimmed.split(',').map(str::trim) {
            if word == "all" {
                effects = Effects::ALL.with_plane_strain(effects.plane_strain);
                continue;
            }
            if word == "none" {
                // `none` alone is the empty list; beside effects it contradicts them.
                return Err(ModelError::NoneWithOthers);
            }
            effects.set(word)?;
        }
        effects.validate()?;
        Ok(effects)
    }

    /// Switches on the effect called `name`.
    pub fn set(&mut self, name: &str) -> Result<(), ModelError> {
        match name {
            "shear" => self.shear = true,
            "extension" => self.extension = true,
            "poisson" => self.poisson = true,
            "plane_strain" => self.plane_strain = true,
            other => return Err(ModelError::UnknownEffect(other.to_string())),
        }
        Ok(())
    }

    /// Poisson's effect acts through the axial strain, so it needs `extension`.
    pub fn validate(&self) -> Result<(), ModelError> {
        if self.poisson && !self.extension {
            return Err(ModelError::PoissonWithoutExtension);
        }
        Ok(())
    }

    /// The names of the effects that are on, in the canonical order.
    pub fn names(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        if self.shear {
            out.push("shear");
        }
        if self.extension {
            out.push("extension");
        }
        if self.poisson {
            out.push("poisson");
        }
        if self.plane_strain {
            out.push("plane_strain");
        }
        out
    }
}

impl fmt::Display for Effects {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names = self.names();
        if names.is_empty() {
            write!(f, "none")
        } else {
            write!(f, "{}", names.join(","))
        }
    }
}

/// Errors in the description of a beam.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// The slenderness `L / t0` is not finite or lies outside `[1, MAX_SLENDERNESS]`.
    #[error(
        "slenderness L/t0 must be from 1 (a beam at least as long as it is thick) to {MAX_SLENDERNESS:e}, got {}", crate::text::bounded(*.0)
    )]
    Slenderness(f64),
    /// Poisson's ratio `nu` is not finite or lies outside `[0, 0.5)`.
    #[error("Poisson's ratio must be in [0, 0.5), got {}", crate::text::bounded(*.0))]
    PoissonRatio(f64),
    /// The shear coefficient `kappa` (given, or Cowper's from `nu`) is not a finite number
    /// `> 0` and at most [`MAX_KAPPA`].
    #[error(
        "shear coefficient kappa must be a finite number > 0 and at most {MAX_KAPPA} (real \
         sections' lie between about 0.5 and 1), got {}",
        crate::text::bounded(*.0)
    )]
    ShearCoefficient(f64),
    /// An effect name other than `shear`, `extension`, `poisson` or `plane_strain` (the name
    /// given).
    #[error(
        "unknown effect `{0}` (expected shear, extension, poisson, plane_strain, none or all)"
    )]
    UnknownEffect(String),
    /// `none` listed beside effects (`none,shear`).
    #[error("`none` stands alone: it cannot be listed with other effects")]
    NoneWithOthers,
    /// `poisson` is on without `extension`: the section shrinks with the axial strain, which
    /// is zero without extension.
    #[error("the poisson effect needs extension: add \"extension\" to the effects")]
    PoissonWithoutExtension,
}

/// The most slender beam described (L/t0): a hair 100 times thinner than the thinnest the
/// solver is tested on (1e4); beyond it the axial and shear compliances underflow.
pub const MAX_SLENDERNESS: f64 = 1e6;

/// The largest shear coefficient `kappa` a beam may have: real sections' lie between about
/// 0.5 and 1 (5/6 for a rectangle); shear is switched off with the effects, not with a huge
/// `kappa` (1e300 printed as 300 digits and made the shear compliance subnormal).
pub const MAX_KAPPA: f64 = 10.0;

/// Cowper's shear coefficient of a rectangular section, `10 (1 + nu) / (12 + 11 nu)`.
pub fn cowper_kappa(nu: f64) -> f64 {
    10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)
}

/// A beam in the nondimensional core: everything the solution depends on.
///
/// Width and Young's modulus cancel out once loads are written as `alpha` and `beta`; what
/// remains is the slenderness `L / t0`, Poisson's ratio, the shear coefficient and the effects.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BeamModel {
    /// `L / t0`, from 1 to [`MAX_SLENDERNESS`]; sets the axial and shear compliances.
    pub slenderness: f64,
    /// Poisson's ratio, in `[0, 0.5)`; enters the shear modulus `G = E / (2 (1 + nu))` and
    /// the section's shrink `1 - nu eps`.
    pub nu: f64,
    /// Shear coefficient of the section, `gamma = Q / (kappa G A)`.
    pub kappa: f64,
    /// Which effects the beam includes.
    pub effects: Effects,
    /// `I0 / (A0 L^2)`: axial compliance in units of `L^2 / (E I0)`.
    c_e: f64,
    /// `E I0 / (kappa G A0 L^2)`: shear compliance.
    c_s: f64,
    /// `w0 / t0`, when known ([`BeamModel::with_width_ratio`]): with plane strain, the plate
    /// fraction comes from it (the ends) and from each case's curvature (the anticlastic
    /// curl), see [`crate::beam::plate`]. Unknown: an unboundedly wide section.
    #[serde(skip_serializing_if = "Option::is_none")]
    width_ratio: Option<f64>,
    /// The plate fraction `phi` in use (0 without plane strain).
    plate_fraction: f64,
    /// `E / E_eff = 1 - nu^2 phi`; scales the bending and axial compliances.
    plate: f64,
}

impl BeamModel {
    /// A validated beam; `kappa = None` takes Cowper's value for the rectangle.
    pub fn new(
        slenderness: f64,
        nu: f64,
        kappa: Option<f64>,
        effects: Effects,
    ) -> Result<BeamModel, ModelError> {
        if !(slenderness.is_finite() && (1.0..=MAX_SLENDERNESS).contains(&slenderness)) {
            return Err(ModelError::Slenderness(slenderness));
        }
        if !(nu.is_finite() && (0.0..0.5).contains(&nu)) {
            return Err(ModelError::PoissonRatio(nu));
        }
        let kappa = kappa.unwrap_or_else(|| cowper_kappa(nu));
        if !(kappa.is_finite() && kappa > 0.0 && kappa <= MAX_KAPPA) {
            return Err(ModelError::ShearCoefficient(kappa));
        }
        effects.validate()?;
        Ok(BeamModel::from_valid(slenderness, nu, kappa, effects))
    }

    /// The beam with parameters already checked as [`BeamModel::new`] does.
    fn from_valid(slenderness: f64, nu: f64, kappa: f64, effects: Effects) -> BeamModel {
        let c_e = 1.0 / (12.0 * slenderness * slenderness);
        let c_s = c_e * 2.0 * (1.0 + nu) / kappa;
        BeamModel {
            slenderness,
            nu,
            kappa,
            effects,
            c_e,
            c_s,
            width_ratio: None,
            plate_fraction: 0.0,
            plate: 1.0,
        }
        .with_plate_fraction(1.0)
    }

    /// The same beam with a section `w0 / t0` wide: with plane strain its plate fraction is
    /// then the ends' ([`crate::beam::plate::ends_fraction`]), which a load path raises case
    /// by case by the anticlastic part ([`crate::beam::BeamSolver`] does). A ratio that is not
    /// a positive number leaves the beam as it is.
    pub fn with_width_ratio(self, width_over_thickness: f64) -> BeamModel {
        if !(width_over_thickness.is_finite() && width_over_thickness > 0.0) {
            return self;
        }
        let ends = super::plate::ends_fraction(
            width_over_thickness / self.slenderness,
            width_over_thickness,
        );
        BeamModel {
            width_ratio: Some(width_over_thickness),
            ..self
        }
        .with_plate_fraction(ends)
    }

    /// The same beam with a section `w0 / t0` wide, held flat at both ends and bent in an S
    /// by them (a flexure clamped to the ground and to a guided stage): with plane strain
    /// its plate fraction is the guided ends' ([`crate::beam::plate::guided_ends_fraction`]).
    /// A ratio that is not a positive number leaves the beam as it is.
    pub fn with_guided_width_ratio(self, width_over_thickness: f64) -> BeamModel {
        if !(width_over_thickness.is_finite() && width_over_thickness > 0.0) {
            return self;
        }
        let ends = super::plate::guided_ends_fraction(
            width_over_thickness / self.slenderness,
            width_over_thickness,
        );
        BeamModel {
            width_ratio: Some(width_over_thickness),
            ..self
        }
        .with_plate_fraction(ends)
    }

    /// The same beam with the plate fraction `phi` (clamped to `[0, 1]`): the modulus is
    /// `E / (1 - nu^2 phi)` with plane strain on, `E` without it (`phi` is then 0).
    pub fn with_plate_fraction(self, phi: f64) -> BeamModel {
        let phi = if self.effects.plane_strain && !phi.is_nan() {
            phi.clamp(0.0, 1.0)
        } else {
            0.0
        };
        BeamModel {
            plate_fraction: phi,
            plate: 1.0 - self.nu * self.nu * phi,
            ..self
        }
    }

    /// The same beam without plane strain (plane stress, the narrow beam).
    pub(crate) fn narrow(&self) -> BeamModel {
        BeamModel {
            effects: self.effects.with_plane_strain(false),
            ..*self
        }
        .with_plate_fraction(0.0)
    }

    /// Drops the width, keeping the plate fraction in use.
    pub(crate) fn forget_width(&mut self) {
        self.width_ratio = None;
    }

    /// `w0 / t0`, when the model was given it.
    pub fn width_ratio(&self) -> Option<f64> {
        self.width_ratio
    }

    /// The plate fraction in use: 0 without plane strain; with it, 1 for an unboundedly wide
    /// section, else the ends' or (once a path has set it) the case's.
    pub fn plate_fraction(&self) -> f64 {
        self.plate_fraction
    }

    /// Whether this is the plain-bending beam: no shear, no extension, no Poisson (plane
    /// strain only scales its bending compliance).
    pub(crate) fn is_plain(&self) -> bool {
        !self.effects.shear && !self.effects.extension && !self.effects.poisson
    }

    /// The inextensible, shear-rigid elastica (slenderness and nu are then irrelevant).
    pub fn elastica() -> BeamModel {
        // Slenderness 100, nu = 0.3, Cowper's kappa and no effects pass every check of `new`.
        BeamModel::from_valid(100.0, 0.3, cowper_kappa(0.3), Effects::NONE)
    }

    /// Axial compliance `I0 / (A0 L^2) = 1 / (12 (L/t0)^2)` at the nominal modulus (the
    /// scale of the PRB matrix's `k_ex`; plane strain divides the beam's by
    /// [`BeamModel::plate_factor`]).
    pub fn axial_compliance(&self) -> f64 {
        self.c_e
    }

    /// `E_eff / E`: `1 / (1 - nu^2 phi)` with plane strain (`phi` the plate fraction), else 1.
    pub fn plate_factor(&self) -> f64 {
        1.0 / self.plate
    }

    /// `E / E_eff`, the factor on the curvature and the axial strain.
    #[inline(always)]
    pub(crate) fn plate_compliance(&self) -> f64 {
        self.plate
    }

    /// Shear compliance `E I0 / (kappa G A0 L^2)`.
    pub fn shear_compliance(&self) -> f64 {
        self.c_s
    }

    /// Strains of the section under axial force `n` and shear force `q` (units of
    /// `E I0 / L^2`): `(eps, gamma, I / I0)`, or `None` where the material law has no state.
    pub fn section_strains(&self, n: f64, q: f64) -> Option<(f64, f64, f64)> {
        let (eps, _, p) = self.axial_strain(n).ok()?;
        let gamma = if self.effects.shear {
            self.c_s * q / (p * p)
        } else {
            0.0
        };
        let stiffness = if self.effects.poisson { p.powi(4) } else { 1.0 } / self.plate;
        Some((eps, gamma, stiffness))
    }

    /// The section state for an axial force `n`: strain, `d eps / d N`, shrink factor `p`.
    #[inline(always)]
    pub(crate) fn axial_strain(&self, n: f64) -> Result<(f64, f64, f64), MaterialLimit> {
        if !self.effects.extension {
            return Ok((0.0, 0.0, 1.0));
        }
        let c_e = self.c_e * self.plate;
        let rhs = c_e * n;
        let (eps, de_dn, p) = if self.effects.poisson && self.nu > 0.0 {
            let (eps, deps_dr) =
                solve_poisson(self.nu, rhs).ok_or(MaterialLimit::Necked { axial_force: n })?;
            (eps, c_e * deps_dr, 1.0 - self.nu * eps)
        } else {
            (rhs, c_e, 1.0)
        };
        if 1.0 + eps <= 0.0 {
            return Err(MaterialLimit::Crushed { axial_force: n });
        }
        Ok((eps, de_dn, p))
    }
}

/// The constitutive law has no state for this axial force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum MaterialLimit {
    /// Tension beyond the peak of `eps (1 - nu eps)^2`.
    Necked { axial_force: f64 },
    /// Compression that shortens the centre line to nothing.
    Crushed { axial_force: f64 },
}

impl fmt::Display for MaterialLimit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MaterialLimit::Necked { axial_force } => write!(
                f,
                "axial tension {axial_force:.4} E I0/L^2 exceeds what the Poisson material law can \
                 carry (the section necks)"
            ),
            MaterialLimit::Crushed { axial_force } => write!(
                f,
                "axial compression {axial_force:.4} E I0/L^2 shortens the centre line to nothing"
            ),
        }
    }
}

/// Solves `eps (1 - nu eps)^2 = r` for the physical root `eps < 1 / (3 nu)`.
/// Returns `eps` and `d eps / d r` there.
#[inline(always)]
fn solve_poisson(nu: f64, r: f64) -> Option<(f64, f64)> {
    // Beyond the peak `r = 4 / (27 nu)` (at `eps = 1 / (3 nu)`), compared without a division.
    if 27.0 * nu * r >= 4.0 || !r.is_finite() {
        return None;
    }
    // For r < 0, (1 - nu eps)^2 > 1 so r <= eps < 0; for r > 0, r <= eps < eps_peak.
    // Small strains (every slender beam): the Lagrange-inversion series of the root,
    // eps = r (1 + 2 x + 7 x^2 + 30 x^3 + 143 x^4 + 728 x^5 + ...) with x = nu r. Six terms
    // leave a relative error below (27 |x| / 4)^6 < 1e-7 for |x| < 0.01, and one Newton step
    // squares that to round-off. d eps / d r is the series differentiated: good to 1e-7
    // relative, plenty for the sensitivities it feeds, with no second division.
    // Below |x| = 1e-3 (a slender beam's every section) the series alone is good to
    // (27e-3 / 4)^6 < 1e-13 relative, and the Newton step's division is spared.
    let x = nu * r;
    if x.abs() < 0.01 {
        let eps = r * (1.0 + x * (2.0 + x * (7.0 + x * (30.0 + x * (143.0 + x * 728.0)))));
        let eps = if x.abs() < 1e-3 {
            eps
        } else {
            let p = 1.0 - nu * eps;
            eps - (eps * p * p - r) / (p * (1.0 - 3.0 * nu * eps))
        };
        let deps_dr = 1.0 + x * (4.0 + x * (21.0 + x * (120.0 + x * (715.0 + x * 4368.0))));
        return Some((eps, deps_dr));
    }
    let eps_peak = 1.0 / (3.0 * nu);
    let (mut lo, mut hi) = if r < 0.0 { (r, 0.0) } else { (r, eps_peak) };
    // Two terms of the series r + 2 nu r^2 + ... start Newton close to the root.
    let mut eps = (r + 2.0 * nu * r * r).clamp(lo, hi);
    for _ in 0..80 {
        let p = 1.0 - nu * eps;
        let g = eps * p * p - r;
        if g == 0.0 {
            break;
        }
        if g > 0.0 {
            hi = eps;
        } else {
            lo = eps;
        }
        let slope = p * (1.0 - 3.0 * nu * eps);
        let mut next = eps - g / slope;
        // Newton, unless it leaves the bracket (then bisect). At convergence the Newton
        // step lands on the bracket end it came from, which must not count as leaving.
        if !(next >= lo && next <= hi) {
            next = 0.5 * (lo + hi);
        }
        let done = (next - eps).abs() <= 2.0 * f64::EPSILON * eps.abs();
        eps = next;
        if done {
            break;
        }
    }
    let p = 1.0 - nu * eps;
    Some((eps, 1.0 / (p * (1.0 - 3.0 * nu * eps))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poisson_root_satisfies_the_equation() {
        for &nu in &[0.1, 0.3, 0.45, 0.499] {
            for &r in &[
                -5.0,
                -0.3,
                -1e-9,
                0.0,
                1e-9,
                0.01,
                0.2,
                4.0 / (27.0 * nu) * 0.999,
            ] {
                let (eps, _) = solve_poisson(nu, r).unwrap();
                let p = 1.0 - nu * eps;
                assert!(
                    (eps * p * p - r).abs() <= 1e-14 * (1.0 + r.abs()),
                    "nu {nu} r {r}"
                );
                assert!(eps < 1.0 / (3.0 * nu));
            }
        }
    }

    #[test]
    fn necking_is_reported() {
        assert!(solve_poisson(0.49, 4.0 / (27.0 * 0.49) * 1.001).is_none());
    }

    #[test]
    fn effects_parse_and_print() {
        assert_eq!(Effects::parse_list("none").unwrap(), Effects::NONE);
        assert_eq!(
            Effects::parse_list("none,shear"),
            Err(ModelError::NoneWithOthers)
        );
        assert_eq!(
            Effects::parse_list("shear, extension").unwrap().to_string(),
            "shear,extension"
        );
        assert_eq!(
            Effects::parse_list("poisson"),
            Err(ModelError::PoissonWithoutExtension)
        );
        let wide = Effects::parse_list("all, plane_strain").unwrap();
        assert_eq!(wide, Effects::ALL.with_plane_strain(true));
        assert_eq!(wide.to_string(), "shear,extension,poisson,plane_strain");
        assert_eq!(
            Effects::parse_list("plane_strain,all").unwrap(),
            Effects::ALL.with_plane_strain(true)
        );
        const { assert!(!Effects::ALL.plane_strain) };
        assert!(matches!(
            Effects::parse_list("shear,twist"),
            Err(ModelError::UnknownEffect(w)) if w == "twist"
        ));
    }

    #[test]
    fn bad_beams_are_rejected() {
        assert!(BeamModel::new(-1.0, 0.3, None, Effects::ALL).is_err());
        assert!(BeamModel::new(10.0, 0.7, None, Effects::ALL).is_err());
        assert!(BeamModel::new(10.0, f64::NAN, None, Effects::ALL).is_err());
        assert!(BeamModel::new(10.0, 0.3, Some(0.0), Effects::ALL).is_err());
        assert!((cowper_kappa(0.3) - 13.0 / 15.3).abs() < 1e-15);
    }
}
