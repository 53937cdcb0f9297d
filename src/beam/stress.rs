//! The largest fibre stress along the beam (DESIGN §11).
//!
//! At a section `s` the fibre stress is largest at the outer fibre on the side the moment
//! stretches:
//!
//! ```text
//! sigma(s) = |N| / A + |M| (t / 2) / I
//! ```
//!
//! with the section's axial force `N = alpha_x cos psi + alpha_y sin psi` and moment
//! `M(s) = beta + alpha_y (a - x) - alpha_x (b - y)` (statics: the moment is fixed by the
//! load and the shape, so plane strain changes the shape, not this formula), and the section
//! at `s`: with Poisson's effect it shrinks by `p = 1 - nu eps` in width and thickness, so
//! `A = A0 p^2`, `t = t0 p`, `I = I0 p^4`. In units of `E` (the nominal modulus that makes the
//! loads nondimensional):
//!
//! ```text
//! sigma / E = c_e |N| / p^2 + |M| / (2 (L / t0) p^3),    c_e = I0 / (A0 L^2)
//! ```
//!
//! # Finding the maximum
//! `sigma` is smooth except where `N` or `M` changes sign, and there it has a kink pointing
//! down (a minimum), so its maximum is at an end of the beam or where `d sigma / ds = 0`.
//! The derivative is exact at every shape point (the beam's own equations give `M'`,
//! `psi'` and, through the material law, `p'`), so each interval between shape points gets
//! the cubic Hermite interpolant of `sigma`; an interval whose slope turns from rising to
//! falling holds an interior peak, which is then found on the beam itself: short shots from
//! the interval's left point (the integrator, not the interpolant) locate the zero of
//! `d sigma / ds` by safeguarded regula falsi to `1e-10 L`. So a coarse shape costs a few
//! short integrations, never accuracy: a peak is missed only if one interval of the shape
//! holds two interior extrema of `sigma`.

use serde::{Deserialize, Serialize};

use super::shoot::{Meter, Segment, TipForce};
use super::shot::shoot;
use super::{BeamModel, BeamSolver, Load, ShapePoint, TipPose};
use crate::cancel::CancelToken;

/// The largest fibre stress along a beam and where it is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Stress {
    /// The largest fibre stress, in units of the beam's Young's modulus (`sigma / E`).
    pub max: f64,
    /// Where it is, `s / L` (0 at the clamp).
    pub at: f64,
}

/// Storage for [`BeamSolver::max_stress`]'s per-point values, kept along a path so that each
/// case allocates nothing.
#[derive(Debug, Default, Clone)]
pub(crate) struct StressScratch {
    values: Vec<f64>,
    /// Each point's bending stress, without its shrink.
    bending: Vec<f64>,
    matters: Vec<bool>,
    slopes: Vec<Option<f64>>,
}

/// How close to the peak the search on the beam goes, units of L.
const PEAK_TOL: f64 = 1e-10;
/// The most short shots spent on one interior peak.
const PEAK_SHOTS: usize = 40;

impl BeamModel {
    /// The fibre stress `sigma / E` of a section carrying the axial force `n` and the moment
    /// `m` (units of `E I0 / L^2` and `E I0 / L`), its shrink included when Poisson's effect
    /// is on; `None` where the material law has no state (necked or crushed).
    pub fn fibre_stress(&self, n: f64, m: f64) -> Option<f64> {
        let (_, _, p) = self.axial_strain(n).ok()?;
        Some(self.fibre_stress_shrunk(n, m, p))
    }

    fn fibre_stress_shrunk(&self, n: f64, m: f64, p: f64) -> f64 {
        let p2 = p * p;
        self.axial_compliance() * n.abs() / p2 + m.abs() / (2.0 * self.slenderness * p2 * p)
    }
}

/// `sigma` and `d sigma / ds` at a section of angle `psi` carrying the moment `m`.
fn stress_and_slope(model: &BeamModel, force: TipForce, psi: f64, m: f64) -> Option<(f64, f64)> {
    let (sn, cs) = crate::trig::sin_cos(psi);
    let n = force.alpha_x * cs + force.alpha_y * sn;
    let q = -force.alpha_x * sn + force.alpha_y * cs;
    let (eps, de_dn, p) = model.axial_strain(n).ok()?;
    // The shot's rates of `psi` and `M` (the arithmetic of `shoot::rhs`, from this section's
    // state).
    let inv_p = if model.effects.poisson { 1.0 / p } else { 1.0 };
    let inv_p2 = inv_p * inv_p;
    let bend_compliance = if model.effects.poisson {
        model.plate_compliance() * inv_p2 * inv_p2
    } else {
        model.plate_compliance()
    };
    let gamma = if model.effects.shear {
        model.shear_compliance() * q * inv_p2
    } else {
        0.0
    };
    let (dpsi, dm) = (m * bend_compliance, -(1.0 + eps) * q + gamma * n);
    let dn = q * dpsi;
    let dp = if model.effects.poisson {
        -model.nu * de_dn * dn
    } else {
        0.0
    };
    let c_e = model.axial_compliance();
    let bend = 1.0 / (2.0 * model.slenderness);
    let (p2, p3) = (p * p, p * p * p);
    let sigma = c_e * n.abs() / p2 + bend * m.abs() / p3;
    let slope = c_e * (n.signum() * dn / p2 - 2.0 * n.abs() * dp / p3)
        + bend * (m.signum() * dm / p3 - 3.0 * m.abs() * dp / (p3 * p));
    Some((sigma, slope))
}

/// The cubic Hermite interpolant on `[0, 1]` of values `v0, v1` and slopes `d0, d1` (per unit
/// of the interval): its interior maximum `(t, value)`, if its slope turns from positive to
/// negative inside.
fn hermite_peak(v0: f64, v1: f64, d0: f64, d1: f64) -> Option<(f64, f64)> {
    if !(d0 > 0.0 && d1 < 0.0) {
        return None;
    }
    // p(t) = v0 + d0 t + c2 t^2 + c3 t^3
    let c2 = 3.0 * (v1 - v0) - 2.0 * d0 - d1;
    let c3 = 2.0 * (v0 - v1) + d0 + d1;
    // p'(t) = d0 + 2 c2 t + 3 c3 t^2 goes from d0 > 0 to d1 < 0: one root in (0, 1) where
    // it falls, found by bisection (robust whatever the cubic's coefficients).
    let slope = |t: f64| d0 + t * (2.0 * c2 + 3.0 * c3 * t);
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if slope(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let t = 0.5 * (lo + hi);
    Some((t, v0 + t * (d0 + t * (c2 + t * c3))))
}

impl BeamSolver {
    /// The largest fibre stress along the beam in the equilibrium `(load, tip, shape)` (the
    /// shape's points at uniform `s`, root and tip included, as a solve returns them), and
    /// where it is; `None` without a shape (measured data has none) or where the material
    /// law has no state. See the module's docs for the method.
    pub fn max_stress(&self, load: Load, tip: TipPose, shape: &[ShapePoint]) -> Option<Stress> {
        self.max_stress_pruned(load, tip, shape, true, &mut StressScratch::default())
    }

    /// [`BeamSolver::max_stress`] in storage kept from case to case (a path's cases).
    pub(crate) fn max_stress_with(
        &self,
        load: Load,
        tip: TipPose,
        shape: &[ShapePoint],
        scratch: &mut StressScratch,
    ) -> Option<Stress> {
        self.max_stress_pruned(load, tip, shape, true, scratch)
    }

    /// [`BeamSolver::max_stress`], with (`prune`) or without the bound that spares the far
    /// points their sine and cosine (the same result either way: a test checks it).
    fn max_stress_pruned(
        &self,
        load: Load,
        tip: TipPose,
        shape: &[ShapePoint],
        prune: bool,
        scratch: &mut StressScratch,
    ) -> Option<Stress> {
        let StressScratch {
            values,
            bending,
            matters,
            slopes,
        } = scratch;
        values.clear();
        let model = &self.model;
        let force = TipForce {
            alpha_x: load.alpha_x,
            alpha_y: load.alpha_y,
        };
        let moment = |p: &ShapePoint| {
            load.beta + load.alpha_y * (tip.a - p.x) - load.alpha_x * (tip.b - p.y)
        };
        if load.alpha_x == 0.0 && load.alpha_y == 0.0 {
            // No force: `M = beta` and `N = 0` at every section (statics), so the stress is
            // the same everywhere; the clamp is where it is first reached.
            let max = model.fibre_stress(0.0, load.beta)?;
            return shape.first().map(|p| Stress { max, at: p.s });
        }
        // Values first (cheap); slopes only around the shape's own local maxima, where an
        // interior peak can hide (a single peak between points makes its higher neighbour
        // a local maximum of the samples).
        //
        // The section's shrink `p` costs a solve of the material law per point, and changes
        // the stress by a factor within `[1 / p(-F)^3, 1 / p(F)^3]` (`F = |force|` bounds
        // `|N|`), so the points are first ranked without it, and it is applied only to
        // those that can still be the largest.
        let bend = 1.0 / (2.0 * model.slenderness);
        let c_e = model.axial_compliance();
        let shrinks = model.effects.poisson;
        // A point's stress, from its sine and cosine (and, with the shrink, a solve of the
        // material law).
        let exact = |p: &ShapePoint| {
            let (sn, cs) = crate::trig::sin_cos(p.psi);
            let n = force.alpha_x * cs + force.alpha_y * sn;
            if shrinks {
                model.fibre_stress(n, moment(p))
            } else {
                Some(c_e * n.abs() + bend * moment(p).abs())
            }
        };
        if !prune {
            for p in shape {
                values.push(exact(p)?);
            }
        } else {
            // `|N| <= F` bounds each point's stress between its bending part `b` (which
            // needs no sine or cosine) times `lo` and `b + c_e F` times `hi`, where `lo` and
            // `hi` bound the shrink's factor `1 / p^3` (or `1 / p^2`, which lies between
            // them) over `|N| <= F`: 1 without Poisson's shrink. The tests below read a
            // point's exact stress only where it can matter: where it can be the largest (its
            // upper bound reaches the largest lower bound), or a local maximum at half the
            // largest or more (its upper bound reaches half the largest lower bound and its
            // neighbours' lower bounds). Every other point is below the largest, and below
            // half of it or below a neighbour, with its exact stress or with its lower bound:
            // the tests skip it either way. So those points and their neighbours get their
            // exact stress and the rest keep their lower bound, and the result is the same,
            // bit for bit, as with every point exact.
            let f = load.alpha_x.hypot(load.alpha_y);
            let (lo, hi) = if shrinks {
                let p_of = |n: f64| model.axial_strain(n).ok().map(|(_, _, p)| p);
                // A force the law cannot carry along the section's axis (that the beam's own
                // sections never meet): no bound, every point gets its exact stress.
                match (p_of(-f), p_of(f)) {
                    (Some(a), Some(b)) => (a.powi(-3), b.powi(-3)),
                    _ => (0.0, f64::INFINITY),
                }
            } else {
                (1.0, 1.0)
            };
            let axial_bound = c_e * f;
            bending.clear();
            bending.extend(shape.iter().map(|p| bend * moment(p).abs()));
            values.extend(bending.iter().map(|b| b * lo));
            let top = values.iter().copied().fold(0.0, f64::max);
            let last = values.len().checked_sub(1)?;
            matters.clear();
            matters.extend((0..=last).map(|i| {
                let upper = (bending[i] + axial_bound) * hi;
                let left = if i == 0 { 0.0 } else { values[i - 1] };
                let right = if i == last { 0.0 } else { values[i + 1] };
                upper >= top || (upper >= 0.5 * top && upper >= left.max(right))
            }));
            for (i, p) in shape.iter().enumerate() {
                if matters[i.saturating_sub(1)] || matters[i] || matters[(i + 1).min(last)] {
                    values[i] = exact(p)?;
                }
            }
        }
        let (mut best_i, mut best) = (0, *values.first()?);
        for (i, &v) in values.iter().enumerate() {
            if v > best {
                (best_i, best) = (i, v);
            }
        }
        let mut best_s = shape[best_i].s;
        let last = values.len() - 1;
        slopes.clear();
        slopes.resize(values.len(), None);
        let mut slope = |i: usize| -> Option<f64> {
            if slopes[i].is_none() {
                let p = &shape[i];
                slopes[i] = Some(stress_and_slope(model, force, p.psi, moment(p))?.1);
            }
            slopes[i]
        };
        // The interval whose interpolant peaks highest inside: `(left point, value)`.
        let mut interior: Option<(usize, f64)> = None;
        for i in 0..=last {
            let left = if i == 0 { values[i] } else { values[i - 1] };
            let right = if i == last { values[i] } else { values[i + 1] };
            // Not a local maximum of the samples, a plateau (within round-off), or far
            // below the largest sample: no peak between its neighbours can matter.
            let rise = values[i] - left.max(right);
            let plateau = values[i] - left.min(right) <= 1e-12 * best;
            if rise < 0.0 || plateau || values[i] < 0.5 * best {
                continue;
            }
            for j in [i.wrapping_sub(1), i] {
                if j >= last {
                    continue;
                }
                let h = shape[j + 1].s - shape[j].s;
                let (d0, d1) = (slope(j)? * h, slope(j + 1)? * h);
                if let Some((_, v)) = hermite_peak(values[j], values[j + 1], d0, d1) {
                    // A gain within round-off of the samples (a constant stress, as under a
                    // pure moment) is no peak.
                    if v > best * (1.0 + 1e-12) && interior.is_none_or(|(_, b)| v > b) {
                        interior = Some((j, v));
                    }
                }
            }
        }
        if let Some((i, _)) = interior {
            if let Some((s, v)) =
                self.peak_on_beam(load, &shape[i], moment(&shape[i]), &shape[i + 1])
            {
                if v > best {
                    (best_s, best) = (s, v);
                }
            }
        }
        Some(Stress {
            max: best,
            at: best_s,
        })
    }

    /// The stress peak between the shape points `left` (moment `m_left`) and `right`, found
    /// on the beam by short shots from `left`: `(s, sigma)`.
    fn peak_on_beam(
        &self,
        load: Load,
        left: &ShapePoint,
        m_left: f64,
        right: &ShapePoint,
    ) -> Option<(f64, f64)> {
        let model = &self.model;
        let force = TipForce {
            alpha_x: load.alpha_x,
            alpha_y: load.alpha_y,
        };
        let cancel = CancelToken::never();
        let mut meter = Meter::new(self.budget.rk_steps, model, cancel);
        let settings = self.settings(load);
        let mut at = |s: f64| -> Option<(f64, f64)> {
            if s <= left.s {
                return stress_and_slope(model, force, left.psi, m_left);
            }
            let segment = Segment {
                s_start: left.s,
                s_end: s,
                psi: left.psi,
                moment: m_left,
                origin: (left.x, left.y),
            };
            let shot = shoot::<8>(model, force, segment, settings, None, &mut meter).ok()?;
            stress_and_slope(model, force, shot.end[0], shot.end[1])
        };
        let (mut lo, mut hi) = (left.s, right.s);
        let (_, mut d_lo) = at(lo)?;
        let (_, mut d_hi) = at(hi)?;
        if !(d_lo > 0.0 && d_hi < 0.0) {
            return None;
        }
        // Regula falsi on the slope, Illinois-safeguarded (halving the weight of a side
        // kept twice), with a bisection whenever the secant lands at the ends.
        let mut side = 0i8;
        let mut best = None;
        let mut last = f64::NAN;
        for _ in 0..PEAK_SHOTS {
            let mut s = (lo * d_hi - hi * d_lo) / (d_hi - d_lo);
            if !(s > lo && s < hi) {
                s = 0.5 * (lo + hi);
            }
            if (s - last).abs() <= PEAK_TOL {
                break;
            }
            last = s;
            let (v, d) = at(s)?;
            best = Some((s, v));
            if d > 0.0 {
                lo = s;
                d_lo = d;
                if side == 1 {
                    d_hi *= 0.5;
                }
                side = 1;
            } else {
                hi = s;
                d_hi = d;
                if side == -1 {
                    d_lo *= 0.5;
                }
                side = -1;
            }
            if hi - lo <= PEAK_TOL || d == 0.0 {
                break;
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::{Effects, Resolution, ShapePoint, TipPose};
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        /// Sparing the far points their sine and cosine changes nothing, bit for bit, on
        /// solved shapes of the elastica, of a stubby shearing, stretching beam with and
        /// without Poisson's shrink, and of a slender one with it, at coarse and fine
        /// samplings.
        #[test]
        fn pruning_the_far_points_changes_nothing(
            ax in -8.0..8.0f64,
            ay in -8.0..8.0f64,
            beta in -3.0..3.0f64,
            which in 0usize..4,
            points in 3usize..60,
        ) {
            let effects = |poisson| Effects {
                shear: true,
                extension: true,
                poisson,
                plane_strain: false,
            };
            let model = match which {
                0 => BeamModel::elastica(),
                1 => BeamModel::new(5.0, 0.3, None, effects(false)).unwrap(),
                2 => BeamModel::new(5.0, 0.45, None, effects(true)).unwrap(),
                _ => BeamModel::new(100.0, 0.3, None, effects(true)).unwrap(),
            };
            let resolution = Resolution {
                tol: 1e-8,
                shape_points: points,
            };
            let solver = BeamSolver::new(model, resolution).unwrap();
            let load = Load::new(ax, ay, beta);
            if let Ok(sol) = solver.solve(load) {
                let mut scratch = StressScratch::default();
                let pruned = solver.max_stress_pruned(load, sol.tip, &sol.shape, true, &mut scratch);
                let exact = solver.max_stress_pruned(load, sol.tip, &sol.shape, false, &mut scratch);
                prop_assert!(exact.is_some());
                prop_assert_eq!(pruned, exact);
            }
        }

        /// The same on any centre line (the bounds hold at any angle), of a beam as thick as
        /// it is long and of rubber's Poisson's ratio, at forces up to 94 % of the law's
        /// necking limit, where the shrink multiplies a section's bending stress by a factor from
        /// about 0.7 to 2.3: the shrink's bounds decide which points are read.
        #[test]
        fn pruning_changes_nothing_on_any_centre_line_of_a_shrinking_beam(
            ax in -2.4..2.4f64,
            ay in -2.4..2.4f64,
            beta in -3.0..3.0f64,
            tip in (0.0..1.0f64, -1.0..1.0f64),
            line in proptest::collection::vec((-3.0..3.0f64, -1.0..1.0f64, -1.0..1.0f64), 3..80),
        ) {
            let effects = Effects {
                shear: true,
                extension: true,
                poisson: true,
                plane_strain: false,
            };
            let model = BeamModel::new(1.0, 0.49, None, effects).unwrap();
            let solver = BeamSolver::new(model, Resolution::default()).unwrap();
            let load = Load::new(ax, ay, beta);
            let last = (line.len() - 1) as f64;
            let shape: Vec<ShapePoint> = line
                .iter()
                .enumerate()
                .map(|(i, &(psi, x, y))| ShapePoint { s: i as f64 / last, x, y, psi })
                .collect();
            let tip = TipPose { a: tip.0, b: tip.1, phi: 0.0 };
            let mut scratch = StressScratch::default();
            let pruned = solver.max_stress_pruned(load, tip, &shape, true, &mut scratch);
            let exact = solver.max_stress_pruned(load, tip, &shape, false, &mut scratch);
            prop_assert!(exact.is_some());
            prop_assert_eq!(pruned, exact);
        }
    }
}
