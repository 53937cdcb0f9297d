//! Modelling only what a scene requires: automatic effects (checked, not assumed), the
//! topology ladder's choice, and the trade-off measurements.
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use std::path::Path;

mod common;

use common::{json, prbfit};
use prbfit::beam::{Effects, Resolution};
use prbfit::eval::Baseline;
use prbfit::fit::{CancelToken, Fidelity};
use prbfit::mech::exact;
use prbfit::mech::figures::compare;
use prbfit::prb::PrbMatrix;
use prbfit::scene::{BeamSpec, EffectsChoice, Scene};
use prbfit::study::effects::{decide_effects, AUTO_FRACTION};
use prbfit::study::{resolve_effects, Sampling, Study};

fn scene(name: &str) -> Scene {
    let p = format!("{}/assets/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    Scene::from_file(Path::new(&p)).unwrap()
}

/// The tip change between every-effect-on (plane strain included) and `effects`, as a
/// fraction of the targets,
/// computed here independently of the decision's own bookkeeping.
fn change_fraction(scene: &Scene, effects: Effects) -> f64 {
    let solve = |e: Effects| {
        let mut b = scene.beam;
        b.effects = EffectsChoice::Fixed(e);
        Baseline::for_model(b.model(), &scene.loads, Resolution::default()).unwrap()
    };
    let (full, reduced) = (solve(Effects::ALL.with_plane_strain(true)), solve(effects));
    full.solutions
        .iter()
        .zip(&reduced.solutions)
        .map(|(x, y)| {
            let pos = (x.tip.a - y.tip.a).hypot(x.tip.b - y.tip.b);
            let ang = (x.tip.phi - y.tip.phi).abs();
            (pos / scene.accuracy.max_pos_err).max(ang / scene.accuracy.max_ang_err)
        })
        .fold(0.0, f64::max)
}

/// Shear, stretch and Poisson are negligible on the slender steel leaf; its width is not: 8 mm
/// wide and 0.3 mm thick, it is 2.4-5.5 % stiffer than a narrow beam by 3D FEA
/// (`tests/data.rs::the_steel_leaf_needs_plane_strain_by_3d_fea`), which moves its tip by
/// several times the target.
#[test]
fn slender_steel_needs_only_plane_strain() {
    let s = scene("steel-flexure");
    let d = decide_effects(&s, Resolution::default(), &CancelToken::new()).unwrap();
    assert_eq!(d.effects, Effects::NONE.with_plane_strain(true), "{d:?}");
    assert!(d.impacts[3].fraction_of_target > 1.0, "{d:?}");
    let dropped = change_fraction(&s, d.effects);
    assert!(
        dropped < AUTO_FRACTION,
        "dropping them all moves the tip {dropped} of target"
    );
    assert!((dropped - d.dropped_together_fraction).abs() < 1e-9);
}

#[test]
fn short_rubber_keeps_what_it_needs() {
    let s = scene("urethane-joint");
    let d = decide_effects(&s, Resolution::default(), &CancelToken::new()).unwrap();
    let full = Effects::ALL.with_plane_strain(true);
    assert_eq!(d.effects, full, "{d:?}");
    // Each kept effect is kept for a reason: dropping it alone exceeds the fraction.
    for (name, e) in [
        (
            "shear",
            Effects {
                shear: false,
                ..full
            },
        ),
        (
            "extension",
            Effects {
                extension: false,
                poisson: false,
                ..full
            },
        ),
        (
            "poisson",
            Effects {
                poisson: false,
                ..full
            },
        ),
        ("plane_strain", Effects::ALL),
    ] {
        let f = change_fraction(&s, e);
        assert!(f > AUTO_FRACTION, "{name}: {f}");
    }
}

/// On every example scene, whatever auto drops moves the tip less than the stated fraction.
#[test]
fn auto_dropped_effects_are_small_on_every_scene() {
    for name in ["default", "steel-flexure", "urethane-joint"] {
        let s = scene(name);
        let (resolved, decision) =
            resolve_effects(&s, Resolution::default(), &CancelToken::new()).unwrap();
        let d = decision.expect("the example scenes use auto");
        assert_eq!(resolved.beam.effects, EffectsChoice::Fixed(d.effects));
        let f = change_fraction(&s, d.effects);
        assert!(f <= AUTO_FRACTION, "{name}: {f}");
    }
}

/// A long select shows each ladder fit's progress between its rows (a fit on 100000 cases
/// left the progress line standing for a minute): every fitted row's topology reports, in
/// ladder order, before its row, and its last report's best `J` is at least the row's.
#[test]
fn select_reports_each_fits_progress_before_its_row() {
    let study = Study::as_given(&scene("default"), Sampling::Fidelity(Fidelity::Draft)).unwrap();
    let events = std::cell::RefCell::new(Vec::<(String, bool, f64)>::new());
    let sel = study
        .select_with_progress(
            Fidelity::Draft,
            &CancelToken::new(),
            &mut |row| {
                let j = row.figures.objective;
                events.borrow_mut().push((row.name.clone(), true, j));
            },
            &mut |topology, fit| {
                events
                    .borrow_mut()
                    .push((topology.to_string(), false, fit.best_objective));
            },
        )
        .unwrap();
    let events = events.into_inner();
    let fitted: Vec<&str> = sel
        .rows
        .iter()
        .filter(|r| !r.published)
        .map(|r| r.name.as_str())
        .collect();
    assert!(fitted.len() >= 3, "{fitted:?}");
    for name in fitted {
        let row_at = events.iter().position(|e| e.1 && e.0 == name).unwrap();
        let last_fit = events[..row_at]
            .iter()
            .rposition(|e| !e.1 && e.0 == name)
            .unwrap_or_else(|| panic!("{name}: no progress before its row"));
        assert!(
            events[last_fit].2 >= events[row_at].2 * (1.0 - 1e-12),
            "{name}: progress J {} below the row's {}",
            events[last_fit].2,
            events[row_at].2
        );
    }
}

/// The chosen model meets the targets and every simpler rung does not; where nothing meets
/// them the closest is named.
#[test]
fn the_simplest_sufficient_model_is_chosen() {
    for name in ["default", "steel-flexure", "urethane-joint"] {
        let (s, _) =
            resolve_effects(&scene(name), Resolution::default(), &CancelToken::new()).unwrap();
        let study = Study::as_given(&s, Sampling::Fidelity(Fidelity::Normal)).unwrap();
        let sel = study
            .select(Fidelity::Normal, &CancelToken::new(), &mut |_| {})
            .unwrap();
        println!("{name}: chosen {:?}", sel.chosen.map(|i| &sel.rows[i].name));
        match sel.chosen {
            Some(i) => {
                let chosen = &sel.rows[i];
                assert!(chosen.figures.meets(&s.accuracy));
                for r in &sel.rows {
                    if r.dof < chosen.dof {
                        assert!(
                            !r.meets_targets,
                            "{} is simpler and meets the targets",
                            r.name
                        );
                    }
                }
            }
            None => {
                assert!(sel.rows.iter().all(|r| !r.meets_targets));
                let best = sel
                    .rows
                    .iter()
                    .map(|r| r.target_ratio)
                    .fold(f64::MAX, f64::min);
                assert_eq!(sel.rows[sel.closest].target_ratio, best);
                assert!(best > 1.0);
            }
        }
        // The ladder is fitted, and the published models are judged as they are.
        assert!(sel.rows.iter().any(|r| r.published && r.name == "su-3r"));
        assert!(sel.rows.iter().filter(|r| !r.published).count() >= 4);
    }
}

#[test]
fn cli_select_and_tradeoff() {
    let path = format!(
        "{}/assets/scenes/urethane-joint.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let v = json(&prbfit(&["select", "--scene", &path, "--json"]));
    let rows = v["rows"].as_array().unwrap();
    assert!(rows
        .iter()
        .all(|r| r["topology"].is_string() && r["prb"].is_string()));
    let chosen = &v["chosen"];
    assert!(chosen["meets_targets"].as_bool().unwrap());
    PrbMatrix::parse(chosen["prb"].as_str().unwrap()).unwrap();
    assert_eq!(v["effects_decision"]["effects"]["shear"], true);

    let v = json(&prbfit(&["tradeoff", "--topology", "L-R-R", "--json"]));
    let knobs = v["knobs"].as_array().unwrap();
    let names: Vec<&str> = knobs.iter().map(|k| k["knob"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "beam resolution",
            "load sampling",
            "fidelity preset",
            "topology"
        ]
    );
    // Finer beam resolution is more accurate: the tightest tolerance beats the loosest.
    let res = knobs[0]["rows"].as_array().unwrap();
    let err = |r: &serde_json::Value| r["error"].as_f64().unwrap();
    assert!(err(res.last().unwrap()) < err(&res[0]));
    for k in knobs {
        for r in k["rows"].as_array().unwrap() {
            assert!(r["seconds"].as_f64().unwrap() > 0.0 && err(r).is_finite());
        }
    }
}

/// The procedure of `decide_effects`, every effect judged on every case, written here again
/// from its description: the decided effects and each effect's fraction of the target.
fn decided_on_every_case(s: &Scene) -> (Effects, [f64; 4]) {
    decided_on_every_case_by(|e| change_fraction(s, e))
}

/// The decision procedure, re-written here, over every case: `change(e)` is what modelling with
/// `e` instead of every effect changes, as a fraction of the targets.
fn decided_on_every_case_by(change: impl Fn(Effects) -> f64) -> (Effects, [f64; 4]) {
    let full = Effects::ALL.with_plane_strain(true);
    let dropped = [
        Effects {
            shear: false,
            ..full
        },
        Effects {
            extension: false,
            poisson: false,
            ..full
        },
        Effects {
            poisson: false,
            ..full
        },
        Effects::ALL,
    ];
    let fractions = dropped.map(&change);
    let mut kept = fractions.map(|f| f > AUTO_FRACTION);
    kept[1] |= kept[2];
    loop {
        let effects = Effects {
            shear: kept[0],
            extension: kept[1],
            poisson: kept[2],
            plane_strain: kept[3],
        };
        let back = (0..4)
            .filter(|&k| !kept[k])
            .max_by(|&a, &b| fractions[a].total_cmp(&fractions[b]));
        match back {
            Some(k) if change(effects) > AUTO_FRACTION => {
                kept[k] = true;
                kept[1] |= kept[2];
            }
            _ => return (effects, fractions),
        }
    }
}

/// A scene of many cases per path is decided on a sample of each path and checked on every
/// case (issue 24: auto at most 10x the plain beam): the decision is the one every case gives,
/// each effect's figure is its change on the sample (a lower bound of its change on every
/// case: the sample's cases are among them), and the figure of everything dropped together is
/// the change on every case.
#[test]
fn a_decision_on_a_sample_of_each_path_is_the_decision_on_every_case() {
    for name in ["default", "steel-flexure", "urethane-joint"] {
        let mut s = scene(name);
        for path in &mut s.loads {
            path.steps = 40;
        }
        let d = decide_effects(&s, Resolution::default(), &CancelToken::new()).unwrap();
        let (effects, fractions) = decided_on_every_case(&s);
        assert_eq!(d.effects, effects, "{name}: {d:?}");
        for (impact, every) in d.impacts.iter().zip(fractions) {
            // Equal where the largest change is at a sampled case; never above the figure on
            // every case, up to the tolerance of two solves of the same case (a sampled case is
            // reached by a different continuation; tips agree to the solver's 1e-9, which is
            // 1e-7 of a 0.01 target).
            assert!(
                impact.fraction_of_target <= every + 1e-7,
                "{name} {}: {} on the sample, {every} on every case",
                impact.effect,
                impact.fraction_of_target
            );
        }
        let together = change_fraction(&s, d.effects);
        assert!(
            (d.dropped_together_fraction - together).abs() < 1e-9,
            "{name}: {} reported, {together} on every case",
            d.dropped_together_fraction
        );
    }
}

/// A mechanism's stage-motion and reaction change between every effect on (plane strain
/// included) and `effects` on every flexure, as a fraction of the targets, over every case
/// of its drives.
fn mech_change_fraction(scene: &Scene, effects: Effects) -> f64 {
    let m = scene.mechanism.as_ref().unwrap();
    let with = |e: Effects| {
        let mut m = m.clone();
        for f in &mut m.flexures {
            f.beam.effects = EffectsChoice::Fixed(e);
        }
        exact::solve(&m, Resolution::default()).unwrap()
    };
    let (full, reduced) = (with(Effects::ALL.with_plane_strain(true)), with(effects));
    let f = compare(&m.drives, &reduced, &full, 1.0, 1.0)
        .unwrap()
        .figures;
    let a = &scene.accuracy;
    (f.max_pos_err / a.max_pos_err)
        .max(f.max_ang_err / a.max_ang_err)
        .max(f.max_force_err.map_or(0.0, |x| x / a.max_force_err))
}

/// A mechanism's `auto` is decided on the same sample of its drives as a cantilever's on its
/// load paths, and checked on every case: on the slider-crank (slender steel, and as stubby
/// rubber, which keeps shear) and the parallel stage, at 40 steps a drive, the decision is the
/// one made on every case, each effect's figure never above its figure on every case, and
/// the reported together-figure the every-case one.
#[test]
fn a_mechanism_decided_on_a_sample_of_its_drives_is_decided_on_every_case() {
    let stubby = |b: &mut BeamSpec| {
        b.thickness = 0.01;
        b.youngs_modulus = 10e6;
        b.poisson_ratio = 0.49;
    };
    let keep = |_: &mut BeamSpec| {};
    type Edit<'a> = &'a dyn Fn(&mut BeamSpec);
    let cases: [(&str, &str, Edit); 3] = [
        ("slider-crank", "slider-crank", &keep),
        ("slider-crank", "stubby rubber slider-crank", &stubby),
        ("parallel-stage", "parallel-stage", &keep),
    ];
    for (file, name, edit) in cases {
        let mut s = scene(file);
        edit(&mut s.beam);
        s.beam.effects = EffectsChoice::Auto;
        let m = s.mechanism.as_mut().unwrap();
        for f in &mut m.flexures {
            edit(&mut f.beam);
            f.beam.effects = EffectsChoice::Auto;
        }
        for d in &mut m.drives {
            d.steps = 40;
        }
        s.validate().unwrap();
        let d = decide_effects(&s, Resolution::default(), &CancelToken::new()).unwrap();
        let (effects, fractions) = decided_on_every_case_by(|e| mech_change_fraction(&s, e));
        assert_eq!(d.effects, effects, "{name}: {d:?}");
        // The stubby rubber keeps shear (0.92 of the target), the steel ones only their
        // width's plane strain: both branches of the decision are exercised.
        assert_eq!(d.effects.shear, name.starts_with("stubby"), "{name}: {d:?}");
        for (impact, every) in d.impacts.iter().zip(fractions) {
            // Two solves of one case reached by different continuations agree to the
            // solver's 1e-9; over a 0.01 target (or 0.05 of a reaction) that is 1e-7.
            assert!(
                impact.fraction_of_target <= every + 1e-7,
                "{name} {}: {} on the sample, {every} on every case",
                impact.effect,
                impact.fraction_of_target
            );
        }
        let together = mech_change_fraction(&s, d.effects);
        assert!(
            (d.dropped_together_fraction - together).abs() < 1e-9,
            "{name}: {} reported, {together} on every case",
            d.dropped_together_fraction
        );
    }
}
