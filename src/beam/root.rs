//! The beam shot from its clamp with its tip force and root moment given: an initial-value
//! problem, for solvers that take the root moment as an unknown (the mechanism's Newton
//! iteration, `crate::mech::exact`).
//!
//! A loaded beam is a boundary-value problem (the tip moment is given, the root moment is
//! not), solved by shooting in [`BeamSolver::solve`]; with the root moment given instead
//! there is nothing to solve: one integration gives the tip, the tip moment that holds it,
//! and from the variational equations their exact derivatives with respect to the force and
//! the root moment (the tip's compliance). The map has no folds, so a beam held by a
//! mechanism past its own load-controlled limit point is as regular as any other.

use super::shoot::ShotSettings;
use super::shoot::{Meter, Samples, ShotFailure, TipForce};
use super::shot::{root_shot, root_shot_pair};
use super::{BeamSolver, Load, ShapePoint, SolveError, TipPose};
use crate::cancel::CancelToken;

/// The beam shot from its clamp under a tip force and a root moment ([`BeamSolver::shoot_root`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RootShot {
    /// The tip pose.
    pub tip: TipPose,
    /// The bending moment at the tip, `beta = M(L) L / (E I0)`: the tip moment that holds
    /// this shape under the force.
    pub tip_moment: f64,
    /// `d(a, b, phi, beta) / d(alpha_x, alpha_y, m0)`, row-major (4 rows, 3 columns), from the
    /// variational equations integrated with the shot.
    pub jacobian: [[f64; 3]; 4],
}

impl RootShot {
    /// The shot's tip state with its sensitivities, in the layout of `shoot::State<16>`.
    fn from_state(u: [f64; 16]) -> RootShot {
        // Slots: psi, M, x, y; then d/dM0 (4..8), d/dalpha_x (8..12), d/dalpha_y (12..16).
        let row = |k: usize| [u[8 + k], u[12 + k], u[4 + k]];
        RootShot {
            tip: tip_of(u).0,
            tip_moment: u[1],
            jacobian: [row(2), row(3), row(0), row(1)],
        }
    }

    /// `dM(L)/dM(0)`, positive where the beam under its tip wrench alone (a given load) is
    /// stable (the single beam's test).
    pub fn stability(&self) -> f64 {
        self.jacobian[3][2]
    }
}

impl BeamSolver {
    /// The beam integrated from its clamp with the tip force `(alpha_x, alpha_y)` and the
    /// root moment `m0` (units of this beam): an initial-value problem, one integration, no
    /// Newton iteration and no fold. A mechanism that takes the root moment as its unknown
    /// instead of the tip moment solves its flexures this way (`crate::mech::exact`). One
    /// shot over the whole beam: perturbations grow like `exp(sqrt(|alpha|))`, so forces
    /// past a few hundred lose digits (the loaded solvers split the beam instead).
    pub fn shoot_root(&self, alpha_x: f64, alpha_y: f64, m0: f64) -> Result<RootShot, SolveError> {
        self.shoot_root_sampled(alpha_x, alpha_y, m0, None)
    }

    /// [`BeamSolver::shoot_root`], also sampling the centre line it shoots into `shape` (as
    /// [`BeamSolver::root_shape`] does, from the same integration).
    pub fn shoot_root_sampled(
        &self,
        alpha_x: f64,
        alpha_y: f64,
        m0: f64,
        shape: Option<&mut Vec<ShapePoint>>,
    ) -> Result<RootShot, SolveError> {
        self.root_state::<16>([alpha_x, alpha_y, m0], shape)
            .map(RootShot::from_state)
    }

    /// [`BeamSolver::shoot_root_sampled`] without the variational equations: the tip and the
    /// tip moment alone, for a third of the arithmetic (a mechanism's Newton checks its last
    /// iterate this way). The step sizes follow the state's own error alone, so the tip
    /// agrees with the full shot's to the tolerance, not to the last digit.
    pub fn shoot_root_tip(
        &self,
        alpha_x: f64,
        alpha_y: f64,
        m0: f64,
        shape: Option<&mut Vec<ShapePoint>>,
    ) -> Result<(TipPose, f64), SolveError> {
        self.root_state::<4>([alpha_x, alpha_y, m0], shape)
            .map(tip_of)
    }

    /// The tip state of the shot from the clamp with `(alpha_x, alpha_y, m0)` (`N = 16`: with
    /// its sensitivities; `N = 4`: without), sampling the centre line into `shape` if given.
    fn root_state<const N: usize>(
        &self,
        w: [f64; 3],
        shape: Option<&mut Vec<ShapePoint>>,
    ) -> Result<[f64; N], SolveError> {
        let (load, force, settings) = self.root_setup(w)?;
        let cancel = CancelToken::never();
        let mut meter = Meter::new(self.budget.rk_steps, &self.model, cancel);
        let samples = self.samples(shape);
        let (u, _) = root_shot::<N>(&self.model, force, w[2], settings, samples, &mut meter)
            .map_err(|e| shot_error(e, load, &meter))?;
        Ok(u)
    }

    /// A shot from the clamp's load (checked finite), force and settings.
    fn root_setup(&self, w: [f64; 3]) -> Result<(Load, TipForce, ShotSettings), SolveError> {
        let load = Load::new(w[0], w[1], w[2]);
        if !load.is_finite() {
            return Err(SolveError::NonFiniteLoad(load));
        }
        let mut settings = self.settings(load);
        settings.moment_scale = load.magnitude();
        let force = TipForce {
            alpha_x: w[0],
            alpha_y: w[1],
        };
        Ok((load, force, settings))
    }

    /// The shape samples of a shot into `shape`, if given (cleared first).
    fn samples<'s>(&self, shape: Option<&'s mut Vec<ShapePoint>>) -> Option<Samples<'s>> {
        shape.map(|points| {
            points.clear();
            points.reserve(self.resolution.shape_points);
            Samples {
                points,
                count: self.resolution.shape_points,
                sensitivities: None,
            }
        })
    }

    /// The centre line of the beam [`BeamSolver::shoot_root`] shoots: the resolution's
    /// `shape_points` points evenly spaced along it, root and tip included (units of this
    /// beam, its clamp at the origin along +x). For drawing a flexure whose tip force and
    /// root moment a mechanism solved (the tip wrench's `beta + alpha_y a - alpha_x b` is the
    /// root moment).
    pub fn root_shape(
        &self,
        alpha_x: f64,
        alpha_y: f64,
        m0: f64,
    ) -> Result<Vec<ShapePoint>, SolveError> {
        let load = Load::new(alpha_x, alpha_y, m0);
        if !load.is_finite() {
            return Err(SolveError::NonFiniteLoad(load));
        }
        let cancel = CancelToken::never();
        let mut meter = Meter::new(self.budget.rk_steps, &self.model, cancel);
        let mut settings = self.settings(load);
        settings.moment_scale = load.magnitude();
        let mut points = Vec::with_capacity(self.resolution.shape_points);
        let samples = Samples {
            points: &mut points,
            count: self.resolution.shape_points,
            sensitivities: None,
        };
        let force = TipForce { alpha_x, alpha_y };
        root_shot::<8>(&self.model, force, m0, settings, Some(samples), &mut meter)
            .map_err(|e| shot_error(e, load, &meter))?;
        Ok(points)
    }
}

/// The tip pose and tip moment of a shot's end state (`psi, M, x, y` first).
fn tip_of<const N: usize>(u: [f64; N]) -> (TipPose, f64) {
    let tip = TipPose {
        a: u[2],
        b: u[3],
        phi: u[0],
    };
    (tip, u[1])
}

/// One beam of [`shoot_root_pair`]: its solver, its `(alpha_x, alpha_y, m0)`, and where to
/// sample its centre line, if anywhere.
pub type PairShot<'a, 's> = (&'a BeamSolver, [f64; 3], Option<&'s mut Vec<ShapePoint>>);

/// Two beams shot from their clamps, each with its `(alpha_x, alpha_y, m0)`: each result is
/// exactly [`BeamSolver::shoot_root_sampled`]'s for that beam alone, the two integrated side
/// by side for about two thirds of the time (the beams of a mechanism's flexures).
pub fn shoot_root_pair(shots: [PairShot<'_, '_>; 2]) -> [Result<RootShot, SolveError>; 2] {
    root_state_pair::<16>(shots).map(|r| r.map(RootShot::from_state))
}

/// [`shoot_root_pair`] without the variational equations: each result is exactly
/// [`BeamSolver::shoot_root_tip`]'s for that beam alone.
pub fn shoot_root_tip_pair(
    shots: [PairShot<'_, '_>; 2],
) -> [Result<(TipPose, f64), SolveError>; 2] {
    root_state_pair::<4>(shots).map(|r| r.map(tip_of))
}

/// [`BeamSolver::root_state`] of two beams, integrated side by side.
fn root_state_pair<const N: usize>(
    shots: [PairShot<'_, '_>; 2],
) -> [Result<[f64; N], SolveError>; 2] {
    let [(sa, wa, sha), (sb, wb, shb)] = shots;
    let (ra, rb) = (sa.root_setup(wa), sb.root_setup(wb));
    let ((la, fa, ta), (lb, fb, tb)) = match (ra, rb) {
        (Ok(a), Ok(b)) => (a, b),
        (ra, rb) => {
            // A load that is not finite: the other beam is shot alone.
            let alone = |r: Result<_, SolveError>, s: &BeamSolver, w, sh| {
                r.and_then(|_| s.root_state::<N>(w, sh))
            };
            return [alone(ra, sa, wa, sha), alone(rb, sb, wb, shb)];
        }
    };
    let cancel = CancelToken::never();
    let mut meter_a = Meter::new(sa.budget.rk_steps, &sa.model, cancel);
    let mut meter_b = Meter::new(sb.budget.rk_steps, &sb.model, cancel);
    let [a, b] = root_shot_pair::<N>(
        [
            (&sa.model, fa, wa[2], ta, sa.samples(sha)),
            (&sb.model, fb, wb[2], tb, sb.samples(shb)),
        ],
        [&mut meter_a, &mut meter_b],
    );
    [
        a.map(|(u, _)| u).map_err(|e| shot_error(e, la, &meter_a)),
        b.map(|(u, _)| u).map_err(|e| shot_error(e, lb, &meter_b)),
    ]
}

/// A failed shot from the clamp as the solver reports it.
fn shot_error(e: ShotFailure, load: Load, meter: &Meter<'_>) -> SolveError {
    let failure = |reason: &str| SolveError::NoConvergence {
        load,
        fraction: 0.0,
        reason: reason.to_string(),
    };
    match e {
        ShotFailure::Material(limit) => SolveError::MaterialLimit {
            load,
            fraction: 0.0,
            reason: limit.to_string(),
        },
        ShotFailure::StepBudget => failure("the integrator's step size collapsed"),
        ShotFailure::NonFinite => failure("the shot overflowed"),
        ShotFailure::OutOfEffort => SolveError::EffortExceeded {
            load,
            fraction: 0.0,
            steps: 0,
            shots: 0,
            rk_steps: meter.tries,
        },
        ShotFailure::Cancelled => SolveError::Cancelled {
            load,
            fraction: 0.0,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::{BeamModel, Effects, EffortBudget, Resolution};

    fn stubby_rubber() -> BeamSolver {
        let effects = Effects {
            shear: true,
            extension: true,
            poisson: true,
            plane_strain: false,
        };
        let model = BeamModel::new(4.0, 0.49, None, effects).unwrap();
        BeamSolver::new(model, Resolution::with_tol(1e-10)).unwrap()
    }

    /// The variational equations against central differences of the shot itself, with every
    /// effect on (the force terms are the new part). Central differences with h = 1e-5 err
    /// by O(h^2) ~ 1e-10 times the third derivative, plus 1e-10 / h ~ 1e-5 from the shots'
    /// own tolerance; the sensitivities are integrated to a relative 1e-7. So 1e-4 relative.
    #[test]
    fn root_shot_jacobian_matches_differences() {
        for solver in [
            stubby_rubber(),
            BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(1e-10)).unwrap(),
        ] {
            let x = [-1.3, 2.1, 0.7];
            let shot = solver.shoot_root(x[0], x[1], x[2]).unwrap();
            let out = |s: &RootShot| [s.tip.a, s.tip.b, s.tip.phi, s.tip_moment];
            for col in 0..3 {
                let h = 1e-5;
                let mut xp = x;
                let mut xm = x;
                xp[col] += h;
                xm[col] -= h;
                let p = out(&solver.shoot_root(xp[0], xp[1], xp[2]).unwrap());
                let m = out(&solver.shoot_root(xm[0], xm[1], xm[2]).unwrap());
                for row in 0..4 {
                    let fd = (p[row] - m[row]) / (2.0 * h);
                    let an = shot.jacobian[row][col];
                    assert!(
                        (fd - an).abs() <= 1e-4 * (1.0 + fd.abs()),
                        "row {row} col {col}: analytic {an}, differences {fd}"
                    );
                }
            }
        }
    }

    /// The shot by values (no variational equations) is the full shot's tip and tip moment,
    /// to the shots' tolerance (1e-10: both about that far from the beam; 1e-8 as above),
    /// through both integrators (Taylor series for the elastica, Dormand-Prince with every
    /// effect), and samples the same centre line.
    #[test]
    fn a_shot_by_values_is_the_full_shot() {
        for solver in [
            stubby_rubber(),
            BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(1e-10)).unwrap(),
        ] {
            for (ax, ay, m0) in [(-1.3, 2.1, 0.7), (0.0, 0.0, 1.5), (2.0, -0.5, -0.4)] {
                let full = solver.shoot_root(ax, ay, m0).unwrap();
                let mut shape = Vec::new();
                let (tip, moment) = solver.shoot_root_tip(ax, ay, m0, Some(&mut shape)).unwrap();
                assert!(tip.max_diff(&full.tip) < 1e-8, "{tip:?} vs {:?}", full.tip);
                assert!((moment - full.tip_moment).abs() < 1e-8 * (1.0 + moment.abs()));
                let drawn = solver.root_shape(ax, ay, m0).unwrap();
                assert_eq!(shape.len(), drawn.len());
                for (p, q) in shape.iter().zip(&drawn) {
                    let d = (p.x - q.x)
                        .abs()
                        .max((p.y - q.y).abs())
                        .max((p.psi - q.psi).abs());
                    assert!(p.s == q.s && d < 1e-8, "at s = {}: {p:?} vs {q:?}", p.s);
                }
            }
        }
    }

    /// The root shot's tip moment, given as a load, reproduces its tip (the loaded solver
    /// follows the path from rest; this load is below any limit point).
    #[test]
    fn root_shot_is_the_loaded_beam() {
        let solver = stubby_rubber();
        let shot = solver.shoot_root(0.8, 1.5, 1.2).unwrap();
        let loaded = solver.solve(Load::new(0.8, 1.5, shot.tip_moment)).unwrap();
        assert!(
            shot.tip.max_diff(&loaded.tip) < 1e-8,
            "{:?} vs {:?}",
            shot.tip,
            loaded.tip
        );
        assert!(shot.stability() > 0.0);
    }

    /// The drawn centre line is the shot's: it starts at the clamp, ends at the shot's tip,
    /// and its samples are evenly spaced along the beam.
    #[test]
    fn root_shape_ends_at_the_shot_tip() {
        let solver = stubby_rubber();
        let (ax, ay, m0) = (-0.6, 2.4, 1.1);
        let shot = solver.shoot_root(ax, ay, m0).unwrap();
        let shape = solver.root_shape(ax, ay, m0).unwrap();
        assert_eq!(shape.len(), solver.resolution.shape_points);
        let (first, last) = (shape[0], shape[shape.len() - 1]);
        assert_eq!((first.x, first.y, first.psi), (0.0, 0.0, 0.0));
        let tip = TipPose {
            a: last.x,
            b: last.y,
            phi: last.psi,
        };
        assert!(tip.max_diff(&shot.tip) < 1e-8, "{tip:?} vs {:?}", shot.tip);
        for (k, p) in shape.iter().enumerate() {
            let s = k as f64 / (shape.len() - 1) as f64;
            assert!((p.s - s).abs() < 1e-12);
        }
    }

    /// The shape a sampled root shot records (what a mechanism's exact flexure takes its
    /// stress from) is the drawn one, sample for sample: both integrate the same beam to the
    /// same tolerance, so they agree to the shot's error (1e-8 of L, as the tip above), and
    /// the sampled shot's tip and Jacobian are the unsampled one's exactly (sampling only
    /// interpolates between the steps).
    #[test]
    fn a_sampled_root_shot_records_the_drawn_shape() {
        let solver = stubby_rubber();
        for (ax, ay, m0) in [(-0.6, 2.4, 1.1), (3.0, -1.0, 0.2), (0.0, 0.0, 1.5)] {
            let mut shape = vec![ShapePoint {
                s: 9.0,
                x: 9.0,
                y: 9.0,
                psi: 9.0,
            }];
            let sampled = solver
                .shoot_root_sampled(ax, ay, m0, Some(&mut shape))
                .unwrap();
            assert_eq!(sampled, solver.shoot_root(ax, ay, m0).unwrap());
            let drawn = solver.root_shape(ax, ay, m0).unwrap();
            assert_eq!(shape.len(), drawn.len(), "the stale point is cleared");
            for (p, q) in shape.iter().zip(&drawn) {
                assert_eq!(p.s, q.s);
                let d = (p.x - q.x)
                    .abs()
                    .max((p.y - q.y).abs())
                    .max((p.psi - q.psi).abs());
                assert!(d < 1e-8, "at s = {}: {p:?} vs {q:?}", p.s);
            }
        }
    }

    /// Two beams shot side by side give each exactly what it gives alone, bit for bit (their
    /// `Debug` text, which writes every float exactly): with and without the variational
    /// equations, with and without the shape samples, for beams of other effects and
    /// slenderness side by side, a plain elastica (its Taylor shot, taken alone) beside a
    /// Reissner beam, and shots that fail beside shots that do not: a section that necks at
    /// once or part-way along, and a beam whose effort budget runs out (each lane has its own
    /// meter). Where the processor has AVX2 and FMA, the pair runs in that build and the
    /// single shots in the baseline one, so this also checks that the two builds agree.
    #[test]
    fn a_pair_of_shots_is_each_shot_alone() {
        let steel = BeamSolver::new(
            BeamModel::new(100.0, 0.3, None, Effects::ALL)
                .unwrap()
                .with_width_ratio(20.0),
            Resolution::with_tol(1e-9),
        )
        .unwrap();
        let rubber = stubby_rubber();
        // Stretching without Poisson's shrink: its series are of another kind than the
        // rubber's, so the two are not built in one register's lanes.
        let stretchy = BeamSolver::new(
            BeamModel::new(
                10.0,
                0.3,
                None,
                Effects {
                    poisson: false,
                    ..Effects::ALL
                },
            )
            .unwrap(),
            Resolution::with_tol(1e-9),
        )
        .unwrap();
        let elastica = BeamSolver::new(BeamModel::elastica(), Resolution::with_tol(1e-9)).unwrap();
        let starved = steel.with_budget(EffortBudget {
            rk_steps: 5,
            ..EffortBudget::default()
        });
        // The rubber's section necks past an axial force of about 58 (E I0 / L^2): at once
        // under a pull of 200, and part-way along where a pull of 50 with a side force of 30
        // turns into the beam's axis.
        let neck_at_once = [200.0, 0.0, 0.0];
        let neck_part_way = [50.0, 30.0, 8.0];
        let fails = |s: &BeamSolver, w: [f64; 3]| s.shoot_root(w[0], w[1], w[2]).is_err();
        assert!(fails(&rubber, neck_at_once));
        assert!(
            fails(&rubber, neck_part_way),
            "the part-way case must fail to test it"
        );
        assert!(
            fails(&starved, [0.5, 1.0, 0.4]),
            "the starved beam must run out"
        );
        type Beam<'a> = (&'a BeamSolver, [f64; 3]);
        let cases: [(Beam<'_>, Beam<'_>); 9] = [
            ((&steel, [-0.044, 1.2, 0.6]), (&steel, [0.044, 1.2, 0.61])),
            ((&stretchy, [0.8, 1.5, 0.3]), (&rubber, [-0.6, 2.4, 1.1])),
            ((&steel, [10.0, 2.4, -0.3]), (&rubber, [-0.6, 2.4, 1.1])),
            ((&elastica, [-1.3, 2.1, 0.7]), (&rubber, [3.0, -1.0, 0.2])),
            ((&rubber, neck_at_once), (&steel, [0.5, 1.0, 0.4])),
            ((&steel, [0.5, 1.0, 0.4]), (&rubber, neck_part_way)),
            ((&rubber, neck_part_way), (&rubber, neck_at_once)),
            ((&starved, [0.5, 1.0, 0.4]), (&steel, [0.5, 1.0, 0.4])),
            ((&steel, [-0.6, 2.4, 1.1]), (&starved, [-0.6, 2.4, 1.1])),
        ];
        let text = |r: &dyn std::fmt::Debug| format!("{r:?}");
        for ((sa, wa), (sb, wb)) in cases {
            let context = format!("{wa:?} beside {wb:?}");
            // With the variational equations: unsampled, then sampled.
            let alone = |s: &BeamSolver, w: [f64; 3]| s.shoot_root(w[0], w[1], w[2]);
            let [pa, pb] = shoot_root_pair([(sa, wa, None), (sb, wb, None)]);
            assert_eq!(text(&pa), text(&alone(sa, wa)), "{context}");
            assert_eq!(text(&pb), text(&alone(sb, wb)), "{context}");
            let sampled_alone = |s: &BeamSolver, w: [f64; 3]| {
                let mut shape = Vec::new();
                let shot = s.shoot_root_sampled(w[0], w[1], w[2], Some(&mut shape));
                (text(&shot), text(&shape))
            };
            let (mut shape_a, mut shape_b) = (Vec::new(), Vec::new());
            let [pa, pb] =
                shoot_root_pair([(sa, wa, Some(&mut shape_a)), (sb, wb, Some(&mut shape_b))]);
            assert_eq!(
                (text(&pa), text(&shape_a)),
                sampled_alone(sa, wa),
                "{context}"
            );
            assert_eq!(
                (text(&pb), text(&shape_b)),
                sampled_alone(sb, wb),
                "{context}"
            );
            // By values, sampled.
            let tip_alone = |s: &BeamSolver, w: [f64; 3]| {
                let mut shape = Vec::new();
                let tip = s.shoot_root_tip(w[0], w[1], w[2], Some(&mut shape));
                (text(&tip), text(&shape))
            };
            let (mut shape_a, mut shape_b) = (Vec::new(), Vec::new());
            let [ta, tb] =
                shoot_root_tip_pair([(sa, wa, Some(&mut shape_a)), (sb, wb, Some(&mut shape_b))]);
            assert_eq!((text(&ta), text(&shape_a)), tip_alone(sa, wa), "{context}");
            assert_eq!((text(&tb), text(&shape_b)), tip_alone(sb, wb), "{context}");
        }
    }
}
