//! The one description of a PRB chain that every simulator format writes: links with their
//! lengths, masses and inertias, and the joints between them, in SI units, laid along +x from
//! the clamp at the origin with revolute joints about +z.
//!
//! A segment `n` (1-based) is the link `segment{n}`. Its root end carries the revolute joint
//! `theta{n}` (a torsion spring), or the fixed joint `fixed{n}` when it has none; an extension
//! spring adds the prismatic joint `delta{n}` along the segment, which needs a tiny
//! intermediate link `segment{n}_hinge` in formats whose joints connect exactly two links
//! (URDF, SDF); MJCF puts both joints in one body. The free end carries the `tip` frame.

use crate::prb::PrbMatrix;
use crate::scene::BeamSpec;
use crate::si::si_model;

/// Length of the intermediate link of a segment with an extension spring, as a fraction of L
/// (massless in effect; it only gives the prismatic joint a parent).
pub const HINGE_LINK_FRACTION: f64 = 1e-6;

/// Mass and principal inertias (about the link's centre, along x, y, z) of a box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// kg
    pub mass: f64,
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
    /// The segment as a box `length x thickness x width`.
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
    /// The chain of `matrix` for `beam`, its links boxes of `density` (kg/m^3).
    pub fn new(matrix: &PrbMatrix, beam: &BeamSpec, density: f64) -> Chain {
        let si = si_model(matrix, beam);
        let boxed = |length: f64| box_mass(beam, density, length);
        let mut start_x = 0.0;
        let segments = si
            .segments
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let seg = ChainSegment {
                    index: i + 1,
                    start_x,
                    length: s.length,
                    hinge: s.k_theta,
                    slide: s.k_ex,
                    mass: boxed(s.length),
                };
                start_x += s.length;
                seg
            })
            .collect();
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

/// Mass and inertia of a box `length x width x thickness` of `density` (a zero length is
/// taken as 1e-9 L so that no simulator sees a massless body).
fn box_mass(beam: &BeamSpec, density: f64, length: f64) -> MassProperties {
    let length = length.max(1e-9 * beam.length);
    let (w, t) = (beam.width, beam.thickness);
    let mass = density * length * w * t;
    MassProperties {
        mass,
        inertia: [
            mass * (w * w + t * t) / 12.0,
            mass * (length * length + t * t) / 12.0,
            mass * (length * length + w * w) / 12.0,
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
