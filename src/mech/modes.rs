//! Small free vibration of the beam mechanism (DESIGN §8, §10) about its equilibrium: the
//! flexures (each the §2 beam with its distributed mass, [`crate::beam::modes`]) and the
//! rigid stage with its mass and rotary inertia about `P` (its centre of mass at `P`).
//!
//! # Method
//! Each flexure is discretised about its equilibrium in a case (its tip wrench, which holds
//! its shape) by the beam's spectral Ritz method ([`FlexureModel`]), in its own units and
//! frame, and brought to flexure 1's: stiffness times `kappa_i / lambda_i`, mass times
//! `r_i lambda_i^3` (`lambda_i = L_i / L1`, `kappa_i = E I_i / E I1`, `r_i` the mass per
//! length over flexure 1's). The stage adds its three coordinates `(dx, dy, dphi)` of `P`
//! with the mass `diag(m, m, J)`. The joints are linear constraints on the motion: a
//! clamped tip moves and turns with the stage point it is bolted to, a pinned one moves with
//! it, a coupler keeps its length (the tip's and the stage end's motions agree along it); a
//! prescribed stage coordinate is held (the drive holds it while the mechanism rings).
//!
//! The stiffness is the Hessian of the Lagrangian on those constraints: each flexure's own
//! (material and the geometric stiffness of its tip wrench), the stage's part of the joints'
//! reactions (a tip force `F` on a joint at arm `rho` from `P` adds `-F . rho` to the stage's
//! rotation) and each coupler's string stiffness (its tension over its length, across it).
//! The stage's own dead loads add nothing (they are linear in its pose). The constraints
//! are eliminated exactly (Gaussian elimination with complete pivoting gives a basis of
//! their null space), and the reduced symmetric-definite problem is solved as the beam's
//! ([`generalized_lowest`]).
//!
//! Frequencies are flexure 1's `Omega = omega sqrt(rho A1 L1^4 / (E I1))`. Known answers
//! (`tests/mech_modes.rs`): the parallel stage with a heavy stage rings at
//! `sqrt(24 E I / (L^3 M))`, the massless flexures' limit; with the stage held, each
//! flexure is a clamped-clamped beam; pushed along its flexures, its first frequency
//! vanishes at their sway buckling load `2 pi^2 E I / L^2`, where the statics stop.
//!
//! # API
//! - [`MechMass`]: per-flexure mass per length, stage mass and inertia (nondimensional;
//!   [`MechMass::from_si`] from one density and the stage's kg and kg m^2);
//! - [`mech_modes`]`(mechanism, mass, held, case, settings) -> Result<MechModes,
//!   ModesError>`: about the unloaded mechanism (`case = None`) or a solved case;
//!   `held` from [`held_by`]`(drive)`;
//! - [`drive_modes`]`(mechanism, mass, resolution, settings)`: every case of every drive,
//!   solved exactly first.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::beam::modes::{generalized_lowest, FlexureModel, ModePoint, ModeSettings, ModesError};
use crate::beam::{Load, Resolution, TipPose};
use crate::scene::{Drive, Mechanism};

use super::geometry::{rotate, Frame, Geometry, Joint};
use super::{exact, MechCase, MechError};

/// The masses of a mechanism in flexure 1's units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MechMass {
    /// Per flexure, in order: its mass per unit length over flexure 1's (`rho_i A_i /
    /// (rho_1 A_1)`; 1 for flexure 1).
    pub line_density: Vec<f64>,
    /// The stage's mass over flexure 1's `rho A0 L`.
    pub stage_mass: f64,
    /// The stage's rotary inertia about `P` over flexure 1's `rho A0 L^3`.
    pub stage_inertia: f64,
}

impl MechMass {
    /// The masses from SI: one `density` (kg/m^3) for every flexure, the stage's `mass` (kg)
    /// and rotary `inertia` about `P` (kg m^2).
    pub fn from_si(
        mechanism: &Mechanism,
        density: f64,
        mass: f64,
        inertia: f64,
    ) -> Result<MechMass, ModesError> {
        let first = mechanism
            .flexures
            .first()
            .ok_or_else(|| ModesError::BadInput("a mechanism needs a flexure".to_string()))?;
        if !(density.is_finite() && density > 0.0) {
            return Err(ModesError::BadInput(format!(
                "density must be a finite number > 0, got {}",
                crate::text::bounded(density)
            )));
        }
        let line = density * first.beam.area();
        let l1 = first.beam.length;
        let line_density = mechanism
            .flexures
            .iter()
            .map(|f| density * f.beam.area() / line)
            .collect();
        MechMass {
            line_density,
            stage_mass: mass / (line * l1),
            stage_inertia: inertia / (line * l1.powi(3)),
        }
        .checked(mechanism.flexures.len())
    }

    /// Every flexure of flexure 1's section and material, and the stage's mass and inertia
    /// (nondimensional).
    pub fn uniform(flexures: usize, stage_mass: f64, stage_inertia: f64) -> MechMass {
        MechMass {
            line_density: vec![1.0; flexures],
            stage_mass,
            stage_inertia,
        }
    }

    /// These masses if they fit `flexures` flexures and none is negative or NaN.
    fn checked(self, flexures: usize) -> Result<MechMass, ModesError> {
        if self.line_density.len() != flexures {
            return Err(ModesError::BadInput(format!(
                "{} line densities for {flexures} flexures",
                self.line_density.len()
            )));
        }
        if self
            .line_density
            .iter()
            .any(|r| !(r.is_finite() && *r > 0.0))
        {
            return Err(ModesError::BadInput(
                "every flexure's mass per length must be a finite number > 0".to_string(),
            ));
        }
        for (what, v) in [
            ("stage mass", self.stage_mass),
            ("stage inertia", self.stage_inertia),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(ModesError::BadInput(format!(
                    "{what} must be a finite number >= 0, got {}",
                    crate::text::bounded(v)
                )));
            }
        }
        Ok(self)
    }
}

/// Which stage coordinates a drive holds (its prescribed ones), `[dx, dy, dphi]`.
pub fn held_by(drive: &Drive) -> [bool; 3] {
    std::array::from_fn(|c| drive.coordinates[c].is_prescribed())
}

/// One mode of a mechanism, for drawing: everything in the global frame, flexure 1's units,
/// the largest motion of any centre line (or of `P`) 1.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MechModeShape {
    /// The mode's frequency, flexure 1's `Omega`.
    pub omega: f64,
    /// The stage's motion `[dx, dy, dphi]` of `P`.
    pub stage: [f64; 3],
    /// Per flexure, its stations root to tip: the equilibrium's centre line and its motion.
    pub flexures: Vec<Vec<ModePoint>>,
}

/// The lowest modes of a mechanism about one equilibrium.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MechModes {
    /// Flexure 1's nondimensional frequencies `Omega`, ascending (negative: unstable).
    pub omega: Vec<f64>,
    /// The modes' shapes (empty when no stations were asked for).
    pub shapes: Vec<MechModeShape>,
}

/// One flexure's equilibrium: its wrench (own units and frame) and tip.
fn flexure_state(case: Option<&MechCase>, i: usize) -> (Load, TipPose) {
    match case.and_then(|c| c.flexures.get(i)) {
        Some(f) => (f.wrench, f.tip),
        None => (Load::new(0.0, 0.0, 0.0), TipPose::STRAIGHT),
    }
}

/// The modes of `mechanism` (validated) with masses `mass` about its unloaded equilibrium
/// (`case = None`) or a solved `case`, the stage coordinates `held` fixed.
pub fn mech_modes(
    mechanism: &Mechanism,
    mass: &MechMass,
    held: [bool; 3],
    case: Option<&MechCase>,
    settings: &ModeSettings,
) -> Result<MechModes, ModesError> {
    if settings.count == 0 {
        return Err(ModesError::BadInput(
            "the number of modes must be at least 1".to_string(),
        ));
    }
    let nf = mechanism.flexures.len();
    let mass = mass.clone().checked(nf)?;
    if let Some(c) = case {
        if c.flexures.len() != nf {
            return Err(ModesError::BadInput(format!(
                "the case has {} flexures, the mechanism {nf}",
                c.flexures.len()
            )));
        }
    }
    let geometry = Geometry::new(mechanism);
    let pose = case.map_or([0.0; 3], |c| c.stage);
    let mut flexures = Vec::with_capacity(nf);
    let mut offsets = Vec::with_capacity(nf + 1);
    let mut total = 0;
    for (i, f) in mechanism.flexures.iter().enumerate() {
        let (wrench, tip) = flexure_state(case, i);
        let m0 = wrench.beta + wrench.alpha_y * tip.a - wrench.alpha_x * tip.b;
        let model =
            FlexureModel::for_modes(&f.beam.model(), wrench, m0, settings.degree, settings.count)?;
        offsets.push(total);
        total += model.dofs();
        flexures.push(model);
    }
    let stage = total;
    total += 3;
    let mut k = DMatrix::<f64>::zeros(total, total);
    let mut m = DMatrix::<f64>::zeros(total, total);
    let mut rows: Vec<DVector<f64>> = Vec::new();
    let angle = pose[2];
    for (i, (flex, frame)) in flexures.iter().zip(&geometry.frames).enumerate() {
        let (o, n) = (offsets[i], flex.dofs());
        let (lam, kap, r) = (frame.length, frame.stiffness, mass.line_density[i]);
        k.view_mut((o, o), (n, n))
            .copy_from(&(flex.stiffness() * (kap / lam)));
        m.view_mut((o, o), (n, n))
            .copy_from(&(flex.mass() * (r * lam.powi(3))));
        // The tip's global motion per coordinate: lambda R(angle_i) (da, db), and dpsi.
        let t = flex.tip_map();
        let (s, c) = frame.angle.sin_cos();
        let mut tip_x = DVector::<f64>::zeros(total);
        let mut tip_y = DVector::<f64>::zeros(total);
        let mut tip_phi = DVector::<f64>::zeros(total);
        for j in 0..n {
            tip_x[o + j] = lam * (c * t[(0, j)] - s * t[(1, j)]);
            tip_y[o + j] = lam * (s * t[(0, j)] + c * t[(1, j)]);
            tip_phi[o + j] = t[(2, j)];
        }
        // The joint's stage point and its arm from P, in the current pose.
        let (wrench, tip) = flexure_state(case, i);
        let force = frame.force_to_global([wrench.alpha_x, wrench.alpha_y]);
        let q0 = match frame.joint {
            Joint::Link { to, .. } => to,
            Joint::Clamped | Joint::Pinned => frame.unloaded_tip(),
        };
        let p0 = geometry.stage_point;
        let arm = rotate([q0[0] - p0[0], q0[1] - p0[1]], angle);
        // The stage point's motion: (dx - dphi arm_y, dy + dphi arm_x).
        let mut stage_x = DVector::<f64>::zeros(total);
        let mut stage_y = DVector::<f64>::zeros(total);
        stage_x[stage] = 1.0;
        stage_x[stage + 2] = -arm[1];
        stage_y[stage + 1] = 1.0;
        stage_y[stage + 2] = arm[0];
        // The joint's reaction on the stage, F on the flexure: -F . rho on the rotation.
        k[(stage + 2, stage + 2)] -= force[0] * arm[0] + force[1] * arm[1];
        match frame.joint {
            Joint::Clamped => {
                rows.push(&tip_x - &stage_x);
                rows.push(&tip_y - &stage_y);
                let mut turn = tip_phi.clone();
                turn[stage + 2] -= 1.0;
                rows.push(turn);
            }
            Joint::Pinned => {
                rows.push(&tip_x - &stage_x);
                rows.push(&tip_y - &stage_y);
            }
            Joint::Link { length, .. } => {
                let tip_g = frame.to_global([tip.a, tip.b]);
                let end = geometry.stage_map(pose, q0);
                let (ux, uy) = ((end[0] - tip_g[0]) / length, (end[1] - tip_g[1]) / length);
                let (dx, dy) = (&stage_x - &tip_x, &stage_y - &tip_y);
                rows.push(&dx * ux + &dy * uy);
                // The coupler's string stiffness: tension / length across it.
                let tension = force[0] * ux + force[1] * uy;
                let across = &dx * (-uy) + &dy * ux;
                k += (tension / length) * &across * across.transpose();
            }
        }
    }
    m[(stage, stage)] += mass.stage_mass;
    m[(stage + 1, stage + 1)] += mass.stage_mass;
    m[(stage + 2, stage + 2)] += mass.stage_inertia;
    for (c, &h) in held.iter().enumerate() {
        if h {
            let mut row = DVector::<f64>::zeros(total);
            row[stage + c] = 1.0;
            rows.push(row);
        }
    }
    let z = null_space(&rows, total);
    if z.ncols() == 0 {
        return Err(ModesError::BadInput(
            "the mechanism cannot move at all: its joints and drive hold every coordinate"
                .to_string(),
        ));
    }
    let kr = z.transpose() * &k * &z;
    let mr = z.transpose() * &m * &z;
    let (omega_sq, vectors) = generalized_lowest(&kr, &mr, settings.count)?;
    let omega: Vec<f64> = omega_sq
        .iter()
        .map(|&w2| w2.signum() * w2.abs().sqrt())
        .collect();
    let shapes = if settings.shape_points >= 2 {
        vectors
            .iter()
            .zip(&omega)
            .map(|(v, &w)| {
                let full = &z * v;
                draw(&flexures, &offsets, &geometry, &full, stage, w, settings)
            })
            .collect()
    } else {
        Vec::new()
    };
    Ok(MechModes { omega, shapes })
}

/// A mode's shape in the global frame, normalised.
fn draw(
    flexures: &[FlexureModel],
    offsets: &[usize],
    geometry: &Geometry,
    full: &DVector<f64>,
    stage: usize,
    omega: f64,
    settings: &ModeSettings,
) -> MechModeShape {
    let mut lines = Vec::with_capacity(flexures.len());
    for (i, (flex, frame)) in flexures.iter().zip(&geometry.frames).enumerate() {
        let coords = &full.as_slice()[offsets[i]..offsets[i] + flex.dofs()];
        let points = flex
            .stations(coords, settings.shape_points)
            .into_iter()
            .map(|p| station_to_global(frame, p))
            .collect::<Vec<_>>();
        lines.push(points);
    }
    let mut stage_motion = [full[stage], full[stage + 1], full[stage + 2]];
    normalise(&mut stage_motion, &mut lines);
    MechModeShape {
        omega,
        stage: stage_motion,
        flexures: lines,
    }
}

/// A station of a flexure's mode (its own frame and units) in the global frame, flexure 1's
/// units.
pub(super) fn station_to_global(frame: &Frame, p: ModePoint) -> ModePoint {
    let at = frame.to_global([p.x, p.y]);
    let d = rotate([p.dx, p.dy], frame.angle);
    ModePoint {
        s: p.s,
        x: at[0],
        y: at[1],
        dx: frame.length * d[0],
        dy: frame.length * d[1],
        dpsi: p.dpsi,
    }
}

/// Scales a mode's motion (the stage's `[dx, dy, dphi]` of `P` and every station's) so that
/// the largest motion of `P` or of any station is 1 and the largest of their components is
/// positive (the beam's and the PRB mechanism's shapes alike).
pub(super) fn normalise(stage: &mut [f64; 3], lines: &mut [Vec<ModePoint>]) {
    let mut size = stage[0].hypot(stage[1]);
    let mut largest = if stage[0].abs() > stage[1].abs() {
        stage[0]
    } else {
        stage[1]
    };
    for p in lines.iter().flatten() {
        size = size.max(p.dx.hypot(p.dy));
        for v in [p.dx, p.dy] {
            if v.abs() > largest.abs() {
                largest = v;
            }
        }
    }
    if size > 0.0 && size.is_finite() {
        let scale = largest.signum() / size;
        for p in lines.iter_mut().flatten() {
            p.dx *= scale;
            p.dy *= scale;
            p.dpsi *= scale;
        }
        for v in stage.iter_mut() {
            *v *= scale;
        }
    }
}

/// A basis of the vectors `x` with `row . x = 0` for every row (columns of the result), by
/// Gaussian elimination with complete pivoting: each pivot column is solved for in terms of
/// the free ones, and rows that turn out dependent are dropped.
fn null_space(rows: &[DVector<f64>], n: usize) -> DMatrix<f64> {
    let mut a = DMatrix::<f64>::zeros(rows.len(), n);
    for (i, r) in rows.iter().enumerate() {
        a.row_mut(i).copy_from(&r.transpose());
    }
    let scale = a.iter().fold(0.0f64, |s, v| s.max(v.abs())).max(1.0);
    let mut pivots: Vec<(usize, usize)> = Vec::new();
    let mut used = vec![false; n];
    let mut live: Vec<usize> = (0..rows.len()).collect();
    while !live.is_empty() {
        // The largest entry among the live rows and unused columns.
        let mut best = (0, 0, 0.0f64);
        for &i in &live {
            for j in 0..n {
                if !used[j] && a[(i, j)].abs() > best.2 {
                    best = (i, j, a[(i, j)].abs());
                }
            }
        }
        if best.2 <= 1e-12 * scale {
            break;
        }
        let (pi, pj) = (best.0, best.1);
        let pivot = a[(pi, pj)];
        let row = a.row(pi) / pivot;
        a.row_mut(pi).copy_from(&row);
        for i in 0..rows.len() {
            if i != pi {
                let f = a[(i, pj)];
                if f != 0.0 {
                    let shifted = a.row(i) - &row * f;
                    a.row_mut(i).copy_from(&shifted);
                }
            }
        }
        used[pj] = true;
        pivots.push((pi, pj));
        live.retain(|&i| i != pi);
    }
    let free: Vec<usize> = (0..n).filter(|&j| !used[j]).collect();
    let mut z = DMatrix::<f64>::zeros(n, free.len());
    for (c, &j) in free.iter().enumerate() {
        z[(j, c)] = 1.0;
        for &(pi, pj) in &pivots {
            z[(pj, c)] = -a[(pi, j)];
        }
    }
    z
}

/// Why a mechanism's modes along its drives could not be found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MechModesError {
    /// The statics failed (their own message).
    #[error(transparent)]
    Statics(#[from] MechError),
    /// The modes failed.
    #[error(transparent)]
    Modes(#[from] ModesError),
}

/// The modes about every case of every drive of `mechanism`, solved exactly at
/// `resolution` first: one `Vec` per drive, one [`MechModes`] per case, each drive's
/// prescribed coordinates held.
pub fn drive_modes(
    mechanism: &Mechanism,
    mass: &MechMass,
    resolution: Resolution,
    settings: &ModeSettings,
) -> Result<Vec<Vec<MechModes>>, MechModesError> {
    let solved = exact::solve(mechanism, resolution)?;
    let mut out = Vec::with_capacity(solved.len());
    for (drive, cases) in mechanism.drives.iter().zip(&solved) {
        let held = held_by(drive);
        let modes = cases
            .iter()
            .map(|c| mech_modes(mechanism, mass, held, Some(c), settings))
            .collect::<Result<Vec<_>, _>>()?;
        out.push(modes);
    }
    Ok(out)
}
