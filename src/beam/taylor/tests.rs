//! The Taylor integrator's tests: against a fine Runge-Kutta reference, against the
//! Dormand-Prince shots' samples, and its two builds against each other.

use super::*;
use crate::beam::model::MaterialLimit;
use crate::beam::shoot::rhs;
use crate::beam::{BeamModel, Effects};
use crate::cancel::CancelToken;

fn settings(tol: f64) -> ShotSettings {
    ShotSettings {
        tol,
        variational_tol: 1e-12,
        moment_scale: 1.0,
        h0: 0.1,
        max_steps: 200_000,
    }
}

/// Classical RK4 on the same right-hand side with a tiny fixed step: an independent
/// reference (global error about 1e-14 at 4000 steps on these loads).
fn rk4<const N: usize>(model: &BeamModel, force: TipForce, u0: State<N>, len: f64) -> State<N> {
    let steps = 4000;
    let h = len / steps as f64;
    let f = |u: &State<N>| rhs(model, force, u).unwrap();
    let mut u = u0;
    for _ in 0..steps {
        let k1 = f(&u);
        let k2 = f(&std::array::from_fn(|i| u[i] + 0.5 * h * k1[i]));
        let k3 = f(&std::array::from_fn(|i| u[i] + 0.5 * h * k2[i]));
        let k4 = f(&std::array::from_fn(|i| u[i] + h * k3[i]));
        u = std::array::from_fn(|i| u[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    u
}

fn check<const N: usize>(model: &BeamModel, force: TipForce, segment: Segment) {
    let cancel = CancelToken::new();
    let mut meter = Meter::new(u64::MAX / 4, model, &cancel);
    let (u, steps) =
        integrate::<N>(model, force, segment, settings(1e-12), None, &mut meter).unwrap();
    let mut u0: State<N> = [0.0; N];
    if N > 4 {
        u0[0] = segment.psi;
        u0[1] = segment.moment;
        u0[5] = 1.0;
        if N == 12 {
            u0[8] = 1.0;
        }
    }
    let u0: State<N> = if N > 4 { u0 } else { segment.initial_state() };
    let reference = rk4(model, force, u0, segment.s_end - segment.s_start);
    for i in 0..N {
        assert!(
            (u[i] - reference[i]).abs() <= 1e-10 * (1.0 + reference[i].abs()),
            "N = {N}, component {i}: Taylor {} vs RK4 {} ({steps} steps)",
            u[i],
            reference[i]
        );
    }
}

/// The samples and their sensitivities (summed to fewer orders) against the
/// Dormand-Prince shot's, both at tol 1e-12: the shape to 1e-10, the sensitivities to the
/// production variational tolerance's 1e-6 (relative), whose truncation they carry.
#[test]
fn taylor_samples_match_the_runge_kutta_shots() {
    let model = BeamModel::elastica();
    let cancel = CancelToken::new();
    let force = TipForce {
        alpha_x: -2.0,
        alpha_y: 4.0,
    };
    let mut settings = settings(1e-12);
    settings.variational_tol = 1e-6;
    settings.moment_scale = 4.5;
    for (segment, columns) in [
        (
            Segment {
                s_start: 0.0,
                s_end: 0.5,
                psi: 0.0,
                moment: 2.5,
                origin: (0.0, 0.0),
            },
            3,
        ),
        (
            Segment {
                s_start: 0.5,
                s_end: 1.0,
                psi: 0.9,
                moment: 1.1,
                origin: (0.45, 0.2),
            },
            6,
        ),
    ] {
        let run = |taylor: bool| {
            let mut points = Vec::new();
            let mut sens = Vec::new();
            let samples = Samples {
                points: &mut points,
                count: 41,
                sensitivities: Some(&mut sens),
            };
            let mut meter = Meter::new(u64::MAX / 4, &model, &cancel);
            let shape = Some(samples);
            if columns == 3 && taylor {
                integrate::<8>(&model, force, segment, settings, shape, &mut meter).unwrap();
            } else if columns == 3 {
                crate::beam::dopri::integrate::<8>(
                    &model, force, segment, settings, shape, &mut meter,
                )
                .unwrap();
            } else if taylor {
                integrate::<12>(&model, force, segment, settings, shape, &mut meter).unwrap();
            } else {
                crate::beam::dopri::integrate::<12>(
                    &model, force, segment, settings, shape, &mut meter,
                )
                .unwrap();
            }
            (points, sens)
        };
        let (points, sens) = run(true);
        let (ref_points, ref_sens) = run(false);
        // Root and 20 samples on the first half; the second's 20 after its start.
        assert_eq!(points.len(), if columns == 3 { 21 } else { 20 });
        assert_eq!(points.len(), ref_points.len());
        for (a, b) in points.iter().zip(&ref_points) {
            assert_eq!(a.s, b.s);
            let diff = (a.x - b.x)
                .abs()
                .max((a.y - b.y).abs())
                .max((a.psi - b.psi).abs());
            assert!(diff <= 1e-10, "sample at s = {}: {a:?} vs {b:?}", a.s);
        }
        for (a, b) in sens.iter().zip(&ref_sens) {
            for m in 0..6 {
                let tol = 1e-6 * (1.0 + b[m].abs());
                assert!(
                    (a[m] - b[m]).abs() <= tol,
                    "sensitivity {m}: {a:?} vs {b:?}"
                );
                if m >= columns {
                    assert_eq!(a[m], 0.0);
                }
            }
        }
    }
}

/// The loads of the checks against references: tension, compression and bending, up to a
/// strain of about 0.2 on the stubby rubber beam (its law necks near 0.3 of `E A0`).
const LOADS: [(f64, f64, f64); 5] = [
    (0.0, 3.0, 1.2),
    (-7.0, 7.0, -2.5),
    (2.0, -1.0, 6.0),
    (0.0, 0.0, 2.0),
    (1.0, 0.5, -0.5),
];

/// The two plain-bending models: the elastica and a plate (plane strain, L/t = 30).
fn plain_models() -> [BeamModel; 2] {
    [
        BeamModel::elastica(),
        BeamModel::new(30.0, 0.3, None, Effects::NONE.with_plane_strain(true)).unwrap(),
    ]
}

/// The whole beam from its clamp, and an inner segment, both starting with the moment
/// `m0`.
fn whole_and_inner(m0: f64) -> (Segment, Segment) {
    let whole = Segment::from_clamp(m0);
    let inner = Segment {
        s_start: 0.25,
        s_end: 0.75,
        psi: 0.4,
        moment: m0,
        origin: (0.1, 0.2),
    };
    (whole, inner)
}

#[test]
fn taylor_shots_match_a_fine_runge_kutta_reference() {
    for model in &plain_models() {
        for &(ax, ay, m0) in &LOADS {
            let force = TipForce {
                alpha_x: ax,
                alpha_y: ay,
            };
            let (whole, inner) = whole_and_inner(m0);
            check::<8>(model, force, whole);
            check::<16>(model, force, whole);
            check::<12>(model, force, inner);
        }
    }
}

/// The AVX2 build of the integrator gives the baseline build's bits: end states, step
/// counts, samples and their sensitivities, for every state size, on the elastica and a
/// plate, at a tight and a loose tolerance.
#[cfg(target_arch = "x86_64")]
#[test]
fn both_builds_give_the_same_bits() {
    if !crate::cpu::wide() {
        eprintln!("this processor has no AVX2 and FMA: only the baseline build runs here");
        return;
    }
    let cancel = CancelToken::new();
    fn run<const N: usize>(
        wide: bool,
        model: &BeamModel,
        force: TipForce,
        segment: Segment,
        settings: ShotSettings,
        cancel: &CancelToken,
    ) -> (Vec<u64>, u32) {
        let mut points = Vec::new();
        let mut sens = Vec::new();
        let shape = Some(Samples {
            points: &mut points,
            count: 41,
            sensitivities: Some(&mut sens),
        });
        let mut meter = Meter::new(u64::MAX / 4, model, cancel);
        let (u, steps) = if wide {
            // SAFETY: `cpu::wide` said this processor has AVX2 and FMA.
            unsafe { integrate_wide::<N>(model, force, segment, settings, shape, &mut meter) }
        } else {
            integrate_any::<N>(model, force, segment, settings, shape, &mut meter)
        }
        .unwrap();
        let mut values = u.to_vec();
        values.extend(points.iter().flat_map(|p| [p.s, p.x, p.y, p.psi]));
        values.extend(sens.iter().flatten());
        (values.iter().map(|v| v.to_bits()).collect(), steps)
    }
    let mut compared = 0;
    for model in &plain_models() {
        for (ax, ay, m0) in [
            (0.0, 3.0, 1.2),
            (-7.0, 7.0, -2.5),
            (2.0, -1.0, 6.0),
            (-20.0, 1.0, 9.0),
        ] {
            let force = TipForce {
                alpha_x: ax,
                alpha_y: ay,
            };
            let (whole, inner) = whole_and_inner(m0);
            for tol in [1e-12, 1e-9, 1e-5] {
                let mut settings = settings(tol);
                settings.variational_tol = 1e-6;
                let same = [
                    run::<4>(true, model, force, whole, settings, &cancel)
                        == run::<4>(false, model, force, whole, settings, &cancel),
                    run::<8>(true, model, force, whole, settings, &cancel)
                        == run::<8>(false, model, force, whole, settings, &cancel),
                    run::<12>(true, model, force, inner, settings, &cancel)
                        == run::<12>(false, model, force, inner, settings, &cancel),
                    run::<16>(true, model, force, whole, settings, &cancel)
                        == run::<16>(false, model, force, whole, settings, &cancel),
                ];
                assert_eq!(same, [true; 4], "loads ({ax}, {ay}, {m0}), tol {tol}");
                compared += 4;
            }
        }
    }
    assert_eq!(compared, 96);
}

/// Beams with the other effects, whose state alone the series integrate: a stubby shearing,
/// stretching beam; a stubby rubber beam (Poisson's shrink at nu = 0.45); a slender steel one
/// with everything; and a wide plate with everything (plane strain too).
fn full_models() -> [BeamModel; 4] {
    let effects = |poisson| Effects {
        shear: true,
        extension: true,
        poisson,
        plane_strain: false,
    };
    [
        BeamModel::new(3.0, 0.3, None, effects(false)).unwrap(),
        BeamModel::new(2.5, 0.45, None, effects(true)).unwrap(),
        BeamModel::new(100.0, 0.3, None, effects(true)).unwrap(),
        BeamModel::new(8.0, 0.3, None, Effects::ALL.with_plane_strain(true)).unwrap(),
    ]
}

#[test]
fn series_of_the_other_effects_match_a_fine_runge_kutta_reference() {
    for model in &full_models() {
        for &(ax, ay, m0) in &LOADS {
            let force = TipForce {
                alpha_x: ax,
                alpha_y: ay,
            };
            let (whole, inner) = whole_and_inner(m0);
            check::<4>(model, force, whole);
            check::<4>(model, force, inner);
        }
    }
}

/// The full models' samples against the Dormand-Prince shot's, both at tol 1e-12, to 1e-10;
/// and their two builds bit for bit.
#[test]
fn series_of_the_other_effects_sample_as_the_runge_kutta_shots_do() {
    let cancel = CancelToken::new();
    let mut compared = 0;
    for model in &full_models() {
        for &(ax, ay, m0) in &LOADS {
            let force = TipForce {
                alpha_x: ax,
                alpha_y: ay,
            };
            let (whole, inner) = whole_and_inner(m0);
            for segment in [whole, inner] {
                let run = |how: u8| {
                    let mut points = Vec::new();
                    let shape = Some(Samples {
                        points: &mut points,
                        count: 41,
                        sensitivities: None,
                    });
                    let mut meter = Meter::new(u64::MAX / 4, model, &cancel);
                    let settings = settings(1e-12);
                    let end = match how {
                        0 => integrate_any::<4>(model, force, segment, settings, shape, &mut meter),
                        #[cfg(target_arch = "x86_64")]
                        1 if crate::cpu::wide() => {
                            // SAFETY: `cpu::wide` said this processor has AVX2 and FMA.
                            unsafe {
                                integrate_wide::<4>(
                                    model, force, segment, settings, shape, &mut meter,
                                )
                            }
                        }
                        1 => integrate_any::<4>(model, force, segment, settings, shape, &mut meter),
                        _ => crate::beam::dopri::integrate::<4>(
                            model, force, segment, settings, shape, &mut meter,
                        ),
                    }
                    .unwrap();
                    (end, points)
                };
                let (end, points) = run(0);
                let (wide_end, wide_points) = run(1);
                let (_, ref_points) = run(2);
                assert_eq!(end.0.map(f64::to_bits), wide_end.0.map(f64::to_bits));
                assert_eq!(points, wide_points);
                assert_eq!(points.len(), ref_points.len());
                for (a, b) in points.iter().zip(&ref_points) {
                    assert_eq!(a.s, b.s);
                    let diff = (a.x - b.x)
                        .abs()
                        .max((a.y - b.y).abs())
                        .max((a.psi - b.psi).abs());
                    assert!(
                        diff <= 1e-10,
                        "{model:?}: sample at s = {}: {a:?} vs {b:?}",
                        a.s
                    );
                    compared += 1;
                }
            }
        }
    }
    // Per model and load, the whole beam's 41 samples and the inner segment's 20.
    assert_eq!(compared, 4 * 5 * 61);
}

/// Forces the Poisson law cannot carry: a tension that necks the section once the beam has
/// turned towards it (`0.335 E A0` against the law's peak `4 / (27 nu) E A0 = 0.329 E A0`,
/// `0.3 E A0` at the clamp), and a compression that crushes it at the clamp; the series name
/// them as the law does.
#[test]
fn the_series_name_the_law_s_limits() {
    let model = BeamModel::new(2.5, 0.45, None, Effects::ALL).unwrap();
    let cancel = CancelToken::new();
    let c_e = model.axial_compliance();
    let shoot = |ax: f64, ay: f64, m0: f64| {
        let force = TipForce {
            alpha_x: ax / c_e,
            alpha_y: ay / c_e,
        };
        let mut meter = Meter::new(u64::MAX / 4, &model, &cancel);
        let segment = Segment::from_clamp(m0);
        integrate::<4>(&model, force, segment, settings(1e-9), None, &mut meter).map(|(u, _)| u)
    };
    let necked = shoot(0.3, 0.15, 2.0);
    assert!(
        matches!(
            necked,
            Err(ShotFailure::Material(MaterialLimit::Necked { .. }))
        ),
        "{necked:?}"
    );
    // Without the pull's turn the same beam carries it.
    assert!(shoot(0.3, 0.0, 0.0).is_ok());
    let crushed = shoot(-2.5, 0.0, 0.0);
    assert!(
        matches!(
            crushed,
            Err(ShotFailure::Material(MaterialLimit::Crushed { .. }))
        ),
        "{crushed:?}"
    );
}

/// A shot with sensitivities of a beam with the other effects (the Runge-Kutta pair's) ends
/// where the same shot by values (the series') ends, to the bit, alone or in a pair: a
/// mechanism's Newton iterate checked by values is checked against the equations its
/// Jacobian's residual solved. The sensitivities are the pair's own.
#[test]
fn a_shot_with_sensitivities_ends_where_the_series_do() {
    let cancel = CancelToken::new();
    for model in &full_models() {
        for &(ax, ay, m0) in &LOADS {
            let force = TipForce {
                alpha_x: ax,
                alpha_y: ay,
            };
            let settings = settings(1e-9);
            let mut meter = Meter::new(u64::MAX / 4, model, &cancel);
            let shoot = crate::beam::shot::root_shot::<16>;
            let (full, _) = shoot(model, force, m0, settings, None, &mut meter).unwrap();
            let (values, _) =
                crate::beam::shot::root_shot::<4>(model, force, m0, settings, None, &mut meter)
                    .unwrap();
            assert_eq!(full[..4], values[..], "{model:?}, loads ({ax}, {ay}, {m0})");
            let pair = |m: f64| (model, force, m, settings, None);
            let mut other = Meter::new(u64::MAX / 4, model, &cancel);
            let [a, b] = crate::beam::shot::root_shot_pair::<16>(
                [pair(m0), pair(0.5 * m0)],
                [&mut meter, &mut other],
            );
            let (a, b) = (a.unwrap().0, b.unwrap().0);
            let (half, _) = crate::beam::shot::root_shot::<4>(
                model,
                force,
                0.5 * m0,
                settings,
                None,
                &mut meter,
            )
            .unwrap();
            assert_eq!(a[..4], values[..]);
            assert_eq!(b[..4], half[..]);
            // The sensitivities are the Runge-Kutta pair's.
            let (rk, _) = crate::beam::dopri::integrate::<16>(
                model,
                force,
                Segment::from_clamp(m0),
                settings,
                None,
                &mut meter,
            )
            .unwrap();
            assert_eq!(full[4..], rk[4..]);
        }
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]
    /// On any beam with any of the other effects (from a stubby block to a hair, from cork to
    /// nearly incompressible rubber, with or without plane strain), under any load that the
    /// material law carries, the series' shot of the state ends where the Runge-Kutta pair's
    /// does: both at tol 1e-11, to 1e-8 (each is within about 1e-10 of the exact end on the
    /// fixed cases above; the margin covers a long path's accumulation and its turns).
    #[test]
    fn series_agree_with_the_runge_kutta_pair_on_any_beam(
        log_slenderness in 0.0..4.0f64,
        nu in 0.0..0.499f64,
        shear in proptest::prelude::any::<bool>(),
        stretch in proptest::prelude::any::<(bool, bool)>(),
        plane_strain in proptest::prelude::any::<bool>(),
        ax in -10.0..10.0f64,
        ay in -10.0..10.0f64,
        m0 in -6.0..6.0f64,
    ) {
        let (extension, poisson) = (stretch.0 || stretch.1, stretch.1);
        let effects = Effects { shear, extension, poisson, plane_strain };
        proptest::prop_assume!(effects != Effects::NONE.with_plane_strain(plane_strain));
        let model = BeamModel::new(10f64.powf(log_slenderness), nu, None, effects).unwrap();
        let cancel = CancelToken::new();
        let force = TipForce { alpha_x: ax, alpha_y: ay };
        let segment = Segment::from_clamp(m0);
        let mut meter = Meter::new(u64::MAX / 4, &model, &cancel);
        let rk = crate::beam::dopri::integrate::<4>(&model, force, segment, settings(1e-11), None, &mut meter);
        // Loads past the law's limits fail both ways (named by each; not compared here).
        proptest::prop_assume!(rk.is_ok());
        let (rk, _) = rk.unwrap();
        let (series, _) = integrate::<4>(&model, force, segment, settings(1e-11), None, &mut meter).unwrap();
        for i in 0..4 {
            proptest::prop_assert!(
                (series[i] - rk[i]).abs() <= 1e-8 * (1.0 + rk[i].abs()),
                "component {i}: series {:?} vs Runge-Kutta {:?}", series, rk
            );
        }
    }
}

/// Two shots integrated side by side ([`integrate_pair`]) are each the shot integrated alone,
/// to the bit: end states, step counts and samples, in both builds (the pair's baseline
/// build against the single shot's baseline build, and, where the processor has them, its
/// AVX2 build too). On every pair of the beams with the other effects (series of one kind
/// built in one register's lanes, of two kinds one after the other) and of the plain ones
/// with and without sensitivities, under loads that take different numbers of steps, and
/// with a shot whose material law fails beside one that goes on.
#[test]
fn a_pair_of_series_shots_is_each_shot_alone() {
    let cancel = CancelToken::new();
    // A failure by its `Debug` text (which writes its numbers exactly).
    type Out = Result<(Vec<u64>, u32), String>;
    fn bits<const N: usize>(r: Result<(State<N>, u32), ShotFailure>, points: &[ShapePoint]) -> Out {
        let (u, steps) = r.map_err(|e| format!("{e:?}"))?;
        let mut values = u.to_vec();
        values.extend(points.iter().flat_map(|p| [p.s, p.x, p.y, p.psi]));
        Ok((values.iter().map(|v| v.to_bits()).collect(), steps))
    }
    fn alone<const N: usize>(
        model: &BeamModel,
        (ax, ay, m0): (f64, f64, f64),
        cancel: &CancelToken,
    ) -> Out {
        let force = TipForce {
            alpha_x: ax,
            alpha_y: ay,
        };
        let mut points = Vec::new();
        let shape = Some(Samples {
            points: &mut points,
            count: 41,
            sensitivities: None,
        });
        let mut meter = Meter::new(u64::MAX / 4, model, cancel);
        let r = integrate_any::<N>(
            model,
            force,
            Segment::from_clamp(m0),
            settings(1e-9),
            shape,
            &mut meter,
        );
        bits(r, &points)
    }
    fn pair<const N: usize>(
        wide: bool,
        models: [&BeamModel; 2],
        loads: [(f64, f64, f64); 2],
        cancel: &CancelToken,
    ) -> [Out; 2] {
        let (mut pa, mut pb) = (Vec::new(), Vec::new());
        let shot = |model, (ax, ay, m0): (f64, f64, f64), points| -> PairShot<'_, '_> {
            let force = TipForce {
                alpha_x: ax,
                alpha_y: ay,
            };
            let shape = Some(Samples {
                points,
                count: 41,
                sensitivities: None,
            });
            (model, force, Segment::from_clamp(m0), settings(1e-9), shape)
        };
        let shots = [
            shot(models[0], loads[0], &mut pa),
            shot(models[1], loads[1], &mut pb),
        ];
        let mut ma = Meter::new(u64::MAX / 4, models[0], cancel);
        let mut mb = Meter::new(u64::MAX / 4, models[1], cancel);
        let [ra, rb] = if wide {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the caller asks for the wide build only where `cpu::wide` said this
            // processor has AVX2 and FMA.
            let r = unsafe { integrate_pair_wide::<N>(shots, [&mut ma, &mut mb]) };
            #[cfg(not(target_arch = "x86_64"))]
            let r = integrate_pair_any::<N>(shots, [&mut ma, &mut mb]);
            r
        } else {
            integrate_pair_any::<N>(shots, [&mut ma, &mut mb])
        };
        [bits(ra, &pa), bits(rb, &pb)]
    }
    let builds: &[bool] = if crate::cpu::wide() {
        &[false, true]
    } else {
        &[false]
    };
    // The rubber's section necks under a pull of 200 at once.
    let necks = (200.0, 0.0, 0.0);
    let full = full_models();
    assert!(
        alone::<4>(&full[1], necks, &cancel).is_err(),
        "the necking case must fail"
    );
    let mut compared = 0;
    for (i, a) in full.iter().enumerate() {
        for (j, b) in full.iter().enumerate() {
            for l in 0..LOADS.len() {
                let loads = [LOADS[l], LOADS[(l + i + j + 1) % LOADS.len()]];
                for &wide in builds {
                    let got = pair::<4>(wide, [a, b], loads, &cancel);
                    let want = [
                        alone::<4>(a, loads[0], &cancel),
                        alone::<4>(b, loads[1], &cancel),
                    ];
                    assert_eq!(
                        got, want,
                        "models {i} and {j}, loads {loads:?}, wide {wide}"
                    );
                    compared += 1;
                }
            }
            for &wide in builds {
                let loads = [necks, LOADS[i]];
                if j == 1 {
                    let got = pair::<4>(wide, [b, a], loads, &cancel);
                    let want = [
                        alone::<4>(b, loads[0], &cancel),
                        alone::<4>(a, loads[1], &cancel),
                    ];
                    assert!(got[0].is_err(), "the rubber must neck beside model {i}");
                    assert_eq!(got, want, "necking beside model {i}, wide {wide}");
                }
            }
        }
    }
    for a in &plain_models() {
        for b in &plain_models() {
            for &wide in builds {
                let loads = [LOADS[0], LOADS[2]];
                let want = [
                    alone::<4>(a, loads[0], &cancel),
                    alone::<4>(b, loads[1], &cancel),
                ];
                assert_eq!(pair::<4>(wide, [a, b], loads, &cancel), want);
                let want = [
                    alone::<16>(a, loads[0], &cancel),
                    alone::<16>(b, loads[1], &cancel),
                ];
                assert_eq!(pair::<16>(wide, [a, b], loads, &cancel), want);
                compared += 2;
            }
        }
    }
    assert_eq!(compared, (16 * 5 + 4 * 2) * builds.len());
}
