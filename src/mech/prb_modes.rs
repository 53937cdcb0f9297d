//! The PRB mechanism's natural frequencies (DESIGN §10): the closed chain — every flexure's
//! PRB chain, the couplers and the stage — linearised about one of its equilibria, in flexure
//! 1's units (`Omega = omega sqrt(rho A0 L^4 / (E I0))` of flexure 1).
//!
//! The mechanism solver's equations are the dynamics' too: each chain's joint rows
//! `K q - J^T w` are the generalised forces the chain's inertia balances (`= -M q''`), the
//! stage's balance rows are its loaded coordinates' (`= -M_stage s''`), and the tip
//! compatibility rows are constraints whose multipliers are the tip wrenches. So the
//! linearised free vibration is `A v = omega^2 B v` with `A` the solver's own Jacobian at the
//! equilibrium (springs, constraints, and the geometric stiffness of the wrenches and of the
//! stage's rotation) and `B` holding each chain's mass matrix ([`crate::prb::PrbSolver::mass_matrix`])
//! and the stage's mass and inertia (its loaded coordinates only: a prescribed coordinate is
//! held by its guide or actuator). Couplers are massless. Each chain's equations are in its
//! own flexure's units, so its mass matrix is scaled by `(A_i L_i^4 / (E_i I_i)) / (A_1 L_1^4
//! / (E_1 I_1))` (one density for every flexure) to share flexure 1's time scale.
//!
//! The modes' shapes ([`prb_mode_shapes`], for drawing over the beam mechanism's) are the
//! null vectors of `A - omega^2 B`: each chain's joint rates moved into its joints' motion
//! ([`crate::prb::PrbSolver::joint_motion`]) and the stage's loaded coordinates' rates, in
//! the beam mechanism's form ([`super::modes::MechModeShape`]).

use crate::linalg::frequencies;
use crate::prb::{ModesError, PrbMatrix, TipBody};
use crate::scene::{Coordinate, Mechanism};

use nalgebra::DMatrix;

use super::modes::{normalise, station_to_global, MechModeShape};
use super::prb::{solver, ChainFlexure};
use super::solve::MechSolver;
use super::SolvedState;

/// The unloaded mechanism's state: the drive's prescribed coordinates held at 0 (the first
/// drive's kinds; every coordinate loaded when the mechanism has no drive).
pub fn unloaded_state(mechanism: &Mechanism, matrix: &PrbMatrix) -> SolvedState {
    let held = mechanism
        .drives
        .first()
        .map_or([false; 3], super::modes::held_by);
    unloaded_state_held(mechanism, matrix, held)
}

/// The unloaded mechanism's state with the stage coordinates `held` (`[x, y, phi]`)
/// prescribed at 0 and the others loaded by nothing (a measured drive's kinds, which the
/// mechanism's own drives do not carry).
pub fn unloaded_state_held(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    held: [bool; 3],
) -> SolvedState {
    held_state(&solver(mechanism, matrix, 1e-10), held)
}

/// The unloaded state of the PRB mechanism `s` with the stage coordinates `held` fixed.
fn held_state(s: &MechSolver<ChainFlexure>, held: [bool; 3]) -> SolvedState {
    let at: [Coordinate; 3] = std::array::from_fn(|c| {
        if held[c] {
            Coordinate::Prescribed(0.0)
        } else {
            Coordinate::Loaded(0.0)
        }
    });
    SolvedState {
        unknowns: s.start(&at),
        at,
    }
}

/// [`prb_modes`] about [`unloaded_state_held`]'s state, the PRB mechanism built once (what a
/// dynamic fit asks for every trial model).
pub fn unloaded_prb_modes(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    held: [bool; 3],
    stage: TipBody,
) -> Result<Vec<f64>, ModesError> {
    let s = solver(mechanism, matrix, 1e-10);
    let state = held_state(&s, held);
    let pencil = Pencil::from_solver(s, mechanism, &state, stage)?;
    frequencies(&pencil.a, &pencil.b, pencil.n).map_err(|w2| {
        // Unloaded, a singular or unstable stiffness is no critical load: say what the
        // mechanism solver says of the pose (a self-stress, or a motion nothing holds).
        match pencil
            .solver
            .regular_unloaded(pencil.a.clone(), pencil.n, 1)
        {
            Err(e) => ModesError::Mechanism(e.to_string()),
            Ok(_) => ModesError::Unstable(w2),
        }
    })
}

/// The PRB mechanism's natural frequencies `Omega` (flexure 1's units), lowest first, at
/// `state` (a case's [`super::MechCase::state`] or [`unloaded_state`]), with `stage` the
/// stage's mass and inertia about P in flexure 1's `rho A0 L` and `rho A0 L^3`.
pub fn prb_modes(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    state: &SolvedState,
    stage: TipBody,
) -> Result<Vec<f64>, ModesError> {
    let pencil = Pencil::new(mechanism, matrix, state, stage)?;
    frequencies(&pencil.a, &pencil.b, pencil.n).map_err(ModesError::Unstable)
}

/// The PRB mechanism's first `count` modes at `state` for drawing, as the beam mechanism's
/// ([`super::modes::mech_modes`]): per mode its `Omega`, the stage's motion of `P` and, per
/// flexure, its chain's root, joints and tip ([`crate::prb::PrbSolver::joint_motion`]) with
/// their motion, in the global frame and flexure 1's units, the largest motion 1. Each mode
/// is the null vector of `A - Omega^2 B` (its smallest singular vector).
pub fn prb_mode_shapes(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    state: &SolvedState,
    stage: TipBody,
    count: usize,
) -> Result<Vec<MechModeShape>, ModesError> {
    let pencil = Pencil::new(mechanism, matrix, state, stage)?;
    let omegas = frequencies(&pencil.a, &pencil.b, pencil.n).map_err(ModesError::Unstable)?;
    let n = pencil.n;
    let a = DMatrix::from_row_slice(n, n, &pencil.a);
    let b = DMatrix::from_row_slice(n, n, &pencil.b);
    let s = &pencil.solver;
    let x = &state.unknowns;
    let mut out = Vec::new();
    for &w in omegas.iter().take(count) {
        let svd = (&a - &b * (w * w)).svd(false, true);
        let Some(v_t) = svd.v_t else { continue };
        let smallest = svd
            .singular_values
            .iter()
            .enumerate()
            .min_by(|p, q| p.1.total_cmp(q.1))
            .map_or(0, |(i, _)| i);
        let v: Vec<f64> = v_t.row(smallest).iter().copied().collect();
        let mut lines = Vec::with_capacity(s.models.len());
        for (i, (model, frame)) in s.models.iter().zip(&s.geometry.frames).enumerate() {
            let o = s.offsets[i] + 3;
            let k = model.solver.dof_count();
            let points = model
                .solver
                .joint_motion(&x[o..o + k], &v[o..o + k])
                .into_iter()
                .map(|p| station_to_global(frame, p))
                .collect();
            lines.push(points);
        }
        // The stage's loaded coordinates follow the flexures' unknowns; a prescribed one is
        // held.
        let mut motion = [0.0; 3];
        let mut next = s.flexure_unknowns;
        for (c, coordinate) in state.at.iter().enumerate() {
            if !coordinate.is_prescribed() {
                motion[c] = v[next];
                next += 1;
            }
        }
        normalise(&mut motion, &mut lines);
        out.push(MechModeShape {
            omega: w,
            stage: motion,
            flexures: lines,
        });
    }
    Ok(out)
}

/// The linearised free vibration `A v = Omega^2 B v` at one state (module docs), row-major.
struct Pencil {
    solver: MechSolver<ChainFlexure>,
    a: Vec<f64>,
    b: Vec<f64>,
    n: usize,
}

impl Pencil {
    fn new(
        mechanism: &Mechanism,
        matrix: &PrbMatrix,
        state: &SolvedState,
        stage: TipBody,
    ) -> Result<Pencil, ModesError> {
        Pencil::from_solver(solver(mechanism, matrix, 1e-10), mechanism, state, stage)
    }

    /// As [`Pencil::new`], with the PRB mechanism's solver `s` already built.
    fn from_solver(
        s: MechSolver<ChainFlexure>,
        mechanism: &Mechanism,
        state: &SolvedState,
        stage: TipBody,
    ) -> Result<Pencil, ModesError> {
        let x = &state.unknowns;
        let n = x.len();
        if n != s.flexure_unknowns + state.at.iter().filter(|c| !c.is_prescribed()).count() {
            return Err(ModesError::Coordinates {
                expected: s.flexure_unknowns,
                got: n,
            });
        }
        let sys = s
            .system(&state.at, x)
            .map_err(|_| ModesError::Unstable(f64::NAN))?;
        let a = s.jacobian(&state.at, x, &sys);
        let mut b = vec![0.0; n * n];
        let scale = |f: &crate::scene::Flexure| {
            let beam = &f.beam;
            beam.area() * beam.length.powi(4) / (beam.youngs_modulus * beam.second_moment())
        };
        let base = mechanism.flexures.first().map_or(1.0, scale);
        for (i, (model, f)) in s.models.iter().zip(&mechanism.flexures).enumerate() {
            let o = s.offsets[i] + 3;
            let k = model.solver.dof_count();
            let m = model.solver.mass_matrix(&x[o..o + k], TipBody::default());
            let c = scale(f) / base;
            for r in 0..k {
                for col in 0..k {
                    b[(o + r) * n + o + col] = c * m[r * k + col];
                }
            }
        }
        let mut next = s.flexure_unknowns;
        for (c, coordinate) in state.at.iter().enumerate() {
            if !coordinate.is_prescribed() {
                b[next * n + next] = if c < 2 { stage.mass } else { stage.inertia };
                next += 1;
            }
        }
        Ok(Pencil { solver: s, a, b, n })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Drive, Scene};

    fn parallel() -> Scene {
        Scene::from_toml_str(
            include_str!("../../assets/scenes/parallel-stage.toml"),
            "parallel-stage.toml",
        )
        .unwrap()
    }

    /// A heavy stage on the parallel flexures rings at `sqrt(k / M)` with `k` the PRB
    /// mechanism's own small-motion stiffness in y (found here by its statics, independently
    /// of the modes), the flexures' own mass a correction of order `m_flexures / M`.
    #[test]
    fn heavy_stage_rings_at_its_static_stiffness() {
        let scene = parallel();
        let mut m = scene.mechanism.clone().unwrap();
        let su = crate::prb::published::by_name("su-3r").unwrap().prb;
        // Stiffness: a tiny Fy (alpha = 1e-4 of flexure 1) and the stage's dy.
        m.drives = vec![Drive::proportional(
            [
                Coordinate::Loaded(0.0),
                Coordinate::Loaded(1e-4 * m.scale().1 / m.scale().0.powi(2)),
                Coordinate::Loaded(0.0),
            ],
            1,
        )];
        let cases = super::super::prb::solve(&m, &su, 1e-13).unwrap();
        let k = 1e-4 / cases[0][0].stage[1];
        let heavy = 1e4;
        let state = unloaded_state(&m, &su);
        let w = prb_modes(
            &m,
            &su,
            &state,
            TipBody {
                mass: heavy,
                inertia: heavy,
            },
        )
        .unwrap();
        let want = (k / heavy).sqrt();
        // Two flexures of mass 1 each move with the stage: about 1e-4 of the heavy stage,
        // half that in the frequency.
        assert!((w[0] / want - 1.0).abs() < 2e-4, "{w:?} vs {want}");
        // Near the beams' 24 (12 E I / L^3 per flexure): Su's 3R, fitted to the end-loaded
        // cantilever, is 11 % soft in the S-shaped guided bend (21.3).
        assert!((k / 24.0 - 1.0).abs() < 0.15, "{k}");
        // A light stage (twice a flexure's mass): the flexures' own mass lowers the frequency
        // below sqrt(k / M) but not below sqrt(k / (M + both flexures' mass)).
        let light = prb_modes(
            &m,
            &su,
            &state,
            TipBody {
                mass: 2.0,
                inertia: 0.2,
            },
        )
        .unwrap();
        assert!(
            light[0] < (k / 2.0).sqrt() && light[0] > (k / 4.0).sqrt(),
            "{light:?}"
        );
        // The modes of the loaded case's state agree with the unloaded ones at a tiny load.
        let loaded = cases[0][0].state.clone().unwrap();
        let w2 = prb_modes(
            &m,
            &su,
            &loaded,
            TipBody {
                mass: heavy,
                inertia: heavy,
            },
        )
        .unwrap();
        assert!((w2[0] / w[0] - 1.0).abs() < 1e-5, "{w2:?}");
    }

    /// One clamped flexure with every coordinate loaded and a massless stage is the
    /// cantilever: the mechanism's modes are the chain's own.
    #[test]
    fn one_flexure_mechanism_is_the_cantilever_chain() {
        let scene = parallel();
        let mut m = scene.mechanism.clone().unwrap();
        m.flexures.truncate(1);
        m.stage_point = m.flexures[0].tip();
        m.drives.clear();
        let su = crate::prb::published::by_name("su-3r").unwrap().prb;
        let state = unloaded_state(&m, &su);
        let body = TipBody {
            mass: 0.3,
            inertia: 0.01,
        };
        let w = prb_modes(&m, &su, &state, body).unwrap();
        let chain = crate::prb::PrbSolver::new(&su, m.flexures[0].beam.model().axial_compliance());
        let want = chain
            .modes(crate::beam::Load::new(0.0, 0.0, 0.0), &[0.0; 3], body)
            .unwrap();
        assert_eq!(w.len(), 3, "{w:?}");
        for (a, b) in w.iter().zip(&want) {
            assert!((a / b - 1.0).abs() < 1e-9, "{w:?} vs {want:?}");
        }
    }
}
