//! Frames and units of a mechanism (DESIGN §8), nondimensional.
//!
//! The global frame is the scene's, in units of flexure 1's `L`; forces are
//! `alpha = F L1^2 / (E I1)` and moments `beta = M L1 / (E I1)` (flexure 1's `L1`, `E I1`).
//! Flexure i lives in its own frame: root at the origin, unloaded along +x, lengths in its own
//! `L_i`, loads in its own `E I_i` and `L_i`, so that its tip under its wrench is exactly the
//! single beam's (`prbfit solve --load`). With `lambda_i = L_i / L1`, `kappa_i = E I_i / E I1`
//! and `R_i` the rotation by the flexure's angle, a point maps as
//! `x_global = root_i + lambda_i R_i x_local`, a force as
//! `alpha_global = (kappa_i / lambda_i^2) R_i alpha_local`, a moment as
//! `beta_global = (kappa_i / lambda_i) beta_local`, and angles add the flexure's angle.
//!
//! The stage is rigid: a point of it at `q0` in the unloaded pose goes to
//! `P0 + (dx, dy) + R(dphi) (q0 - P0)` where `P0` is the stage point.

use crate::scene::{Attach, Mechanism};

/// How a flexure's tip meets the stage, nondimensional.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Joint {
    /// The tip is bolted to the stage: position and angle follow it.
    Clamped,
    /// A pin at the unloaded tip: position follows the stage, tip moment zero.
    Pinned,
    /// A rigid coupler pinned at both ends: tip force along the coupler, tip moment zero.
    Link {
        /// The coupler's stage end in the unloaded pose (global frame).
        to: [f64; 2],
        /// The coupler's length (units of flexure 1's `L`).
        length: f64,
    },
}

/// One flexure's frame and scale relative to flexure 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// The clamp, global frame.
    pub root: [f64; 2],
    /// The unloaded direction, radians.
    pub angle: f64,
    /// `lambda_i = L_i / L1`.
    pub length: f64,
    /// `kappa_i = E I_i / (E I1)`.
    pub stiffness: f64,
    /// How the tip meets the stage.
    pub joint: Joint,
}

impl Frame {
    /// A point of the flexure's frame (its own units) in the global frame.
    pub fn to_global(&self, p: [f64; 2]) -> [f64; 2] {
        let r = rotate(p, self.angle);
        [
            self.root[0] + self.length * r[0],
            self.root[1] + self.length * r[1],
        ]
    }

    /// A global point in the flexure's frame (its own units).
    pub fn to_local(&self, p: [f64; 2]) -> [f64; 2] {
        let d = [
            (p[0] - self.root[0]) / self.length,
            (p[1] - self.root[1]) / self.length,
        ];
        rotate(d, -self.angle)
    }

    /// A force in the flexure's units and frame, in the global frame and flexure 1's units.
    pub fn force_to_global(&self, f: [f64; 2]) -> [f64; 2] {
        let s = self.stiffness / (self.length * self.length);
        let r = rotate(f, self.angle);
        [s * r[0], s * r[1]]
    }

    /// A global force (flexure 1's units) in the flexure's frame and units.
    pub fn force_to_local(&self, f: [f64; 2]) -> [f64; 2] {
        let s = self.length * self.length / self.stiffness;
        let r = rotate(f, -self.angle);
        [s * r[0], s * r[1]]
    }

    /// A moment in the flexure's units, in flexure 1's.
    pub fn moment_to_global(&self, beta: f64) -> f64 {
        beta * self.stiffness / self.length
    }

    /// The unloaded tip, global frame.
    pub fn unloaded_tip(&self) -> [f64; 2] {
        self.to_global([1.0, 0.0])
    }
}

/// The mechanism's geometry, nondimensional.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// One frame per flexure, in order.
    pub frames: Vec<Frame>,
    /// The stage point `P0`, global frame.
    pub stage_point: [f64; 2],
}

impl Geometry {
    /// The nondimensional geometry of a validated mechanism.
    pub fn new(mechanism: &Mechanism) -> Geometry {
        let (l1, ei1) = mechanism.scale();
        let scaled = |p: [f64; 2]| [p[0] / l1, p[1] / l1];
        let frames = mechanism
            .flexures
            .iter()
            .map(|f| {
                let joint = match f.attach {
                    Attach::Clamped => Joint::Clamped,
                    Attach::Pinned => Joint::Pinned,
                    Attach::Link { to } => {
                        let tip = f.tip();
                        Joint::Link {
                            to: scaled(to),
                            length: (to[0] - tip[0]).hypot(to[1] - tip[1]) / l1,
                        }
                    }
                };
                Frame {
                    root: scaled(f.root),
                    angle: f.angle,
                    length: f.beam.length / l1,
                    stiffness: f.beam.youngs_modulus * f.beam.second_moment() / ei1,
                    joint,
                }
            })
            .collect();
        Geometry {
            frames,
            stage_point: scaled(mechanism.stage_point),
        }
    }

    /// Where the stage point that sat at `q0` goes when the stage takes `pose`
    /// (`[dx, dy, dphi]`).
    pub fn stage_map(&self, pose: [f64; 3], q0: [f64; 2]) -> [f64; 2] {
        let p = self.stage_point;
        let r = rotate([q0[0] - p[0], q0[1] - p[1]], pose[2]);
        [p[0] + pose[0] + r[0], p[1] + pose[1] + r[1]]
    }

    /// The current stage point `P` for `pose`.
    pub fn stage_point_at(&self, pose: [f64; 3]) -> [f64; 2] {
        [self.stage_point[0] + pose[0], self.stage_point[1] + pose[1]]
    }
}

/// `p` turned by `angle` about the origin.
pub fn rotate(p: [f64; 2], angle: f64) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

/// The z component of `a x b`.
pub fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
