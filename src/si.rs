//! SI values of a nondimensional PRB model for a given beam (DESIGN §1, §3): segment lengths
//! `gamma L` (m), torsion springs `K_theta = k_theta E I0 / L` (N m/rad), extension springs
//! `K_ex = k_ex E A0 / L` (N/m), and the loads `F = alpha E I0 / L^2` (N), `M = beta E I0 / L`
//! (N m). The core works nondimensionally; this is the one place that converts.
//!
//! With a density (`[beam] density`, DESIGN §10) a segment also carries its mass
//! `mu_i rho A0 L` (kg) and its rotary inertia about its centre, bending axis,
//! `m (gamma_i L)^2 / 12` (kg m^2): the PRB model whose frequencies prbfit computes.

use serde::{Deserialize, Serialize};

use crate::beam::Load;
use crate::prb::{Column, PrbMatrix};
use crate::scene::{BeamSpec, Body, Coordinate, LoadPath, Mechanism};

/// One segment in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SiSegment {
    /// m
    pub length: f64,
    /// N m/rad at the segment's root end; absent: no joint.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_theta: Option<f64>,
    /// N/m along the segment; absent: fixed length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_ex: Option<f64>,
    /// kg: `mu_i rho A0 L`; absent without a density.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// kg m^2 about the segment's centre (the bending axis, z): a uniform rod's
    /// `mass (gamma_i L)^2 / 12`; absent without a density.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<f64>,
}

/// A model in SI units for one beam.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SiModel {
    /// L, m.
    pub beam_length: f64,
    /// w0, m.
    pub width: f64,
    /// t0, m.
    pub thickness: f64,
    /// E, Pa.
    pub youngs_modulus: f64,
    /// Root first.
    pub segments: Vec<SiSegment>,
    /// A cantilever's tip body (`[tip]`: kg, kg m^2 about its centre of mass at the tip);
    /// absent without one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tip: Option<Body>,
    /// A mechanism's stage (`[stage]`: kg, kg m^2 about P), on flexure 1's entry; absent
    /// without one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stage: Option<Body>,
}

/// The range of a scene's loads, nondimensional and in SI (N, N m); the paths start at zero,
/// so zero is always inside.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LoadRange {
    /// `[min, max]` of `alpha_x`.
    pub alpha_x: [f64; 2],
    /// `[min, max]` of `alpha_y`.
    pub alpha_y: [f64; 2],
    /// `[min, max]` of `beta`.
    pub beta: [f64; 2],
    /// `[min, max]` of `Fx`, N.
    pub fx: [f64; 2],
    /// `[min, max]` of `Fy`, N.
    pub fy: [f64; 2],
    /// `[min, max]` of `Mz`, N m.
    pub mz: [f64; 2],
}

/// SI value per nondimensional unit of a matrix column for `beam`: L (m) for gamma,
/// `E I0 / L` (N m/rad) for k_theta, `E A0 / L` (N/m) for k_ex, the beam's mass
/// `rho A0 L` (kg) for mu, or 1 (mu stays a fraction) when the beam has no density.
pub fn column_factor(beam: &BeamSpec, col: Column) -> f64 {
    match col {
        Column::Gamma => beam.length,
        Column::KTheta => beam.youngs_modulus * beam.second_moment() / beam.length,
        Column::KEx => beam.youngs_modulus * beam.area() / beam.length,
        Column::Mu => beam_mass(beam).unwrap_or(1.0),
    }
}

/// The beam's mass `rho A0 L` (kg), when the scene gives its density.
pub fn beam_mass(beam: &BeamSpec) -> Option<f64> {
    beam.density.map(|rho| rho * beam.area() * beam.length)
}

/// The force (N) of `alpha = 1` and the moment (N m) of `beta = 1` for `beam`.
pub fn load_factors(beam: &BeamSpec) -> (f64, f64) {
    let ei = beam.youngs_modulus * beam.second_moment();
    (ei / (beam.length * beam.length), ei / beam.length)
}

/// A nondimensional load in SI: `(Fx, Fy, Mz)` in N, N, N m.
pub fn load_si(beam: &BeamSpec, load: &Load) -> [f64; 3] {
    let (force, moment) = load_factors(beam);
    [
        load.alpha_x * force,
        load.alpha_y * force,
        load.beta * moment,
    ]
}

/// The SI values of `matrix` for `beam`, with the segments' masses and inertias when the
/// beam has a density (no body: [`SiModel::tip`] and [`SiModel::stage`] are the caller's).
pub fn si_model(matrix: &PrbMatrix, beam: &BeamSpec) -> SiModel {
    let k_theta = column_factor(beam, Column::KTheta);
    let k_ex = column_factor(beam, Column::KEx);
    let total = beam_mass(beam);
    SiModel {
        beam_length: beam.length,
        width: beam.width,
        thickness: beam.thickness,
        youngs_modulus: beam.youngs_modulus,
        segments: matrix
            .rows()
            .iter()
            .map(|r| SiSegment {
                length: r.gamma * beam.length,
                k_theta: r.k_theta.is_finite().then_some(r.k_theta * k_theta),
                k_ex: r.k_ex.is_finite().then_some(r.k_ex * k_ex),
                mass: total.map(|m| r.mass() * m),
                inertia: total.map(|m| {
                    let length = r.gamma * beam.length;
                    r.mass() * m * length * length / 12.0
                }),
            })
            .collect(),
        tip: None,
        stage: None,
    }
}

/// The range of the load cases of `paths` on `beam`.
pub fn load_range(beam: &BeamSpec, paths: &[LoadPath]) -> LoadRange {
    let span = |f: &dyn Fn(&Load) -> f64| {
        paths.iter().fold([0.0_f64, 0.0_f64], |acc, p| {
            let v = f(&p.end);
            [acc[0].min(v), acc[1].max(v)]
        })
    };
    let ax = span(&|l| l.alpha_x);
    let ay = span(&|l| l.alpha_y);
    let be = span(&|l| l.beta);
    let (force, moment) = load_factors(beam);
    LoadRange {
        alpha_x: ax,
        alpha_y: ay,
        beta: be,
        fx: [ax[0] * force, ax[1] * force],
        fy: [ay[0] * force, ay[1] * force],
        mz: [be[0] * moment, be[1] * moment],
    }
}

/// A mechanism's SI scale (DESIGN §8: flexure 1 sets the units) and the display units the
/// reports and charts use: mm for flexures under a metre (else m), degrees, N, N m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MechUnits {
    /// Flexure 1's `L`, m.
    pub length: f64,
    /// `E I0 / L^2`, N: the force of `alpha = 1`.
    pub force: f64,
    /// `E I0 / L`, N m: the moment of `beta = 1`.
    pub moment: f64,
    /// "mm" or "m".
    pub distance: &'static str,
    /// Display distance units per metre.
    pub per_metre: f64,
}

impl MechUnits {
    /// The units of `mechanism`.
    pub fn new(mechanism: &Mechanism) -> MechUnits {
        let (length, ei) = mechanism.scale();
        let (distance, per_metre) = if length < 1.0 {
            ("mm", 1e3)
        } else {
            ("m", 1.0)
        };
        MechUnits {
            length,
            force: ei / (length * length),
            moment: ei / length,
            distance,
            per_metre,
        }
    }

    /// The SI factor of stage load coordinate `c` (N for x and y, N m for phi).
    pub fn load(&self, c: usize) -> f64 {
        if c == 2 {
            self.moment
        } else {
            self.force
        }
    }

    /// A stage motion of coordinate `c` (units of `L`, radians) in display units (mm or m,
    /// degrees).
    pub fn motion(&self, c: usize, v: f64) -> f64 {
        if c == 2 {
            v.to_degrees()
        } else {
            v * self.length * self.per_metre
        }
    }

    /// A drive's SI end value of coordinate `c` (m, rad, N, N m) in display units.
    pub fn input(&self, c: usize, coordinate: Coordinate) -> f64 {
        match coordinate {
            Coordinate::Prescribed(v) if c == 2 => v.to_degrees(),
            Coordinate::Prescribed(v) => v * self.per_metre,
            Coordinate::Loaded(v) => v,
        }
    }

    /// The display unit of coordinate `c`, prescribed (a motion) or not (a load).
    pub fn unit(&self, c: usize, prescribed: bool) -> &'static str {
        match (prescribed, c == 2) {
            (true, true) => "degrees",
            (true, false) => self.distance,
            (false, true) => "N m",
            (false, false) => "N",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn factors_are_the_design_conversions() {
        let scene = Scene::builtin();
        let b = &scene.beam;
        let ei = b.youngs_modulus * b.width * b.thickness.powi(3) / 12.0;
        let ea = b.youngs_modulus * b.width * b.thickness;
        let rel = |x: f64, y: f64| ((x - y) / y).abs();
        assert!(rel(column_factor(b, Column::KTheta), ei / b.length) < 1e-15);
        assert!(rel(column_factor(b, Column::KEx), ea / b.length) < 1e-15);
        let [fx, fy, mz] = load_si(b, &Load::new(2.0, 3.0, 0.5));
        assert!(rel(fx, 2.0 * ei / b.length.powi(2)) < 1e-15);
        assert!(rel(fy, 3.0 * ei / b.length.powi(2)) < 1e-15);
        assert!(rel(mz, 0.5 * ei / b.length) < 1e-15);
    }
}
