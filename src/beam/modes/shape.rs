//! A mode's shape for drawing: the equilibrium's centre line and the mode's motion at
//! evenly spaced stations.

use serde::Serialize;

use super::basis::{integrated_legendre, integration_matrix, Quadrature};
use super::discrete::BeamMatrices;

/// One station of a mode shape, in units of the beam's `L` and its own frame (clamp at the
/// origin, unloaded along +x).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ModePoint {
    /// Arc length of the unloaded beam, 0 at the clamp, 1 at the tip.
    pub s: f64,
    /// The equilibrium's centre line.
    pub x: f64,
    /// The equilibrium's centre line.
    pub y: f64,
    /// The mode's motion of the centre line, normalised (see [`ModeShape`]).
    pub dx: f64,
    /// The mode's motion of the centre line, normalised.
    pub dy: f64,
    /// The mode's rotation of the section, on the same scale as `dx`, `dy`.
    pub dpsi: f64,
}

/// A mode's shape: the largest motion of the centre line over the stations is 1, and the
/// largest of its components is positive (so a shape does not flip sign between cases).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeShape {
    /// The mode's nondimensional frequency.
    pub omega: f64,
    /// The stations, root to tip.
    pub points: Vec<ModePoint>,
}

/// The shape of the motion `coords` of the beam `m` at `points` stations, normalised.
pub(crate) fn draw(
    m: &BeamMatrices,
    quad: &Quadrature,
    coords: &[f64],
    omega: f64,
    points: usize,
) -> ModeShape {
    let mut out = stations(m, quad, coords, points);
    normalise(&mut out);
    ModeShape { omega, points: out }
}

/// The motion `coords` of the beam `m` at `points` evenly spaced stations, as it is.
pub(crate) fn stations(
    m: &BeamMatrices,
    quad: &Quadrature,
    coords: &[f64],
    points: usize,
) -> Vec<ModePoint> {
    let count = points.max(2);
    let stations: Vec<f64> = (0..count).map(|k| k as f64 / (count - 1) as f64).collect();
    let nq = quad.len();
    let s_out = integration_matrix(&quad.nodes, &quad.weights, &stations);
    let vx = &m.slope_x * nalgebra::DVector::from_column_slice(coords);
    let vy = &m.slope_y * nalgebra::DVector::from_column_slice(coords);
    let n = m.layout.degree;
    let mut phi = vec![0.0; n];
    let mut buf = vec![0.0; n + 2];
    let mut out = Vec::with_capacity(count);
    for (k, &s) in stations.iter().enumerate() {
        let row = &s_out[k * nq..(k + 1) * nq];
        let (mut x, mut y, mut dx, mut dy) = (0.0, 0.0, 0.0, 0.0);
        for q in 0..nq {
            x += row[q] * m.centre_slope[q].0;
            y += row[q] * m.centre_slope[q].1;
            dx += row[q] * vx[q];
            dy += row[q] * vy[q];
        }
        integrated_legendre(s, n, &mut phi, &mut buf);
        let dpsi: f64 = (0..n).map(|j| phi[j] * coords[j]).sum();
        out.push(ModePoint {
            s,
            x,
            y,
            dx,
            dy,
            dpsi,
        });
    }
    out
}

/// Scales the motion so its largest is 1 and its largest component is positive (the
/// rotation's, if the centre line does not move).
pub fn normalise(points: &mut [ModePoint]) {
    let mut size = 0.0f64;
    let mut largest = 0.0f64;
    for p in points.iter() {
        size = size.max(p.dx.hypot(p.dy));
        for v in [p.dx, p.dy] {
            if v.abs() > largest.abs() {
                largest = v;
            }
        }
    }
    if size == 0.0 {
        size = points.iter().fold(0.0f64, |a, p| a.max(p.dpsi.abs()));
        largest = points
            .iter()
            .map(|p| p.dpsi)
            .fold(0.0f64, |a, v| if v.abs() > a.abs() { v } else { a });
    }
    if !(size > 0.0 && size.is_finite()) {
        return;
    }
    let scale = largest.signum() / size;
    for p in points.iter_mut() {
        p.dx *= scale;
        p.dy *= scale;
        p.dpsi *= scale;
    }
}
