//! The equations' tests: the Jacobian against central differences, Newton's checks by
//! values, and the cost and accuracy of long drives.

use super::*;
use crate::beam::{Effects, Resolution};
use crate::mech::{exact, prb, MechCase};
use crate::prb::PrbMatrix;
use crate::scene::{Attach, BeamSpec, DrivePath, EffectsChoice, Flexure, Mechanism};
use Coordinate::{Loaded, Prescribed};

/// Three flexures of different sizes, directions and attachments, every effect on.
fn mixed() -> Mechanism {
    let effects = Effects {
        shear: true,
        extension: true,
        poisson: true,
        plane_strain: false,
    };
    let beam = |length: f64, thickness: f64| BeamSpec {
        length,
        width: 0.01,
        thickness,
        youngs_modulus: 2e9,
        poisson_ratio: 0.45,
        shear_coefficient: None,
        density: None,
        effects: EffectsChoice::Fixed(effects),
        allowable_stress: None,
    };
    let flexure = |root: [f64; 2], deg: f64, attach, b| Flexure {
        root,
        angle: f64::to_radians(deg),
        attach,
        beam: b,
    };
    Mechanism {
        flexures: vec![
            flexure([0.0, 0.03], 0.0, Attach::Clamped, beam(0.1, 0.01)),
            flexure([0.0, -0.03], 10.0, Attach::Pinned, beam(0.12, 0.008)),
            flexure(
                [0.12, 0.1],
                -80.0,
                Attach::Link { to: [0.09, 0.0] },
                beam(0.08, 0.01),
            ),
        ],
        stage_point: [0.1, 0.03],
        drives: Vec::new(),
    }
}

/// The analytic Jacobian against central differences of the whole residual at a point
/// away from equilibrium. Differences with h = 1e-6 err by O(h^2) relative to the
/// residual's curvature plus the shots' tolerance 1e-12 / h = 1e-6; the beam's
/// sensitivities are integrated to a relative 1e-7. So 1e-4 relative to the column.
fn check<M: FlexureModel>(s: &MechSolver<M>, drive: &[Coordinate; 3]) {
    let x0 = s.start(drive);
    let x: Vec<f64> = x0
        .iter()
        .enumerate()
        .map(|(j, v)| v + 0.05 * ((j as f64 * 1.7).sin() + 0.3))
        .collect();
    let n = x.len();
    let at = DrivePath::proportional(*drive, 1).at(0.6);
    let sys = s.system(&at, &x).unwrap();
    let jac = s.jacobian(&at, &x, &sys);
    for col in 0..n {
        let h = 1e-6;
        let mut xp = x.clone();
        let mut xm = x.clone();
        xp[col] += h;
        xm[col] -= h;
        let rp = s.system(&at, &xp).unwrap().residual;
        let rm = s.system(&at, &xm).unwrap().residual;
        let scale = (0..n).fold(1.0_f64, |m, r| m.max(jac[r * n + col].abs()));
        for row in 0..n {
            let fd = (rp[row] - rm[row]) / (2.0 * h);
            let an = jac[row * n + col];
            assert!(
                (fd - an).abs() <= 1e-4 * scale,
                "row {row} col {col}: analytic {an}, differences {fd}"
            );
        }
    }
}

#[test]
fn analytic_jacobian_matches_differences() {
    let m = mixed();
    let drives = [
        [Loaded(0.3), Loaded(-1.0), Loaded(0.2)],
        [Prescribed(0.01), Loaded(2.0), Prescribed(0.05)],
    ];
    let beam = exact::solver(&m, Resolution::with_tol(1e-12)).unwrap();
    let su = PrbMatrix::parse("0.10,inf,inf; 0.35,3.51,40; 0.40,2.99,inf; 0.15,2.58,inf").unwrap();
    let chain = prb::solver(&m, &su, 1e-10);
    for d in &drives {
        check(&beam, d);
        check(&chain, d);
    }
}

/// Evaluations of a model, counted: full ones and checks by values.
#[derive(Default)]
struct Counts {
    full: std::cell::Cell<u32>,
    by_values: std::cell::Cell<u32>,
}

/// The exact beam, counting its evaluations; `checks` false: evaluated in full at every
/// Newton iterate (the trait's default, no check by values).
struct Counted<'a> {
    beam: exact::BeamFlexure,
    checks: bool,
    /// Whether it asks for closely predicted cases, as the beam does.
    predicted: bool,
    counts: &'a Counts,
}

impl FlexureModel for Counted<'_> {
    fn internal(&self) -> usize {
        0
    }
    fn eval(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure> {
        self.counts.full.set(self.counts.full.get() + 1);
        self.beam.eval(w, z)
    }
    fn predicted(&self) -> bool {
        self.predicted
    }
    fn eval_shaped(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure> {
        self.counts.full.set(self.counts.full.get() + 1);
        self.beam.eval_shaped(w, z)
    }
    fn eval_values(&self, w: [f64; 3], z: &[f64]) -> Result<FlexEval, TipFailure> {
        if !self.checks {
            return self.eval(w, z);
        }
        self.counts.by_values.set(self.counts.by_values.get() + 1);
        let e = self.beam.eval_values(w, z)?;
        assert!(
            e.jacobian.is_empty(),
            "the beam's check leaves its Jacobian out"
        );
        Ok(e)
    }
    fn load_stable(&self, eval: &FlexEval, w: [f64; 3], z: &[f64]) -> bool {
        self.beam.load_stable(eval, w, z)
    }
    fn stability_indicator(&self, eval: &FlexEval) -> Option<f64> {
        self.beam.stability_indicator(eval)
    }
    fn stress(&self, eval: &FlexEval, w: [f64; 3], z: &[f64]) -> Option<crate::beam::Stress> {
        self.beam.stress(eval, w, z)
    }
}

/// A parallel stage of two clamped elastica flexures (slenderness 100) 0.6 L apart, its
/// point midway between their tips.
fn elastica_stage() -> Mechanism {
    let clamped = |root: [f64; 2]| Flexure {
        root,
        angle: 0.0,
        attach: Attach::Clamped,
        beam: BeamSpec::unit_elastica(0.01),
    };
    Mechanism {
        flexures: vec![clamped([0.0, 0.3]), clamped([0.0, -0.3])],
        stage_point: [1.0, 0.0],
        drives: Vec::new(),
    }
}

/// [`elastica_stage`]'s solver at tol 1e-10, its flexures counted and checked by values:
/// following its drives with the beam's closely predicted cases (the chord, `path.rs`), and
/// without (the secant and Newton).
fn chorded_and_not<'a>(chorded: &'a Counts, not: &'a Counts) -> [MechSolver<Counted<'a>>; 2] {
    let exact = exact::solver(&elastica_stage(), Resolution::with_tol(1e-10)).unwrap();
    let with = |predicted, counts| {
        let models = exact.models.iter().map(|&beam| Counted {
            beam,
            checks: true,
            predicted,
            counts,
        });
        MechSolver::new(exact.geometry.clone(), models.collect(), exact.tol)
    };
    [with(true, chorded), with(false, not)]
}

/// Newton's last iterate checked by values alone (the beam's shot without its
/// variational equations) gives the cases that full evaluations give: the same Newton
/// iterations, the same stability, and poses, wrenches and stresses that differ at most
/// by the shots' integration error (the two shots may step differently where the
/// sensitivities limit the step; at tol 1e-10 both are good to about 1e-10, so 1e-8 of
/// each figure is a hundred times that). On three flexures with every effect on
/// (Dormand-Prince shots), and on a parallel stage of elastica flexures (Taylor shots),
/// pushed sideways, then with its upper flexure compressed past its buckling load as a
/// dead load (not load-stable: the stability test reads the Jacobian the check carries
/// over). Most cases end on a check, which spares each flexure a full evaluation. (Both
/// follow the drives by the secant and Newton's step, as a PRB chain does: the beam's own
/// cubic prediction is the next test's.)
#[test]
fn a_check_by_values_gives_the_full_evaluations_cases() {
    let stage = elastica_stage();
    let everything = [Loaded(0.3), Loaded(-1.0), Loaded(0.2)];
    let prescribed = [Prescribed(0.01), Loaded(2.0), Prescribed(0.05)];
    let scenes = [
        (mixed(), vec![everything, prescribed]),
        (
            stage,
            vec![
                [Loaded(0.0), Loaded(2.0), Loaded(0.0)],
                [Loaded(-0.941), Loaded(1.878), Loaded(0.299)],
            ],
        ),
    ];
    let close = |a: f64, b: f64, what: &str| {
        assert!(
            (a - b).abs() <= 1e-8 * (1.0 + a.abs()),
            "{what}: {a} vs {b}"
        );
    };
    let mut unstable = 0;
    for (m, drives) in &scenes {
        let exact = exact::solver(m, Resolution::with_tol(1e-10)).unwrap();
        let (fast_counts, full_counts) = (Counts::default(), Counts::default());
        let with = |checks, counts| {
            let models = exact.models.iter().map(|&beam| Counted {
                beam,
                checks,
                predicted: false,
                counts,
            });
            MechSolver::new(exact.geometry.clone(), models.collect(), exact.tol)
        };
        let (fast, full) = (with(true, &fast_counts), with(false, &full_counts));
        for d in drives {
            let a = fast.solve_drive(d, 12, 1).unwrap();
            let b = full.solve_drive(d, 12, 1).unwrap();
            assert_eq!(a.len(), b.len());
            for (ca, cb) in a.iter().zip(&b) {
                assert_eq!(ca.iterations, cb.iterations);
                for k in 0..3 {
                    close(ca.stage[k], cb.stage[k], "stage");
                    close(ca.stage_load[k], cb.stage_load[k], "stage load");
                }
                for (fa, fb) in ca.flexures.iter().zip(&cb.flexures) {
                    assert_eq!(fa.load_stable, fb.load_stable);
                    unstable += usize::from(!fa.load_stable);
                    close(fa.tip.a, fb.tip.a, "tip a");
                    close(fa.tip.b, fb.tip.b, "tip b");
                    close(fa.tip.phi, fb.tip.phi, "tip phi");
                    close(fa.wrench.alpha_x, fb.wrench.alpha_x, "alpha x");
                    close(fa.wrench.alpha_y, fb.wrench.alpha_y, "alpha y");
                    close(fa.wrench.beta, fb.wrench.beta, "tip moment");
                    let (sa, sb) = (fa.stress.unwrap(), fb.stress.unwrap());
                    close(sa.max, sb.max, "stress");
                }
            }
        }
        // A case that ends on a check spares each flexure a full evaluation: at least
        // half of them do.
        let (checked, fast_full) = (fast_counts.by_values.get(), fast_counts.full.get());
        let slow_full = full_counts.full.get();
        let evaluations = (drives.len() * 12 * m.flexures.len()) as u32;
        assert!(
            checked > 0 && fast_full + evaluations / 2 <= slow_full,
            "{checked} checks and {fast_full} full evaluations against {slow_full}"
        );
    }
    assert!(unstable > 0, "the compressed flexure is not load-stable");
}

/// A drive that carries factored Jacobians from case to case (`path.rs`, `Chord`: a
/// case checked by values alone takes its determinant's sign and its flexures' stability
/// from an earlier case's Jacobian) reports every case's stability as a drive followed by
/// the secant and Newton, each case's stability from a Jacobian within Newton's last step of
/// it: the parallel stage of elastica flexures pushed until its upper flexure is compressed
/// past its buckling load as a dead load, in 240 cases, the chord serving cases up to a few
/// before the flip (asserted), so that its reach is what ends it in time. Poses and wrenches
/// agree to the tolerance (1e-10 here, so 1e-8 of `1 + |output|` is a hundred times it: the
/// two follow the drive by different predictors and stop at different residuals). Counts
/// measured: 420 checks by values (the chord's and Newton's) and 74 full evaluations.
#[test]
fn a_chord_keeps_every_case_s_stability() {
    let (chorded_counts, full_counts) = (Counts::default(), Counts::default());
    let [chorded, full] = chorded_and_not(&chorded_counts, &full_counts);
    let drive = [Loaded(-0.941), Loaded(1.878), Loaded(0.299)];
    let steps = 240;
    let a = chorded.solve_drive(&drive, steps, 1).unwrap();
    let b = full.solve_drive(&drive, steps, 1).unwrap();
    assert_eq!(a.len(), b.len());
    let (mut flips, mut flip, mut last) = (0, None, None);
    for (i, (ca, cb)) in a.iter().zip(&b).enumerate() {
        let close = |x: f64, y: f64| (x - y).abs() <= 1e-8 * (1.0 + y.abs());
        for k in 0..3 {
            assert!(close(ca.stage[k], cb.stage[k]), "{ca:?} against {cb:?}");
        }
        let flags: Vec<bool> = ca.flexures.iter().map(|f| f.load_stable).collect();
        for (fa, fb) in ca.flexures.iter().zip(&cb.flexures) {
            assert_eq!(fa.load_stable, fb.load_stable, "at {}", ca.fraction);
            assert!(close(fa.wrench.alpha_y, fb.wrench.alpha_y));
            assert!(close(fa.wrench.beta, fb.wrench.beta));
        }
        if last.as_ref().is_some_and(|l| *l != flags) {
            flips += 1;
            flip = Some(i);
        }
        last = Some(flags);
    }
    assert_eq!(flips, 1, "the upper flexure becomes unstable once");
    // The chord served cases shortly before the flip (a case it takes reports one iteration;
    // one evaluated in full, two or more), so its reach, not its absence, kept the flags.
    let flip = flip.unwrap_or_default();
    assert!(
        a[flip.saturating_sub(8)..flip]
            .iter()
            .any(|c| c.iterations == 1),
        "no case taken by the chord just before the flip at case {flip}"
    );
    // Most cases were checked by values alone, with a Jacobian carried over.
    let (checks, fulls) = (chorded_counts.by_values.get(), chorded_counts.full.get());
    assert!(
        checks >= 2 * steps * 3 / 4 && fulls < checks / 4,
        "{checks} checks and {fulls} full evaluations for {steps} cases of two flexures"
    );
}

/// A drive whose cases the chord serves stops at a bifurcation where a drive followed by
/// the secant and Newton does: the elastica stage pushed along its flexures toward 1.25 times
/// its buckling load `2 pi^2` (two fixed-guided columns of `pi^2 E I / L^2`) in 400 cases,
/// most of them checked by values with the determinant's sign of an earlier case. Both report
/// the last regular point within about twice the smallest step (1e-6 of the drive) before the
/// bifurcation, at tol 1e-10: within 4e-6 of `2 pi^2 / 25` and of each other.
#[test]
fn a_chord_stops_at_the_bifurcation_as_newton_does() {
    let (chorded_counts, full_counts) = (Counts::default(), Counts::default());
    let [chorded, full] = chorded_and_not(&chorded_counts, &full_counts);
    let drive = [Loaded(-25.0), Loaded(0.0), Loaded(0.0)];
    let steps = 400;
    let stop = |r: Result<Vec<MechCase>, MechError>| match r {
        Err(MechError::Critical { fraction, .. }) => fraction,
        other => panic!("expected the bifurcation, got {other:?}"),
    };
    let a = stop(chorded.solve_drive(&drive, steps, 1));
    let b = stop(full.solve_drive(&drive, steps, 1));
    let critical = 2.0 * std::f64::consts::PI.powi(2) / 25.0;
    for f in [a, b] {
        assert!(
            f <= critical && f >= critical - 4e-6,
            "stopped at {f}, critical at {critical}"
        );
    }
    assert!((a - b).abs() <= 4e-6, "{a} against {b}");
    // Most of the 316 cases before it were checked by values, with the chord (217 measured:
    // the chord's reach shrinks as the determinant falls toward the bifurcation).
    let checks = chorded_counts.by_values.get() / 2;
    assert!(checks >= 316 / 2, "{checks} checks a flexure");
}

/// On a drive of many cases the continuation's prediction is the case: the shipped
/// parallel stage (slenderness 100, every effect on) pushed sideways, alone and with a pull
/// along its flexures, 500 cases each at tol 1e-9. Each flexure takes about one
/// evaluation a case, by values alone (the cubic's prediction checked, with the Jacobian
/// of an earlier case: `path.rs`, `Chord`), and a full one in a few percent of them (the
/// start and the first cases of a drive, before the cubic has four points, take Newton
/// steps and checks; then a new reference every few dozen cases), where Newton's step and
/// its check took one full evaluation and one check a case; and every stage pose, tip and
/// wrench is within the tolerance (relative to `1 + |output|`) of a solve at tol 1e-12 (which
/// takes the chord too: the stability flags are compared with a drive that does not in
/// `a_chord_keeps_every_case_s_stability`): the solves before this measured at most 5.8e-10
/// on the same drives, as does this one.
#[test]
fn a_drive_of_many_cases_costs_about_one_evaluation_a_case() {
    let beam = BeamSpec {
        length: 0.05,
        width: 0.01,
        thickness: 0.0005,
        youngs_modulus: 200e9,
        poisson_ratio: 0.3,
        shear_coefficient: None,
        density: None,
        effects: EffectsChoice::Fixed(Effects::ALL),
        allowable_stress: None,
    };
    let clamped = |y: f64| Flexure {
        root: [0.0, y],
        angle: 0.0,
        attach: Attach::Clamped,
        beam,
    };
    let stage = Mechanism {
        flexures: vec![clamped(0.015), clamped(-0.015)],
        stage_point: [0.05, 0.0],
        drives: Vec::new(),
    };
    let exact = exact::solver(&stage, Resolution::with_tol(1e-9)).unwrap();
    let reference = exact::solver(&stage, Resolution::with_tol(1e-12)).unwrap();
    let counts = Counts::default();
    let models = exact.models.iter().map(|&beam| Counted {
        beam,
        checks: true,
        predicted: true,
        counts: &counts,
    });
    let counted = MechSolver::new(exact.geometry.clone(), models.collect(), exact.tol);
    let steps = 500;
    let drives = [
        [Loaded(0.0), Loaded(2.4), Loaded(0.0)],
        [Loaded(1.2), Loaded(2.4), Loaded(0.0)],
    ];
    // Each output's difference relative to `1 + |output|`, the scale of Newton's
    // residuals.
    let (mut worst, mut stress) = (0.0_f64, 0.0_f64);
    let mut differ = |a: f64, b: f64| worst = worst.max((a - b).abs() / (1.0 + b.abs()));
    for d in &drives {
        let got = counted.solve_drive(d, steps, 1).unwrap();
        let want = reference.solve_drive(d, steps, 1).unwrap();
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().zip(&want) {
            for k in 0..3 {
                differ(g.stage[k], w.stage[k]);
            }
            for (fg, fw) in g.flexures.iter().zip(&w.flexures) {
                assert_eq!(fg.load_stable, fw.load_stable);
                differ(fg.tip.a, fw.tip.a);
                differ(fg.tip.b, fw.tip.b);
                differ(fg.tip.phi, fw.tip.phi);
                differ(fg.wrench.alpha_x, fw.wrench.alpha_x);
                differ(fg.wrench.alpha_y, fw.wrench.alpha_y);
                differ(fg.wrench.beta, fw.wrench.beta);
                // The stress is the curvature, a derivative of the shape the shots
                // integrate to the tolerance: within ten times it (8.4e-10 measured on
                // the 1000-case stage, before this and after).
                let (sg, sw) = (fg.stress.unwrap().max, fw.stress.unwrap().max);
                stress = stress.max((sg - sw).abs() / sw.abs());
            }
        }
    }
    assert!(worst <= 1e-9, "{worst:e} from the solve at tol 1e-12");
    assert!(
        stress <= 1e-8,
        "stresses {stress:e} from the solve at tol 1e-12"
    );
    // Per flexure: every case's evaluations, the drives' starts included.
    let cases = drives.len() as u32 * steps;
    let (full, checks) = (counts.full.get() / 2, counts.by_values.get() / 2);
    // Measured: 35 full evaluations and 975 checks for the 1000 cases.
    assert!(
        full + checks <= cases + cases / 20 && full <= cases / 20,
        "{full} full evaluations and {checks} checks a flexure for {cases} cases"
    );
}
