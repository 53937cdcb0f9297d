//! How a solved case of a mechanism moves with its flexure models' cells (a PRB matrix's,
//! DESIGN §3, in every flexure at once): the fit's exact Jacobian for a mechanism, by the
//! implicit function theorem through the whole mechanism's equilibrium.
//!
//! At a solved case the system `R(x, c) = 0` (every flexure's joint and internal rows, the
//! stage's balance) holds; a cell `c` moves the unknowns by `dx/dc = -J^-1 dR/dc`, with `J`
//! the system's Jacobian (the one Newton uses) and `dR/dc` the flexures' own partial
//! derivatives at fixed unknowns ([`FlexureModel::cell_derivatives`]) placed in their rows.
//! A loaded stage coordinate is an unknown; a prescribed one's reaction is the flexures'
//! load on the stage, a function of the unknowns (and of the tip moments, which are
//! unknowns themselves).

use crate::linalg::solve_many;

use super::geometry::Joint;
use super::solve::{FlexureModel, MechSolver};
use super::MechCase;

/// The derivatives of one case's stage pose and stage load with respect to the cells: 3
/// rows (`dx, dy, dphi`; `alpha_x, alpha_y, beta`) of `cells` columns each, row-major. A
/// prescribed coordinate's pose and a loaded one's load are given, so their rows are 0.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseSensitivity {
    /// `d stage / d cells`.
    pub stage: Vec<f64>,
    /// `d stage_load / d cells`.
    pub stage_load: Vec<f64>,
}

impl<M: FlexureModel> MechSolver<M> {
    /// The sensitivity of `case` (solved by this solver: it carries its state) to the
    /// `cells` cells of its flexure models; `None` for a case without a state, a model
    /// without cells (the beam), or a singular Jacobian.
    pub fn case_sensitivity(&self, case: &MechCase, cells: usize) -> Option<CaseSensitivity> {
        let state = case.state.as_ref()?;
        let (x, at) = (&state.unknowns, &state.at);
        let n = x.len();
        let sys = self.system(at, x).ok()?;
        let (mut jac, load_jac) = self.jacobian_and_load(at, x, &sys);
        // dR/dc (n rows of `cells`), and the load's own partials at fixed unknowns.
        let mut rhs = vec![0.0; n * cells];
        let mut load_partial = vec![0.0; 3 * cells];
        let mut own = Vec::new();
        let add = |to: &mut [f64], from: &[f64], scale: f64| {
            for (t, f) in to.iter_mut().zip(from) {
                *t += scale * f;
            }
        };
        for (i, f) in self.geometry.frames.iter().enumerate() {
            let (w, _) = self.own_wrench(i, x);
            let o = self.offsets[i];
            let k = self.models[i].internal();
            if !self.models[i].cell_derivatives(w, &x[o + 3..o + 3 + k], &mut own) {
                return None;
            }
            if own.len() != (4 + k) * cells {
                return None;
            }
            let row = |r: usize| &own[r * cells..(r + 1) * cells];
            // The joint rows read the tip's position, then its angle (clamped) or the tip
            // moment; the internal rows are the model's own.
            let third = if f.joint == Joint::Clamped { 2 } else { 3 };
            for (r, from) in [0, 1, third].into_iter().enumerate() {
                add(
                    &mut rhs[(o + r) * cells..(o + r + 1) * cells],
                    row(from),
                    1.0,
                );
            }
            for r in 0..k {
                let at_row = (o + 3 + r) * cells;
                add(&mut rhs[at_row..at_row + cells], row(4 + r), 1.0);
            }
            add(
                &mut load_partial[2 * cells..],
                row(3),
                f.moment_to_global(1.0),
            );
        }
        // The loaded coordinates' balance rows (`load - given`), in order after the
        // flexures' rows, as their unknowns follow the flexures'.
        let mut pose_col = [None; 3];
        let mut next = self.flexure_unknowns;
        for (c, coordinate) in at.iter().enumerate() {
            if !coordinate.is_prescribed() {
                pose_col[c] = Some(next);
                let to = next * cells;
                add(
                    &mut rhs[to..to + cells],
                    &load_partial[c * cells..(c + 1) * cells],
                    1.0,
                );
                next += 1;
            }
        }
        rhs.iter_mut().for_each(|v| *v = -*v);
        if !solve_many(&mut jac, &mut rhs, n, cells) {
            return None;
        }
        let dx = rhs;
        let mut out = CaseSensitivity {
            stage: vec![0.0; 3 * cells],
            stage_load: vec![0.0; 3 * cells],
        };
        for c in 0..3 {
            let to = c * cells..(c + 1) * cells;
            match pose_col[c] {
                Some(col) => out.stage[to].copy_from_slice(&dx[col * cells..(col + 1) * cells]),
                None => {
                    let load = &mut out.stage_load[to];
                    load.copy_from_slice(&load_partial[c * cells..(c + 1) * cells]);
                    for (j, &d) in load_jac[c * n..(c + 1) * n].iter().enumerate() {
                        if d != 0.0 {
                            add(load, &dx[j * cells..(j + 1) * cells], d);
                        }
                    }
                }
            }
        }
        Some(out)
    }
}
