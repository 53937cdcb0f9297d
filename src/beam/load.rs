//! The beam's load and pose: the tip load in the paper's nondimensional form, the tip pose
//! and the points of the deformed centre line (DESIGN §1, §2).

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::text::bounded;

/// A tip load in the paper's nondimensional form: `alpha_x = Fx L^2 / (E I0)`,
/// `alpha_y = Fy L^2 / (E I0)`, `beta = Mz L / (E I0)`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Load {
    /// Tip force along the clamp's axis (x), `Fx L^2 / (E I0)`; negative compresses the
    /// unloaded beam.
    pub alpha_x: f64,
    /// Tip force across the clamp's axis (y), `Fy L^2 / (E I0)`.
    pub alpha_y: f64,
    /// Tip moment, `Mz L / (E I0)`, counter-clockwise positive; `2 pi` curls the elastica
    /// into a full circle.
    pub beta: f64,
}

impl Load {
    /// The load `(alpha_x, alpha_y, beta)`; the forces keep this direction while the beam
    /// deflects (they are not follower loads).
    pub const fn new(alpha_x: f64, alpha_y: f64, beta: f64) -> Load {
        Load {
            alpha_x,
            alpha_y,
            beta,
        }
    }

    /// The load scaled by `lambda` (a point on a proportional load path).
    pub fn scaled(&self, lambda: f64) -> Load {
        Load::new(
            lambda * self.alpha_x,
            lambda * self.alpha_y,
            lambda * self.beta,
        )
    }

    /// `|alpha_x| + |alpha_y| + |beta|`, the size of the load.
    pub fn magnitude(&self) -> f64 {
        self.alpha_x.abs() + self.alpha_y.abs() + self.beta.abs()
    }

    /// Whether all three components are finite (neither infinite nor NaN); the solver
    /// refuses any other load with
    /// [`SolveError::NonFiniteLoad`](super::SolveError::NonFiniteLoad).
    pub fn is_finite(&self) -> bool {
        self.alpha_x.is_finite() && self.alpha_y.is_finite() && self.beta.is_finite()
    }

    /// Parses `AX,AY,BETA`.
    pub fn parse(text: &str) -> Result<Load, String> {
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        if parts.len() != 3 {
            return Err(format!(
                "expected three numbers AX,AY,BETA, got {} in `{text}`",
                parts.len()
            ));
        }
        let mut v = [0.0; 3];
        for (slot, part) in v.iter_mut().zip(&parts) {
            let x: f64 = part
                .parse()
                .map_err(|_| format!("`{part}` is not a number (in `{text}`)"))?;
            if !x.is_finite() {
                return Err(format!("`{part}` is not a finite number (in `{text}`)"));
            }
            *slot = x;
        }
        Ok(Load::new(v[0], v[1], v[2]))
    }
}

impl fmt::Display for Load {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "alpha_x = {}, alpha_y = {}, beta = {}",
            bounded(self.alpha_x),
            bounded(self.alpha_y),
            bounded(self.beta)
        )
    }
}

/// The tip pose: position in units of L, cross-section angle in radians.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct TipPose {
    /// Tip position along the clamp's axis, `x(L) / L` (1 for the unloaded beam).
    pub a: f64,
    /// Tip position across the clamp's axis, `y(L) / L`.
    pub b: f64,
    /// Tip cross-section angle `psi(L)`, radians, counter-clockwise positive: the
    /// orientation of a rigid body bolted to the tip. With shear on it differs from the
    /// slope of the centre line by the shear angle `atan(gamma / (1 + eps))`.
    pub phi: f64,
}

impl TipPose {
    /// The pose of the unloaded beam.
    pub const STRAIGHT: TipPose = TipPose {
        a: 1.0,
        b: 0.0,
        phi: 0.0,
    };

    /// Largest component difference (units of L and radians).
    pub fn max_diff(&self, other: &TipPose) -> f64 {
        (self.a - other.a)
            .abs()
            .max((self.b - other.b).abs())
            .max((self.phi - other.phi).abs())
    }
}

/// A point of the deformed centre line.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShapePoint {
    /// Material coordinate, units of L.
    pub s: f64,
    /// Position along the clamp's axis, units of L.
    pub x: f64,
    /// Position across the clamp's axis, units of L.
    pub y: f64,
    /// Cross-section angle, radians.
    pub psi: f64,
}
