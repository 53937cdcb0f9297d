//! Small free vibration of the §2 beam about an equilibrium (DESIGN §10): the truth's modes.
//!
//! # What is modelled
//! The clamped beam of DESIGN §2 under its dead tip load, in equilibrium (unloaded, or a
//! solved load case), vibrating a little about it. Nondimensional as the statics: `L = 1`,
//! `E I0 = 1`, and the mass per unit length `rho A0 = 1`, so the frequencies come out as
//! `Omega = omega sqrt(rho A0 L^4 / (E I0))` (the uniform cantilever's are 3.516015,
//! 22.034492, 61.697214; [`FrequencyScale`] turns them into rad/s and Hz).
//! - Distributed mass `rho A0` per unit length of the unloaded beam (each piece keeps its
//!   mass as it stretches or shrinks). With shear on, Timoshenko's beam: the shear strain
//!   and the section's rotary inertia `rho I0` together; with shear off, Euler-Bernoulli
//!   with no rotary inertia. With extension on, the axial strain is a field and the beam
//!   has axial inertia; with it off the centre line is inextensible.
//! - A tip body ([`TipBody`]): mass and rotary inertia about the tip point, its centre of
//!   mass there.
//! - The dead load's geometric stiffness: the second variation of the load's potential, so
//!   a compression lowers the first frequency, which reaches zero where the statics find a
//!   critical point (tested against the continuation's buckling load).
//!
//! # Method: a spectral Ritz method on the strain fields
//! The beam's configuration is described, exactly and with no constraint, by its strain
//! fields: the rotation `psi(s)` (with `psi(0) = 0`), the axial strain `eps(s)` and the
//! shear strain `gamma(s)`; the centre line is their integral
//! `r(s) = int_0^s ((1 + eps) t(psi) + gamma n(psi))`. The potential is
//! `int W(eps, gamma, psi') ds - F . r(L) - Mz psi(L)` and the kinetic energy
//! `1/2 int (rho A |r_t|^2 + rho I psi_t^2) ds` plus the tip body's. Their second
//! variations about the equilibrium give the symmetric `K` (material tangent plus the
//! load's geometric stiffness `theta^2 ((1 + eps) N + gamma Q) - 2 e theta Q + 2 g theta N`,
//! with `theta, e, g` the perturbations of `psi, eps, gamma`) and `M`. The perturbations are
//! expanded in Legendre polynomials (`theta' = sum c_k P_k(2s - 1)`, so `theta(0) = 0`
//! holds exactly; `e`, `g` likewise), and the integrals (including the inner one for `r`)
//! are done by Gauss-Legendre quadrature with a spectral integration matrix.
//!
//! Why this and not a determinant search: it is a Rayleigh-Ritz method on a conforming
//! subspace, so by the min-max theorem the `k`-th computed `omega^2` is an upper bound on
//! the `k`-th true one and converges to it from above: no mode is skipped, which is the
//! counting a determinant search needs Wittrick-Williams for. The polynomial basis
//! converges exponentially for the smooth equilibria met here, so a few dozen unknowns per
//! field give 1e-9 on the first three frequencies; the whole solve is dense linear algebra
//! of that size (no root bracketing, no missed close roots). Turning an effect off removes
//! its field, so the inextensible, shear-rigid limits are exact, not penalties; and because
//! the generalized eigenproblem is reduced through the Cholesky factor of `K` (see `eigen`),
//! the huge axial and shear stiffnesses of a slender beam cost no accuracy in the low modes.
//!
//! # Accuracy
//! The degree grows with the load and the modes wanted (`degree_for`: 12 for three modes of
//! the unloaded beam); the claim is 1e-6 relative on the first three frequencies, checked
//! in `tests/modes.rs` against the closed-form frequency equations (uniform cantilever, tip
//! mass, axial tension and compression, Timoshenko's stubby cantilever) solved there by root
//! finding, and printed by `cargo bench --bench modes` against the degree raised by 16.
//! Measured: 1e-9 or better for loads up to `alpha = 300` and `beta = 6`. The equilibrium
//! is integrated again at the quadrature nodes (see `equilibrium`) to about 1e-9, which is
//! the floor: near a critical point the first frequency goes like the square root of the
//! distance to it and the floor grows accordingly (1e-7 of `Omega_1` at 97 % of Euler's
//! load).
//!
//! # Eigenproblem
//! Dense (through `K`'s Cholesky factor) up to 64 unknowns; above, subspace iteration with
//! a block of `count + 4` generic vectors and Rayleigh-Ritz on it (see `eigen`), which a
//! mechanism's several flexures reach. A `K` that is not positive definite (an equilibrium
//! at or past a critical point) is solved densely through `M` and its negative `omega^2`
//! reported. Asked for no shapes ([`ModeSettings::frequencies`]), the dense route computes
//! the eigenvalues alone (no eigenvectors, no back-substitution): about a tenth off the
//! loaded beam's time per equilibrium, whose larger part is resampling the equilibrium.
//!
//! The Poisson law (the section shrinking with the axial strain) is not hyperelastic; its
//! tangent is symmetrised (see `equilibrium`), a change of order `nu eps kappa` in the
//! stiffness, far below the claim for slender beams.
//!
//! # API
//! - [`beam_modes`]`(model, tip, load, root_moment, settings) -> Result<Modes, ModesError>`:
//!   about the equilibrium under `load` whose root moment is about `root_moment` (the
//!   statics' [`BeamSolution::root_moment`]; it is polished here);
//! - [`unloaded_modes`]`(model, tip, settings)`, [`solution_modes`]`(model, tip, solution,
//!   settings)`, [`path_modes`]`(solver, tip, end, steps, settings)`: the unloaded beam, a
//!   solved case, every case of a load path;
//! - [`Modes`]: `omega` (nondimensional, ascending; negative = unstable, its size the
//!   growth rate), per-mode [`ModeShape`]s for drawing;
//! - [`TipBody`] (nondimensional, or [`TipBody::from_si`]) and [`FrequencyScale`] (SI).
//! - For mechanisms (`crate::mech::modes`): one beam's matrices (stiffness, mass, tip
//!   map) through [`FlexureModel`], and [`generalized_lowest`] for the assembled problem.

mod basis;
mod discrete;
mod eigen;
mod equilibrium;
mod shape;

use serde::Serialize;

use super::{BeamModel, BeamSolution, BeamSolver, Load, SolveError};

pub use shape::{normalise, ModePoint, ModeShape};

/// The body bolted to the tip, in units of the beam: mass over `rho A0 L`, rotary inertia
/// about the tip point over `rho A0 L^3`. Its centre of mass is at the tip point.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct TipBody {
    /// Mass / (rho A0 L).
    pub mass: f64,
    /// Rotary inertia about the tip point / (rho A0 L^3).
    pub inertia: f64,
}

impl TipBody {
    /// No tip body.
    pub const NONE: TipBody = TipBody {
        mass: 0.0,
        inertia: 0.0,
    };

    /// A tip body checked: finite and not negative.
    pub fn new(mass: f64, inertia: f64) -> Result<TipBody, ModesError> {
        if !(mass.is_finite() && mass >= 0.0) {
            return Err(ModesError::BadInput(format!(
                "tip mass must be a finite number >= 0, got {}",
                crate::text::bounded(mass)
            )));
        }
        if !(inertia.is_finite() && inertia >= 0.0) {
            return Err(ModesError::BadInput(format!(
                "tip inertia must be a finite number >= 0, got {}",
                crate::text::bounded(inertia)
            )));
        }
        Ok(TipBody { mass, inertia })
    }

    /// From SI: `mass` (kg) and `inertia` (kg m^2 about the tip point) on a rectangular beam
    /// of `density` (kg/m^3), `width`, `thickness`, `length` (m).
    pub fn from_si(
        mass: f64,
        inertia: f64,
        density: f64,
        width: f64,
        thickness: f64,
        length: f64,
    ) -> Result<TipBody, ModesError> {
        let line = density * width * thickness;
        if !(line.is_finite() && line > 0.0 && length.is_finite() && length > 0.0) {
            return Err(ModesError::BadInput(format!(
                "density, width, thickness and length must be finite numbers > 0, got \
                 {}, {}, {}, {}",
                crate::text::bounded(density),
                crate::text::bounded(width),
                crate::text::bounded(thickness),
                crate::text::bounded(length)
            )));
        }
        TipBody::new(mass / (line * length), inertia / (line * length.powi(3)))
    }
}

/// Converts the nondimensional `Omega` of a beam into rad/s and Hz:
/// `omega = Omega sqrt(E I0 / (rho A0 L^4))`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FrequencyScale {
    /// `sqrt(E I0 / (rho A0 L^4))`, rad/s per unit of `Omega`.
    pub rad_per_s: f64,
}

impl FrequencyScale {
    /// The scale of a rectangular section: `sqrt(E t^2 / (12 rho L^4))` (the width cancels).
    /// Young's modulus `E` (Pa), `density` (kg/m^3), `length` and `thickness` (m).
    pub fn rectangle(
        youngs_modulus: f64,
        density: f64,
        length: f64,
        thickness: f64,
    ) -> Result<FrequencyScale, ModesError> {
        let all = [youngs_modulus, density, length, thickness];
        if all.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(ModesError::BadInput(format!(
                "Young's modulus, density, length and thickness must be finite numbers > 0, \
                 got {}, {}, {}, {}",
                crate::text::bounded(youngs_modulus),
                crate::text::bounded(density),
                crate::text::bounded(length),
                crate::text::bounded(thickness)
            )));
        }
        let rad_per_s =
            (youngs_modulus * thickness * thickness / (12.0 * density)).sqrt() / (length * length);
        Ok(FrequencyScale { rad_per_s })
    }

    /// `omega` in rad/s for a nondimensional `Omega`.
    pub fn rad_per_s(&self, omega: f64) -> f64 {
        omega * self.rad_per_s
    }

    /// The frequency in Hz for a nondimensional `Omega`.
    pub fn hz(&self, omega: f64) -> f64 {
        omega * self.rad_per_s / (2.0 * std::f64::consts::PI)
    }
}

/// How many modes, how finely, and how many stations per drawn shape.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ModeSettings {
    /// Modes wanted (the lowest).
    pub count: usize,
    /// Legendre coefficients per field; `None`: chosen from the load for 1e-6 on the first
    /// three frequencies (`degree_for`).
    pub degree: Option<usize>,
    /// Stations per mode shape (root and tip included); 0: no shapes.
    pub shape_points: usize,
}

impl Default for ModeSettings {
    fn default() -> Self {
        ModeSettings {
            count: 3,
            degree: None,
            shape_points: 41,
        }
    }
}

impl ModeSettings {
    /// `count` modes, the degree chosen for the load, no shapes (the fastest).
    pub fn frequencies(count: usize) -> ModeSettings {
        ModeSettings {
            count,
            degree: None,
            shape_points: 0,
        }
    }
}

/// The lowest modes about one equilibrium.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Modes {
    /// Nondimensional frequencies `Omega`, ascending. A negative value is an unstable mode
    /// (`omega^2 < 0`, the equilibrium is past a critical point): its size is the growth
    /// rate in the same units.
    pub omega: Vec<f64>,
    /// The shapes of the modes, in the same order (empty when no stations were asked for).
    pub shapes: Vec<ModeShape>,
    /// The Legendre coefficients per field used.
    pub degree: usize,
    /// The equilibrium's root moment (polished), units of `E I0 / L`.
    pub root_moment: f64,
}

impl Modes {
    /// The frequencies in Hz on a beam of this scale.
    pub fn hz(&self, scale: &FrequencyScale) -> Vec<f64> {
        self.omega.iter().map(|&w| scale.hz(w)).collect()
    }

    /// The frequencies in rad/s on a beam of this scale.
    pub fn rad_per_s(&self, scale: &FrequencyScale) -> Vec<f64> {
        self.omega.iter().map(|&w| scale.rad_per_s(w)).collect()
    }
}

/// Why the modes could not be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModesError {
    /// A number given is NaN or infinite (what).
    #[error("{0} is not finite")]
    NotFinite(&'static str),
    /// A mass, inertia, density or size out of range, or no mode asked for (the text says
    /// which).
    #[error("{0}")]
    BadInput(String),
    /// The statics failed (their own message).
    #[error(transparent)]
    Statics(#[from] SolveError),
    /// The material law has no state for the axial force met.
    #[error("the material law fails under the axial force {axial_force:.4} E I0/L^2")]
    MaterialLimit {
        /// The axial force, units of `E I0 / L^2`.
        axial_force: f64,
    },
    /// The equilibrium could not be sampled again (why).
    #[error("the equilibrium could not be resampled for the modes: {0}")]
    Equilibrium(String),
    /// A matrix that must be positive definite is not (which).
    #[error("singular eigenproblem: {0}")]
    Singular(&'static str),
}

/// The most Legendre coefficients per field.
pub const MAX_DEGREE: usize = 96;

/// The most modes asked for at once: the unloaded beam's degree rule below reaches
/// [`MAX_DEGREE`] there (a load needs a higher degree still, which the clamp then denies:
/// past this the highest frequencies returned are the discretisation's, not the beam's).
pub const MAX_MODES: usize = (MAX_DEGREE - 6) / 2;

/// The degree that gives 1e-8 on the first `count` frequencies at this load:
/// `6 + 2 count + lambda / 2` (12 for three modes of the unloaded beam), `lambda` the
/// fastest rate at which the shape turns (`sqrt|alpha|`, the moments), to resolve the
/// boundary layers of a large force. Measured (`cargo bench --bench modes` and raising the
/// degree): the unloaded beam's first three are good to 2e-9 at degree 10 and 1e-12 at 12;
/// `alpha_y = 100` (lambda 10) to 4e-8 at 14 and 2e-9 at 16 (the rule gives 17);
/// `alpha_x = 300` to 4e-10 at 14 (the rule gives 21); `beta = 6` to 3e-11 at 12.
pub(crate) fn degree_for(load: &Load, root_moment: f64, count: usize) -> usize {
    let rate = load
        .alpha_x
        .hypot(load.alpha_y)
        .sqrt()
        .max(root_moment.abs())
        .max(load.beta.abs());
    (6.0 + 2.0 * count as f64 + 0.5 * rate)
        .ceil()
        .clamp(10.0, MAX_DEGREE as f64) as usize
}

/// A beam about its equilibrium, discretised: the building block of the beam's modes and of
/// a mechanism's (`crate::mech::modes`), in the beam's own units and frame.
#[derive(Debug, Clone)]
pub struct FlexureModel {
    matrices: discrete::BeamMatrices,
    quad: std::sync::Arc<basis::Quadrature>,
    root_moment: f64,
}

impl FlexureModel {
    /// The beam `model` about its equilibrium under `load` (root moment about
    /// `root_moment`), with `degree` coefficients per field (`None`: chosen from the load
    /// for the first three modes).
    pub fn new(
        model: &BeamModel,
        load: Load,
        root_moment: f64,
        degree: Option<usize>,
    ) -> Result<FlexureModel, ModesError> {
        FlexureModel::for_modes(model, load, root_moment, degree, 3)
    }

    /// As [`FlexureModel::new`], the degree (when `None`) chosen for the first `count`
    /// modes.
    pub fn for_modes(
        model: &BeamModel,
        load: Load,
        root_moment: f64,
        degree: Option<usize>,
        count: usize,
    ) -> Result<FlexureModel, ModesError> {
        let degree = match degree {
            Some(d) if (2..=MAX_DEGREE).contains(&d) => d,
            Some(d) => {
                return Err(ModesError::BadInput(format!(
                    "the modes' degree must be from 2 to {MAX_DEGREE}, got {d}"
                )))
            }
            None => degree_for(&load, root_moment, count),
        };
        let quad = basis::Quadrature::shared(degree + 16);
        let eq = equilibrium::sample(model, &load, root_moment, &quad.nodes)?;
        let layout = discrete::Layout {
            degree,
            extension: model.effects.extension,
            shear: model.effects.shear,
        };
        // rho I0 / (rho A0 L^2) = I0 / (A0 L^2), the nominal axial compliance.
        let rotary = model.axial_compliance();
        let matrices = discrete::assemble(layout, &quad, &eq, rotary);
        Ok(FlexureModel {
            matrices,
            quad,
            root_moment: eq.root_moment,
        })
    }

    /// The number of generalized coordinates (the strain fields' coefficients).
    pub fn dofs(&self) -> usize {
        self.matrices.layout.dofs()
    }

    /// The stiffness matrix: the potential's second variation, the tip load's geometric
    /// stiffness included (symmetric; positive definite at a stable equilibrium).
    pub fn stiffness(&self) -> &nalgebra::DMatrix<f64> {
        &self.matrices.stiffness
    }

    /// The distributed mass matrix (symmetric positive definite), no tip body.
    pub fn mass(&self) -> &nalgebra::DMatrix<f64> {
        &self.matrices.mass
    }

    /// `3 x dofs`: the tip's motion `(da, db, dphi)` per coordinate (the beam's frame).
    pub fn tip_map(&self) -> &nalgebra::DMatrix<f64> {
        &self.matrices.tip
    }

    /// The root moment of the equilibrium (polished).
    pub fn root_moment(&self) -> f64 {
        self.root_moment
    }

    /// The mass matrix with a tip body added.
    pub fn mass_with_tip(&self, tip: TipBody) -> nalgebra::DMatrix<f64> {
        let t = &self.matrices.tip;
        let mut m = self.matrices.mass.clone();
        let (a, b, p) = (t.row(0), t.row(1), t.row(2));
        m += tip.mass * (a.transpose() * a + b.transpose() * b) + tip.inertia * p.transpose() * p;
        m
    }

    /// The motion `coords` at `points` evenly spaced stations (root and tip included), not
    /// normalised: the equilibrium's centre line and the motion, in the beam's own units
    /// and frame.
    pub fn stations(&self, coords: &[f64], points: usize) -> Vec<ModePoint> {
        shape::stations(&self.matrices, &self.quad, coords, points)
    }

    /// The shape of the motion `coords` at `points` stations: the equilibrium's centre line
    /// and the motion, normalised (see [`ModeShape`]).
    pub fn shape(&self, coords: &[f64], omega: f64, points: usize) -> ModeShape {
        shape::draw(&self.matrices, &self.quad, coords, omega, points)
    }
}

/// The lowest modes of the beam `model` with the tip body `tip` about its equilibrium under
/// `load`, whose root moment is about `root_moment` (from the statics).
pub fn beam_modes(
    model: &BeamModel,
    tip: TipBody,
    load: Load,
    root_moment: f64,
    settings: &ModeSettings,
) -> Result<Modes, ModesError> {
    if settings.count == 0 {
        return Err(ModesError::BadInput(
            "the number of modes must be at least 1".to_string(),
        ));
    }
    let tip = TipBody::new(tip.mass, tip.inertia)?;
    let flexure =
        FlexureModel::for_modes(model, load, root_moment, settings.degree, settings.count)?;
    let m = flexure.mass_with_tip(tip);
    // No shapes wanted: the frequencies alone, which skips the eigenvectors.
    let lowest = if settings.shape_points >= 2 {
        eigen::lowest(flexure.stiffness(), &m, settings.count)?
    } else {
        eigen::lowest_values(flexure.stiffness(), &m, settings.count)?
    };
    Ok(collect(&flexure, &lowest, settings))
}

/// The lowest `count` solutions of `K q = omega^2 M q` (`K`, `M` symmetric, `M` positive
/// definite): `omega^2` ascending (negative where `K` is not positive definite) and the
/// vectors, unit modal mass. Through `K`'s Cholesky factor when it has one (the low modes
/// then keep full relative accuracy however stiff the other fields are), else `M`'s.
pub fn generalized_lowest(
    k: &nalgebra::DMatrix<f64>,
    m: &nalgebra::DMatrix<f64>,
    count: usize,
) -> Result<(Vec<f64>, Vec<nalgebra::DVector<f64>>), ModesError> {
    if k.nrows() != k.ncols() || m.shape() != k.shape() {
        return Err(ModesError::BadInput(
            "the stiffness and mass matrices must be square and of one size".to_string(),
        ));
    }
    let lowest = eigen::lowest(k, m, count)?;
    Ok((lowest.omega_sq, lowest.vectors))
}

/// The modes found, with their shapes.
fn collect(flexure: &FlexureModel, lowest: &eigen::Lowest, settings: &ModeSettings) -> Modes {
    let omega: Vec<f64> = lowest
        .omega_sq
        .iter()
        .map(|&w2| w2.signum() * w2.abs().sqrt())
        .collect();
    let shapes = if settings.shape_points >= 2 {
        lowest
            .vectors
            .iter()
            .zip(&omega)
            .map(|(v, &w)| flexure.shape(v.as_slice(), w, settings.shape_points))
            .collect()
    } else {
        Vec::new()
    };
    Modes {
        omega,
        shapes,
        degree: flexure.matrices.layout.degree,
        root_moment: flexure.root_moment,
    }
}

/// The modes of the unloaded beam.
pub fn unloaded_modes(
    model: &BeamModel,
    tip: TipBody,
    settings: &ModeSettings,
) -> Result<Modes, ModesError> {
    beam_modes(model, tip, Load::new(0.0, 0.0, 0.0), 0.0, settings)
}

/// The modes about a solved equilibrium of the statics.
pub fn solution_modes(
    model: &BeamModel,
    tip: TipBody,
    solution: &BeamSolution,
    settings: &ModeSettings,
) -> Result<Modes, ModesError> {
    beam_modes(model, tip, solution.load, solution.root_moment, settings)
}

/// The modes about every case of the proportional load path from zero to `end` in `steps`
/// steps, as [`BeamSolver::solve_path`] solves it (its error if the statics fail: a load past
/// buckling gets the statics' own message).
pub fn path_modes(
    solver: &BeamSolver,
    tip: TipBody,
    end: Load,
    steps: u32,
    settings: &ModeSettings,
) -> Result<Vec<Modes>, ModesError> {
    let cases = solver.solve_path(end, steps)?;
    cases
        .iter()
        .map(|case| solution_modes(&solver.model, tip, case, settings))
        .collect()
}
