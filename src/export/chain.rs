//! The one description of a PRB chain that every simulator format writes: links with their
//! lengths, masses and inertias, and the joints between them, in SI units, laid along +x from
//! the clamp at the origin with revolute joints about +z.
//!
//! A segment `n` (1-based) is the link `segment{n}`. Its root end carries the revolute joint
//! `theta{n}` (a torsion spring), or the fixed joint `fixed{n}` when it has none; an extension
//! spring adds the prismatic joint `delta{n}` along the segment, which needs a tiny
//! intermediate link `segment{n}_hinge` in formats whose joints connect exactly two links
//! (URDF, SDF); MJCF puts both joints in one body. The free end carries the `tip` frame.
//!
//! Masses are the matrix's (DESIGN §10): segment i carries `mu_i rho A0 L` at its middle (a
//! three-column matrix: `mu_i = gamma_i`), its inertia about the bending axis (z) a uniform
//! rod's `m (gamma_i L)^2 / 12`, exactly the PRB model whose frequencies prbfit computes; about
//! x and y `m (l^2 + w^2) / 12` (they do not enter planar motion). A cantilever's tip body ([`Body`],
//! `[tip]`) is added to the last segment's (its centre of mass at the tip, parallel axis
//! theorem), so every format carries it without an extra link. A segment given `mu = 0` gets
//! `1e-9` of the beam's mass: simulators refuse massless moving links.

use crate::prb::PrbMatrix;
use crate::scene::{BeamSpec, Body};
use crate::si::si_model;

/// Length of the intermediate link of a segment with an extension spring, as a fraction of L
/// (massless in effect; it only gives the prismatic joint a parent).
pub const HINGE_LINK_FRACTION: f64 = 1e-6;

/// Mass, centre of mass and principal inertias (about the centre of mass, along x, y, z) of a
/// link.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// kg
    pub mass: f64,
    /// The centre of mass along the link from its root end, m.
    pub com: f64,
    /// kg m^2 about x, y, z.
    pub inertia: [f64; 3],
}

/// One segment of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainSegment {
    /// 1-based, root first.
    pub index: usize,
    /// Distance of the segment's root end from the clamp along x, m (unloaded).
    pub start_x: f64,
    /// m
    pub length: f64,
    /// Stiffness of the revolute joint at the root end, N m/rad; `None`: fixed.
    pub hinge: Option<f64>,
    /// Stiffness of the prismatic joint along the segment, N/m; `None`: rigid.
    pub slide: Option<f64>,
    /// The segment's mass (its mu's share of the beam's, with the tip body on the last).
    pub mass: MassProperties,
}

impl ChainSegment {
    /// The link's name.
    pub fn link(&self) -> String {
        format!("segment{}", self.index)
    }

    /// The intermediate link between the revolute and the prismatic joint.
    pub fn hinge_link(&self) -> String {
        format!("segment{}_hinge", self.index)
    }

    /// The link the root-end joint moves: the intermediate one when there is a slide.
    pub fn first_child(&self) -> String {
        if self.slide.is_some() {
            self.hinge_link()
        } else {
            self.link()
        }
    }

    /// The revolute joint's name (`theta{n}`), or the fixed joint's (`fixed{n}`).
    pub fn root_joint(&self) -> String {
        match self.hinge {
            Some(_) => format!("theta{}", self.index),
            None => format!("fixed{}", self.index),
        }
    }

    /// The prismatic joint's name.
    pub fn slide_joint(&self) -> String {
        format!("delta{}", self.index)
    }
}

/// A PRB chain ready to be written.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// The model's name in the file (`prbfit_l_r_r_r`).
    pub name: String,
    /// Beam length L, m (sets the scale of small links and limits).
    pub beam_length: f64,
    /// Section width, m.
    pub width: f64,
    /// Section thickness, m.
    pub thickness: f64,
    /// Root first.
    pub segments: Vec<ChainSegment>,
    /// The intermediate links' mass properties.
    pub hinge_link_mass: MassProperties,
}

impl Chain {
    /// The chain of `matrix` for `beam` of `density` (kg/m^3), `tip` bolted to its free end.
    pub fn new(matrix: &PrbMatrix, beam: &BeamSpec, density: f64, tip: &Body) -> Chain {
        let si = si_model(matrix, beam);
        let beam_mass = density * beam.area() * beam.length;
        let mut start_x = 0.0;
        let n = si.segments.len();
        let segments = si
            .segments
            .iter()
            .zip(matrix.rows())
            .enumerate()
            .map(|(i, (s, row))| {
                let mass = (row.mass() * beam_mass).max(1e-9 * beam_mass);
                let mut props = rod_mass(beam, mass, s.length);
                if i + 1 == n && !tip.is_none() {
                    props = with_tip(props, s.length, tip);
                }
                let seg = ChainSegment {
                    index: i + 1,
                    start_x,
                    length: s.length,
                    hinge: s.k_theta,
                    slide: s.k_ex,
                    mass: props,
                };
                start_x += s.length;
                seg
            })
            .collect();
        let boxed = |length: f64| rod_mass(beam, density * length * beam.area(), length);
        Chain {
            name: format!("prbfit_{}", ident(&matrix.topology())),
            beam_length: beam.length,
            width: beam.width,
            thickness: beam.thickness,
            segments,
            hinge_link_mass: boxed(HINGE_LINK_FRACTION * beam.length),
        }
    }

    /// The length of the intermediate links, m.
    pub fn hinge_link_length(&self) -> f64 {
        HINGE_LINK_FRACTION * self.beam_length
    }
}

/// A link of `mass` spread along `length` (a zero length is taken as 1e-9 L so that no
/// simulator sees a massless body): its centre in the middle, about z a uniform rod's
/// `m l^2 / 12` (DESIGN §10's PRB segment), about x and y `m (l^2 + w^2) / 12`
/// (out of the plane: only the simulators' inertia checks see them).
fn rod_mass(beam: &BeamSpec, mass: f64, length: f64) -> MassProperties {
    let length = length.max(1e-9 * beam.length);
    let w = beam.width;
    MassProperties {
        mass,
        com: length / 2.0,
        // About x and y `m (l^2 + w^2) / 12`: with z's `m l^2 / 12` the triangle inequality a
        // simulator checks (MuJoCo: A + B >= C, each way) holds with a margin of `m l^2 / 12`
        // for every length, the tiny hinge links' too (a box's would not beside the rod's z).
        inertia: [
            mass * (length * length + w * w) / 12.0,
            mass * (length * length + w * w) / 12.0,
            mass * length * length / 12.0,
        ],
    }
}

/// The MJCF time step as a fraction of the fastest spring's `1 / omega`.
pub const STEP_FRACTION: f64 = 0.01;

/// The time step: [`STEP_FRACTION`] of the fastest spring's `1 / omega`, `omega^2` its
/// stiffness over the unloaded chain's inertia (or mass, for an extension spring) beyond it
/// (the tip body's included):
/// the diagonal estimate `tests/mujoco_check.py` uses for the single chain, with the stage's
/// and couplers' inertia left out (which only slows the springs). With 100 steps per
/// `1 / omega` and the springs' damping integrated implicitly, it is stable with a wide
/// margin; the closures' `tau` of two steps is what needs it this small (module docs).
pub fn time_step(chains: &[Chain]) -> f64 {
    let mut omega_max = 0.0_f64;
    for chain in chains {
        let segs = &chain.segments;
        for (i, s) in segs.iter().enumerate() {
            let mut inertia = 0.0;
            let mut mass = 0.0;
            let mut d = 0.0;
            for t in &segs[i..] {
                let (m, c) = (t.mass.mass, d + t.mass.com);
                inertia += t.mass.inertia[2] + m * c * c;
                mass += m;
                d += t.length;
            }
            if let Some(k) = s.hinge {
                omega_max = omega_max.max((k / inertia).sqrt());
            }
            if let Some(k) = s.slide {
                omega_max = omega_max.max((k / mass).sqrt());
            }
        }
    }
    if omega_max > 0.0 && omega_max.is_finite() {
        STEP_FRACTION / omega_max
    } else {
        // A valid matrix has a spring; this only keeps the file loadable.
        1e-3
    }
}

/// `link` of `length` with `tip` (its centre of mass at the link's end) added: the combined
/// mass, centre and inertias about the combined centre (parallel axis theorem; the body's
/// own inertia about each axis taken as its given one).
fn with_tip(link: MassProperties, length: f64, tip: &Body) -> MassProperties {
    let mass = link.mass + tip.mass;
    let com = (link.mass * link.com + tip.mass * length) / mass;
    let (d_link, d_tip) = (link.com - com, length - com);
    let shift = link.mass * d_link * d_link + tip.mass * d_tip * d_tip;
    MassProperties {
        mass,
        com,
        inertia: [
            link.inertia[0] + tip.inertia,
            link.inertia[1] + tip.inertia + shift,
            link.inertia[2] + tip.inertia + shift,
        ],
    }
}

/// A name safe for XML ids and ROS names.
pub fn ident(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect()
}

/// A number as every format writes it: Rust's shortest exponent form, which round-trips.
pub fn g(v: f64) -> String {
    format!("{v:e}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Links carry the mus' share of the beam's mass with a rod's inertia about z; the tip
    /// body joins the last link by the parallel axis theorem.
    #[test]
    fn links_carry_the_mus_and_the_tip_body() {
        let beam = crate::scene::Scene::builtin().beam;
        let m = PrbMatrix::parse("0.15,inf,inf,0.25; 0.85,2.2525,inf,0.75").unwrap();
        let total = 7850.0 * beam.area() * beam.length;
        let chain = Chain::new(&m, &beam, 7850.0, &Body::default());
        let link = chain.segments[1].mass;
        let l = 0.85 * beam.length;
        assert!((link.mass - 0.75 * total).abs() < 1e-15 * total);
        assert!((link.com - l / 2.0).abs() < 1e-15);
        assert!((link.inertia[2] - link.mass * l * l / 12.0).abs() < 1e-12 * link.inertia[2]);
        let tip = Body {
            mass: link.mass,
            inertia: 1e-9,
        };
        let with = Chain::new(&m, &beam, 7850.0, &tip).segments[1].mass;
        // Two equal masses at l/2 and l: centre at 3l/4, each l/4 from it.
        assert!((with.mass - 2.0 * link.mass).abs() < 1e-15);
        assert!((with.com - 0.75 * l).abs() < 1e-15);
        let want = link.inertia[2] + 1e-9 + 2.0 * link.mass * (l / 4.0).powi(2);
        assert!((with.inertia[2] - want).abs() < 1e-12 * want);
    }
}
