//! Where the parts of a mechanism sit in one case, for drawing: each flexure's centre line,
//! each coupler, the stage, in the global frame and units of flexure 1's `L`
//! ([`super::geometry`]).
//!
//! - The exact beam's centre line is its root shot ([`BeamSolver::root_shape`]) under the tip
//!   force it was solved with and the root moment that force and its tip moment imply,
//!   `m0 = beta + alpha_y a - alpha_x b` (DESIGN §2's `M` at `s = 0`): the shape the solver's
//!   own shot produced, whether or not the flexure would be stable under that wrench alone.
//! - A PRB chain's is its joints ([`PrbSolver::joint_positions`]) at the joint coordinates the
//!   mechanism solver found ([`MechCase::joints`]).
//! - A coupler runs from its flexure's tip to its stage end moved with the stage; the stage is
//!   drawn as its reference point `P` joined to every point where a flexure meets it.
//! - A mode shape ([`mode`], the beam mechanism's or the PRB mechanism's alike) is its
//!   equilibrium moved by a drawing scale times the mode's motion.

use crate::beam::{BeamSolver, Resolution, SolveError};
use crate::prb::{PrbMatrix, PrbSolver};
use crate::scene::Mechanism;

use super::geometry::{Frame, Geometry, Joint};
use super::modes::MechModeShape;
use super::MechCase;

/// One case of a mechanism as drawn, global frame, units of flexure 1's `L`.
#[derive(Debug, Clone, PartialEq)]
pub struct Pose {
    /// Per flexure, its centre line from the clamp to the tip.
    pub flexures: Vec<Vec<[f64; 2]>>,
    /// Every coupler: its flexure's tip, then its stage end.
    pub couplers: Vec<[[f64; 2]; 2]>,
    /// The stage's reference point `P`.
    pub stage_point: [f64; 2],
    /// Where the flexures meet the stage (a clamped or pinned tip, a coupler's stage end),
    /// in flexure order.
    pub stage: Vec<[f64; 2]>,
    /// Every flexure's clamp.
    pub roots: Vec<[f64; 2]>,
}

/// The pose whose stage sits at `stage` (`[dx, dy, dphi]`) and whose flexures' centre lines
/// are `flexures` (global).
fn assemble(geometry: &Geometry, stage: [f64; 3], flexures: Vec<Vec<[f64; 2]>>) -> Pose {
    let tip = |i: usize, f: &Frame| {
        flexures
            .get(i)
            .and_then(|line| line.last().copied())
            .unwrap_or_else(|| f.unloaded_tip())
    };
    let mut couplers = Vec::new();
    let mut attached = Vec::with_capacity(geometry.frames.len());
    for (i, f) in geometry.frames.iter().enumerate() {
        match f.joint {
            Joint::Clamped | Joint::Pinned => {
                attached.push(geometry.stage_map(stage, f.unloaded_tip()));
            }
            Joint::Link { to, .. } => {
                let end = geometry.stage_map(stage, to);
                couplers.push([tip(i, f), end]);
                attached.push(end);
            }
        }
    }
    Pose {
        flexures,
        couplers,
        stage_point: geometry.stage_point_at(stage),
        stage: attached,
        roots: geometry.frames.iter().map(|f| f.root).collect(),
    }
}

/// The unloaded mechanism: straight flexures, the stage at rest.
pub fn unloaded(mechanism: &Mechanism) -> Pose {
    let geometry = Geometry::new(mechanism);
    let flexures = geometry
        .frames
        .iter()
        .map(|f| vec![f.root, f.unloaded_tip()])
        .collect();
    assemble(&geometry, [0.0; 3], flexures)
}

/// The exact mechanism's cases (one `Vec` per drive, as [`super::exact::solve`] returns
/// them) as drawn, each flexure's beam at `resolution`.
pub fn exact(
    mechanism: &Mechanism,
    resolution: Resolution,
    cases: &[Vec<MechCase>],
) -> Result<Vec<Vec<Pose>>, SolveError> {
    let geometry = Geometry::new(mechanism);
    let solvers = mechanism
        .flexures
        .iter()
        .map(|f| BeamSolver::new(f.model(), resolution))
        .collect::<Result<Vec<_>, _>>()?;
    cases
        .iter()
        .map(|drive| {
            drive
                .iter()
                .map(|case| {
                    let mut lines = Vec::with_capacity(solvers.len());
                    for ((solver, frame), f) in
                        solvers.iter().zip(&geometry.frames).zip(&case.flexures)
                    {
                        let w = f.wrench;
                        let m0 = w.beta + w.alpha_y * f.tip.a - w.alpha_x * f.tip.b;
                        let shape = solver.root_shape(w.alpha_x, w.alpha_y, m0)?;
                        lines.push(shape.iter().map(|p| frame.to_global([p.x, p.y])).collect());
                    }
                    Ok(assemble(&geometry, case.stage, lines))
                })
                .collect()
        })
        .collect()
}

/// The PRB mechanism's cases (`matrix` in every flexure; one `Vec` per drive, as
/// [`super::prb::solve`] returns them) as drawn: each chain's root, then every segment's end.
pub fn chains(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    cases: &[Vec<MechCase>],
) -> Vec<Vec<Pose>> {
    let geometry = Geometry::new(mechanism);
    let solvers: Vec<PrbSolver> = mechanism
        .flexures
        .iter()
        .map(|f| PrbSolver::new(matrix, f.model().axial_compliance()))
        .collect();
    cases
        .iter()
        .map(|drive| {
            drive
                .iter()
                .map(|case| {
                    let lines = solvers
                        .iter()
                        .zip(&geometry.frames)
                        .zip(&case.joints)
                        .map(|((solver, frame), q)| {
                            solver
                                .joint_positions(q)
                                .into_iter()
                                .map(|p| frame.to_global(p))
                                .collect()
                        })
                        .collect();
                    assemble(&geometry, case.stage, lines)
                })
                .collect()
        })
        .collect()
}

/// A mode of the mechanism as drawn about the equilibrium its shape was found at, the stage
/// there at `at` (`[dx, dy, dphi]`; zero for the unloaded one): every flexure's stations
/// moved by `scale` times their motion, the stage by `scale` times its own (turned by
/// `scale dphi`), each coupler from its flexure's moved tip to its stage end moved with the
/// stage. `scale = 0` draws the equilibrium.
pub fn mode(mechanism: &Mechanism, at: [f64; 3], shape: &MechModeShape, scale: f64) -> Pose {
    let geometry = Geometry::new(mechanism);
    let lines = shape
        .flexures
        .iter()
        .map(|line| {
            line.iter()
                .map(|p| [p.x + scale * p.dx, p.y + scale * p.dy])
                .collect()
        })
        .collect();
    let stage = std::array::from_fn(|c| at[c] + scale * shape.stage[c]);
    assemble(&geometry, stage, lines)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::mech::{exact, prb};
    use crate::scene::Scene;

    fn slider_crank() -> Mechanism {
        let text = include_str!("../../assets/scenes/slider-crank.toml");
        Scene::from_toml_str(text, "slider-crank")
            .unwrap()
            .mechanism
            .unwrap()
    }

    /// Beam and chain end at the tips the solvers report, the coupler keeps its length, and
    /// the stage point moves with the drive.
    #[test]
    fn poses_follow_the_solved_cases() {
        let m = slider_crank();
        let geometry = Geometry::new(&m);
        let resolution = Resolution::with_tol(1e-8);
        let beam = exact::solve(&m, resolution).unwrap();
        let su =
            PrbMatrix::parse("0.10,inf,inf; 0.35,3.51,inf; 0.40,2.99,inf; 0.15,2.58,inf").unwrap();
        let chain = prb::solve(&m, &su, 1e-10).unwrap();
        let rest = unloaded(&m);
        let Joint::Link { length, .. } = geometry.frames[0].joint else {
            panic!("the slider-crank's flexure has a coupler");
        };
        for (poses, cases) in [
            (exact(&m, resolution, &beam).unwrap(), &beam),
            (chains(&m, &su, &chain), &chain),
        ] {
            for (pose, case) in poses[0].iter().zip(&cases[0]) {
                let f = &case.flexures[0];
                let want = geometry.frames[0].to_global([f.tip.a, f.tip.b]);
                let tip = *pose.flexures[0].last().unwrap();
                assert!(
                    (tip[0] - want[0]).hypot(tip[1] - want[1]) < 1e-7,
                    "{tip:?} {want:?}"
                );
                assert_eq!(pose.flexures[0][0], [0.0, 0.0]);
                let [a, b] = pose.couplers[0];
                assert!(((a[0] - b[0]).hypot(a[1] - b[1]) - length).abs() < 1e-7);
                let moved = pose.stage_point[1] - rest.stage_point[1];
                assert!((moved - case.stage[1]).abs() < 1e-12);
            }
        }
    }
}
