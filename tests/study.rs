//! One problem (DESIGN §7, §8): a plain cantilever is the one-flexure mechanism whose stage
//! is its tip, every coordinate loaded. The study keeps the cantilever's fast paths (the
//! beam's shooting along each load path, the chain's own statics), so this checks that they
//! give what the mechanism's general paths give on the same scene written as a mechanism
//! (`study::truth::one_flexure`): the beam mechanism shot from the root and the PRB
//! mechanism's closed-chain Newton. DESIGN §8 promises the figures do not change.
//!
//! Tolerances, from the methods' errors:
//! - the truths: both solved at tol 1e-10 (a tip good to `claimed_tip_error`, 1e-9, from
//!   two different shootings): the stages agree to 1e-8.
//! - eval figures: an error figure is a difference of tips, each good to 1e-9 (the beam) and
//!   to the Newton tolerance of its PRB solver (`PRB_TOL` = 1e-8 on the mechanism's
//!   residuals, quadratically converged far below it): asserted at 1e-7 absolute (units of
//!   L, radians), and `J` (a mean of squared errors) at 1e-6 relative.
//! - fitted `J`: the same search on residuals that agree that closely, from the same starts
//!   and seed, ends at the same optimum: 1e-6 relative (issue 23).
#![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

use std::path::Path;

mod common;

use prbfit::beam::{Effects, Resolution};
use prbfit::fit::{CancelToken, Fidelity, FitOptions};
use prbfit::prb::PrbMatrix;
use prbfit::scene::{EffectsChoice, Scene};
use prbfit::study::truth::one_flexure;
use prbfit::study::{CaseForm, Figures, Sampling, Study};

fn scene(name: &str) -> Scene {
    let p = format!("{}/assets/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    Scene::from_file(Path::new(&p)).unwrap()
}

/// The scenes of the check, their effects fixed (plane strain left out: a cantilever takes
/// each case's own plate fraction, a mechanism's flexure its ends' only, DESIGN §2 and
/// `beam::plate`, so with plane strain the two are different models, not one model twice).
fn cases() -> Vec<(String, Scene)> {
    let mut out = Vec::new();
    for (name, effects) in [
        ("default", Effects::NONE),
        ("default", Effects::ALL),
        ("steel-flexure", Effects::ALL),
        ("urethane-joint", Effects::ALL),
        ("tapered-flexure", Effects::NONE),
    ] {
        let mut s = scene(name);
        s.beam.effects = EffectsChoice::Fixed(effects);
        out.push((format!("{name} [{effects}]"), s));
    }
    out
}

/// The same scene written as the one-flexure mechanism of DESIGN §8.
fn as_mechanism(s: &Scene) -> Scene {
    let mut m = s.clone();
    m.mechanism = Some(one_flexure(s));
    m.loads.clear();
    m
}

fn figures_agree(what: &str, tip: &Figures, stage: &Figures) {
    for (name, a, b) in [
        ("rms_pos_err", tip.rms_pos_err, stage.rms_pos_err),
        ("max_pos_err", tip.max_pos_err, stage.max_pos_err),
        ("rms_ang_err", tip.rms_ang_err, stage.rms_ang_err),
        ("max_ang_err", tip.max_ang_err, stage.max_ang_err),
    ] {
        assert!((a - b).abs() <= 1e-7, "{what}: {name} {a} vs {b}");
    }
    let (j, k) = (tip.objective, stage.objective);
    assert!((j - k).abs() <= 1e-6 * j.max(k), "{what}: J {j} vs {k}");
}

#[test]
fn a_cantilever_judges_as_its_one_flexure_mechanism() {
    let resolution = Resolution::with_tol(1e-10);
    for (name, s) in cases() {
        let cantilever = Study::new(&s, Sampling::Every(resolution)).unwrap();
        let mechanism = Study::new(&as_mechanism(&s), Sampling::Every(resolution)).unwrap();
        assert_eq!(cantilever.case_form(), CaseForm::Tip);
        assert_eq!(mechanism.case_form(), CaseForm::Stage);
        assert_eq!(cantilever.case_count(), mechanism.case_count(), "{name}");
        // The truths: the beam shot along each load path, the beam mechanism shot from the
        // root, case by case.
        let mut worst = 0.0_f64;
        for (a, b) in cantilever
            .truth()
            .iter()
            .flatten()
            .zip(mechanism.truth().iter().flatten())
        {
            assert!((a.fraction - b.fraction).abs() < 1e-12);
            for c in 0..3 {
                worst = worst.max((a.stage[c] - b.stage[c]).abs());
            }
        }
        assert!(worst < 1e-8, "{name}: stages differ by {worst:e}");
        for model in ["howell-1r", "su-3r", "chen-3r"] {
            let m = prbfit::io::ModelFile::load(model).unwrap().prb;
            let tip = cantilever.judge(&m).unwrap().figures;
            let stage = mechanism.judge(&m).unwrap().figures;
            println!(
                "{name} {model}: J {:.6e} (cantilever) {:.6e} (one-flexure mechanism); max pos \
                 {:.3e} {:.3e}",
                tip.objective, stage.objective, tip.max_pos_err, stage.max_pos_err
            );
            figures_agree(&format!("{name} {model}"), &tip, &stage);
            // Nothing is prescribed: no reaction figures in either; the cantilever has no
            // flexure tip figure (its stage is its tip), the mechanism's is its stage's.
            assert_eq!(tip.max_force_err, None);
            assert_eq!(stage.max_force_err, None);
            assert_eq!(tip.max_tip_err, None);
            let t = stage.max_tip_err.unwrap();
            assert!((t - stage.max_pos_err).abs() < 1e-12, "{name}: {t} vs pos");
        }
    }
}

/// Past buckling the two paths follow the same stable branch: a load tilted 0.01 from an
/// axial push of twice the 3R chains' buckling load, in four steps. The mechanism's path
/// stopped at the first sign change of its Jacobian's determinant, so a secant step that
/// landed on the unstable branch beside the stable one ended it at 0.25 ("a critical
/// point"), where the chain's own path went on (`prbfit modes --load -5,0.01,0` gave the 3R
/// no frequencies while `eval --load` solved it); it now bisects, as the chain does.
#[test]
fn past_buckling_the_one_flexure_mechanism_follows_the_chain() {
    let resolution = Resolution::with_tol(1e-10);
    let mut s = scene("default");
    s.beam.effects = EffectsChoice::Fixed(Effects::NONE);
    s.loads.truncate(1);
    s.loads[0].end = prbfit::beam::Load::new(-5.0, 0.01, 0.0);
    s.loads[0].steps = 4;
    let cantilever = Study::new(&s, Sampling::Every(resolution)).unwrap();
    let mechanism = Study::new(&as_mechanism(&s), Sampling::Every(resolution)).unwrap();
    for model in ["su-3r", "chen-3r"] {
        let m = prbfit::io::ModelFile::load(model).unwrap().prb;
        let tip = cantilever.judge(&m).unwrap();
        let stage = mechanism.judge(&m).unwrap();
        assert!(tip.unfollowed.is_empty(), "{model}: {:?}", tip.unfollowed);
        assert!(
            stage.unfollowed.is_empty(),
            "{model}: {:?}",
            stage.unfollowed
        );
        figures_agree(
            &format!("{model} past buckling"),
            &tip.figures,
            &stage.figures,
        );
    }
}

#[test]
fn a_cantilever_fits_as_its_one_flexure_mechanism() {
    for (name, s) in cases().into_iter().take(3) {
        let sampling = Sampling::Fidelity(Fidelity::Normal);
        let cantilever = Study::new(&s, sampling).unwrap();
        let mechanism = Study::new(&as_mechanism(&s), sampling).unwrap();
        let options = FitOptions {
            fidelity: Fidelity::Normal,
            angle_weight: s.fit.angle_weight,
            seed: 1,
        };
        let start = PrbMatrix::from_topology("L-R-R").unwrap();
        let fit = |study: &Study| {
            study
                .fit(&start, &options, &mut |_| {}, &CancelToken::new())
                .unwrap()
        };
        let (a, b) = (fit(&cantilever), fit(&mechanism));
        let (j, k) = (a.figures.objective, b.figures.objective);
        println!(
            "{name}: fitted 2R J {j:.9e} (cantilever, {} evaluations) {k:.9e} (one-flexure \
             mechanism, {} evaluations)",
            a.evaluations, b.evaluations
        );
        assert!((j - k).abs() <= 1e-6 * j.max(k), "{name}: J {j} vs {k}");
    }
}

/// DESIGN §6: `eval` of a model that cannot follow one load path reports the figures over
/// the cases it followed, names the path (`unfollowed: [{path, fraction, reason}]`, and a
/// line in the text), does not meet the targets, and exits 0. The figures are those of the
/// same model on the scene without that path (judged independently).
#[test]
fn eval_of_a_model_that_stops_on_one_path_reports_the_rest() {
    // A long rigid root and a very soft joint: no equilibrium under the built-in scene's
    // path 4 (force and moment) from its first case on; paths 1 to 3 are followed.
    let soft = "0.9,inf,inf; 0.1,0.01,inf";
    let out = common::prbfit(&["eval", "--prb", soft, "--json"]);
    let v = common::json(&out);
    let unfollowed = v["unfollowed"].as_array().unwrap();
    assert_eq!(unfollowed.len(), 1, "{v}");
    assert_eq!(unfollowed[0]["path"], 4);
    assert_eq!(unfollowed[0]["fraction"], 0.0);
    assert!(unfollowed[0]["reason"]
        .as_str()
        .unwrap()
        .contains("critical point"));
    assert_eq!(v["meets_targets"], false);
    let builtin = Scene::builtin();
    let followed: u32 = builtin.loads[..3].iter().map(|p| p.steps).sum();
    assert_eq!(v["cases"].as_array().unwrap().len(), followed as usize);
    // The same figures as the model on the first three paths alone.
    let mut three = builtin.clone();
    three.loads.truncate(3);
    let study = Study::new(&three, Sampling::Every(Resolution::default())).unwrap();
    let alone = study
        .judge(&PrbMatrix::parse(soft).unwrap())
        .unwrap()
        .figures;
    for (key, want) in [
        ("objective", alone.objective),
        ("max_pos_err", alone.max_pos_err),
        ("rms_ang_err", alone.rms_ang_err),
    ] {
        let got = v[key].as_f64().unwrap();
        assert!((got - want).abs() <= 1e-12 * want, "{key}: {got} vs {want}");
    }
    let text = common::prbfit(&["eval", "--prb", soft]);
    common::succeeded(&text);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("load path 4 not followed past 0.0000"),
        "{text}"
    );
    // A model that follows nothing at all is still a failure (exit 1).
    let none = common::prbfit(&[
        "eval",
        "--scene",
        &format!(
            "{}/assets/scenes/fixed-guided.toml",
            env!("CARGO_MANIFEST_DIR")
        ),
        "--model",
        "howell-1r",
    ]);
    assert_eq!(none.status.code(), Some(1));
}

/// The same on a mechanism: the displacement-driven cantilever pushed 35 mm (0.7 L), where a
/// chain whose only joint sits at mid-length cannot reach past about half its length
/// sideways and stops part way along the drive; `eval` judges the cases before it and names
/// the drive and the fraction reached.
#[test]
fn eval_of_a_mechanism_model_that_stops_part_way_reports_how_far() {
    let dir = common::Scratch::new("study-partial");
    let scene = dir.write("deep.toml", &common::driven_cantilever_pushed_deep());
    let v = common::json(&common::prbfit(&[
        "eval",
        "--scene",
        &scene,
        "--prb",
        "0.5,inf,inf; 0.5,2.0,inf",
        "--json",
    ]));
    let unfollowed = v["unfollowed"].as_array().unwrap();
    assert_eq!(unfollowed.len(), 1, "{v}");
    assert_eq!(unfollowed[0]["path"], 1);
    let reached = v["cases"].as_array().unwrap().len();
    assert!((1..8).contains(&reached), "{v}");
    let fraction = unfollowed[0]["fraction"].as_f64().unwrap();
    assert!((fraction - reached as f64 / 8.0).abs() < 1e-12, "{v}");
    assert!(!unfollowed[0]["reason"].as_str().unwrap().is_empty());
    assert_eq!(v["meets_targets"], false);
    assert!(v["max_force_err"].as_f64().unwrap().is_finite());
}

/// A mechanism's truth is as cancellable as a beam's: a cancelled token stops the exact
/// mechanism's drive paths (between cases) and the `auto` effects decision made on them,
/// where both used to run to the end whatever the token said.
#[test]
fn a_cancelled_mechanism_truth_and_its_effects_decision_stop() {
    use prbfit::mech::{exact, MechError};
    use prbfit::study::{resolve_effects, EffectsError};

    let stage = scene("parallel-stage");
    let mechanism = stage.mechanism.clone().unwrap();
    let cancel = CancelToken::new();
    let solver = exact::solver(&mechanism, Resolution::default()).unwrap();
    // Not cancelled: the drives are followed.
    let drive = mechanism.drive_path(&mechanism.drives[0]);
    assert!(!solver.solve_path(&drive, 1).unwrap().is_empty());
    cancel.cancel();
    let solver = solver.with_cancel(&cancel);
    assert!(matches!(
        solver.solve_path(&drive, 1),
        Err(MechError::Cancelled)
    ));

    let mut auto = stage.clone();
    for f in &mut auto.mechanism.as_mut().unwrap().flexures {
        f.beam.effects = EffectsChoice::Auto;
    }
    match resolve_effects(&auto, Resolution::default(), &cancel) {
        Err(EffectsError::Mechanism {
            source: MechError::Cancelled,
            ..
        }) => {}
        other => panic!(
            "expected a cancelled decision, got {:?}",
            other.map(|r| r.1)
        ),
    }
    assert!(matches!(
        Study::solve(
            &auto,
            Sampling::Fidelity(Fidelity::Draft),
            &cancel,
            &mut |_, _, _| {}
        ),
        Err(prbfit::study::StudyError::Cancelled)
    ));
}

/// The modes about every case stop when cancelled (the Python module's Ctrl-C, the CLI's):
/// between equilibria, and inside each model's following of the drives, where a parallel
/// stage of 2 x 10000 cases used to run its 9 s to the end whatever the token said.
#[test]
fn cancelled_modes_and_model_following_stop() {
    use prbfit::mech::{prb, MechError};
    use prbfit::study::modes::{Equilibria, StudyModesError};

    let mut stage = scene("parallel-stage");
    stage.beam.density = Some(7850.0);
    for f in &mut stage.mechanism.as_mut().unwrap().flexures {
        f.beam.density = Some(7850.0);
    }
    let study = Study::as_given(&stage, Sampling::Fidelity(Fidelity::Draft)).unwrap();
    let su = prbfit::prb::published::by_name("su-3r").unwrap().prb;
    let mechanism = study.mechanism();
    // Not cancelled: every drive followed, and the modes found about every case.
    let followed = prb::follow(mechanism, &su, 1e-9, &CancelToken::new());
    assert!(followed.failures.iter().all(Option::is_none));
    assert!(followed.drives.iter().all(|d| !d.is_empty()));
    let all = study
        .modes(
            std::slice::from_ref(&su),
            Equilibria::Cases,
            2,
            &CancelToken::new(),
        )
        .unwrap();
    assert_eq!(all.len(), study.case_count());

    let cancel = CancelToken::new();
    cancel.cancel();
    let followed = prb::follow(mechanism, &su, 1e-9, &cancel);
    assert!(followed
        .failures
        .iter()
        .all(|f| matches!(f, Some(MechError::Cancelled))));
    assert!(followed.drives.iter().all(Vec::is_empty));
    assert!(matches!(
        study.modes(std::slice::from_ref(&su), Equilibria::Cases, 2, &cancel),
        Err(StudyModesError::Cancelled)
    ));
}
