//! The reader's tests: scenes read, written and read again; bad files named by line and
//! key; and the rules applied the same to a scene read from a file and one built or edited
//! in code.
#![allow(clippy::unwrap_used)]

use crate::prb::PrbMatrix;
use crate::scene::{Attach, Coordinate, Drive, RuleError, Scene, SceneError, DEFAULT_SCENE_TOML};

#[test]
fn toml_round_trip() {
    let mut scene = Scene::builtin();
    let again = Scene::from_toml_str(&scene.to_toml(), "round trip").unwrap();
    assert_eq!(scene, again);
    // With a model, fixed cells and inf included.
    scene.prb = Some(
        PrbMatrix::parse("0.1!,inf,inf; 0.35,3.51,inf; 0.4,2.99!,inf; 0.15,2.58,1e3").unwrap(),
    );
    let text = scene.to_toml();
    assert!(text.contains("[prb]\nmatrix = \"0.1!,inf,inf;"), "{text}");
    let again = Scene::from_toml_str(&text, "round trip").unwrap();
    assert_eq!(scene, again);
}

const SLIDER_CRANK: &str = r#"
name = "slider-crank"
[beam]
length = 0.05
width = 0.01
thickness = 0.0005
youngs_modulus = 200e9
poisson_ratio = 0.3
effects = "none"
[[flexures]]
root = [0.0, 0.0]
angle_deg = 0.0
attach = "link"
[stage]
point = [0.07, -0.02]
[[drives]]
dx = 0.0
dy = 0.01
dphi = 0.0
steps = 10
[accuracy]
max_force_err = 0.03
"#;

/// A mechanism whose truth is data: no [[drives]] (the rows are the drives), and it saves
/// as it was read; [[drives]] beside [truth] are refused at their line.
#[test]
fn mechanism_data_scenes_read_and_round_trip() {
    let start = SLIDER_CRANK.find("[[drives]]").unwrap();
    let end = SLIDER_CRANK.find("[accuracy]").unwrap();
    let text = format!(
        "{}[truth]\ndata = \"rig.csv\"\n\n{}",
        &SLIDER_CRANK[..start],
        &SLIDER_CRANK[end..]
    );
    let scene = Scene::from_toml_str(&text, "rig.toml").unwrap();
    assert!(scene.mechanism.as_ref().unwrap().drives.is_empty());
    assert_eq!(scene.truth.as_ref().unwrap().file, "rig.csv");
    let saved = scene.to_toml();
    assert!(
        saved.contains("[truth]") && !saved.contains("[[drives]]"),
        "{saved}"
    );
    assert_eq!(Scene::from_toml_str(&saved, "again").unwrap(), scene);
    let both = SLIDER_CRANK.replace("[accuracy]", "[truth]\ndata = \"rig.csv\"\n[accuracy]");
    let e = Scene::from_toml_str(&both, "both.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("drives"), "{e}");
    assert!(e.line.is_some(), "{e}");
}

#[test]
fn mechanism_scenes_read_and_round_trip() {
    let scene = Scene::from_toml_str(SLIDER_CRANK, "sc.toml").unwrap();
    let m = scene.mechanism.as_ref().unwrap();
    assert_eq!(m.flexures.len(), 1);
    assert_eq!(m.flexures[0].attach, Attach::Link { to: [0.07, -0.02] });
    assert_eq!(m.stage_point, [0.07, -0.02]);
    assert_eq!(
        m.drives[0].coordinates,
        [
            Coordinate::Prescribed(0.0),
            Coordinate::Prescribed(0.01),
            Coordinate::Prescribed(0.0)
        ]
    );
    assert!(scene.loads.is_empty());
    assert_eq!(scene.accuracy.max_force_err, 0.03);
    assert_eq!(scene.validate(), Ok(()));
    let again = Scene::from_toml_str(&scene.to_toml(), "again").unwrap();
    assert_eq!(again, scene);
    // dy = 0.01 m is 0.2 L; a drive load of 1 N is alpha = F L^2 / (E I0).
    let nd = m.nondimensional(&m.drives[0]);
    assert!((nd[1].value() - 0.2).abs() < 1e-15);
}

#[test]
fn bad_mechanisms_name_their_line_and_key() {
    let cases = [
        (
            "dy = 0.01",
            "dy = 0.01\nfy = 2.0",
            "drives[1].dy",
            "not both",
        ),
        (
            "attach = \"link\"",
            "attach = \"glued\"",
            "flexures[1].attach",
            "glued",
        ),
        (
            "point = [0.07, -0.02]",
            "point = [0.05, 0.0]",
            "flexures[1].link_to",
            "zero length",
        ),
        ("steps = 10", "steps = 0", "drives[1].steps", "1 to"),
        (
            "attach = \"link\"",
            "attach = \"link\"\n[[flexures]]\nroot = [0.0, 0.0]\nattach = \"clamped\"",
            "flexures[2]",
            "overlap",
        ),
    ];
    for (from, to, key, words) in cases {
        let text = SLIDER_CRANK.replacen(from, to, 1);
        let e = Scene::from_toml_str(&text, "sc.toml").unwrap_err();
        assert_eq!(e.key.as_deref(), Some(key), "{e}");
        assert!(e.line.is_some(), "{e}");
        assert!(e.to_string().contains(words), "{e}");
    }
    // A mechanism with [[loads]], and drives without flexures.
    let both = format!("{SLIDER_CRANK}\n[[loads]]\nalpha_y = 1.0\n");
    let e = Scene::from_toml_str(&both, "sc.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("loads"), "{e}");
    let orphan = format!("{DEFAULT_SCENE_TOML}\n[[drives]]\ndy = 0.01\n");
    let e = Scene::from_toml_str(&orphan, "d.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("flexures"), "{e}");
}

/// `none` and `all` are whole settings: in a list beside effects they are refused as such
/// (the message called `none` unknown while listing it among the names it expected).
#[test]
fn none_and_all_stand_alone() {
    for word in ["none", "all"] {
        let text = DEFAULT_SCENE_TOML.replacen(
            "effects = \"auto\"",
            &format!("effects = [\"{word}\", \"shear\"]"),
            1,
        );
        let e = read_error(&text);
        assert_eq!(e.key.as_deref(), Some("beam.effects"), "{e}");
        assert!(e.message.contains(&format!("`{word}` stands alone")), "{e}");
    }
}

/// A point is exactly `[x, y]`: a longer array is refused at its line, not cut to its first
/// two numbers (serde's arrays drop the rest), like a shorter one.
#[test]
fn a_point_of_other_than_two_numbers_is_refused_at_its_line() {
    for (from, to) in [
        ("root = [0.0, 0.0]", "root = [0.0, 0.0, 5.0]"),
        ("root = [0.0, 0.0]", "root = [0.0]"),
        ("point = [0.07, -0.02]", "point = [0.07, -0.02, 99.0, 1.0]"),
        (
            "attach = \"link\"",
            "attach = \"link\"\nlink_to = [0.07, -0.02, 0.0]",
        ),
    ] {
        let text = SLIDER_CRANK.replacen(from, to, 1);
        let e = read_error(&text);
        let last = to.lines().last().unwrap();
        let line = text.lines().position(|l| l == last).unwrap() + 1;
        assert_eq!(e.line, Some(line), "{to}: {e}");
        assert!(
            e.message.contains("expected an array of length 2"),
            "{to}: {e}"
        );
    }
}

#[test]
fn a_bad_prb_matrix_names_its_line_and_cell() {
    let text = format!(
        "{}\n[prb]\nmatrix = \"0.5,inf,inf; 0.6,2,inf\"\n",
        DEFAULT_SCENE_TOML
    );
    let e = Scene::from_toml_str(&text, "s.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("prb.matrix"));
    assert_eq!(e.line, Some(DEFAULT_SCENE_TOML.lines().count() + 3));
    assert!(e.message.contains("sum to 1"), "{e}");
}

/// The reader's error for `text`, which must name a line.
fn read_error(text: &str) -> SceneError {
    let e = Scene::from_toml_str(text, "s.toml").unwrap_err();
    assert!(e.line.is_some(), "no line: {e}");
    e
}

/// A file's error is the rule's: the same key and the same message, placed at a line.
fn same(read: &SceneError, rule: &RuleError) {
    assert_eq!(
        read.key.as_deref(),
        Some(rule.key.as_str()),
        "{read} / {rule}"
    );
    assert_eq!(read.message, rule.message, "{read} / {rule}");
}

/// Each mechanism rule says the same whether the mechanism comes from a file (at the line of
/// its key) or is built in code ([`crate::scene::Mechanism::validate`], no line), and a
/// scene holding the bad mechanism is refused by [`Scene::validate`] with that error.
#[test]
fn mechanism_rules_are_the_same_from_a_file_and_from_code() {
    let good = Scene::from_toml_str(SLIDER_CRANK, "sc.toml").unwrap();
    let m = good.mechanism.clone().unwrap();
    let link = "attach = \"link\"";
    type Edit = fn(&mut crate::scene::Mechanism);
    let cases: [(&str, String, Edit, &str); 7] = [
        (
            link,
            format!("{link}\nthickness = -0.0005"),
            |m| m.flexures[0].beam.thickness = -0.0005,
            "flexures[1].thickness",
        ),
        (
            "root = [0.0, 0.0]",
            "root = [0.0, inf]".into(),
            |m| m.flexures[0].root[1] = f64::INFINITY,
            "flexures[1].root",
        ),
        (
            link,
            format!("{link}\nlink_to = [0.05, 0.0]"),
            |m| m.flexures[0].attach = Attach::Link { to: [0.05, 0.0] },
            "flexures[1].link_to",
        ),
        (
            link,
            format!("{link}\n[[flexures]]\nroot = [0.0, 0.0]\nattach = \"clamped\""),
            |m| {
                let twin = crate::scene::Flexure {
                    attach: Attach::Clamped,
                    ..m.flexures[0]
                };
                m.flexures.push(twin);
            },
            "flexures[2]",
        ),
        (
            "dy = 0.01",
            "dy = 0.0".into(),
            |m| m.drives[0].coordinates[1] = Coordinate::Prescribed(0.0),
            "drives[1]",
        ),
        (
            "dy = 0.01",
            "dy = nan".into(),
            |m| m.drives[0].coordinates[1] = Coordinate::Prescribed(f64::NAN),
            "drives[1].dy",
        ),
        (
            "steps = 10",
            "steps = 0".into(),
            |m| m.drives[0].steps = 0,
            "drives[1].steps",
        ),
    ];
    for (from, to, edit, key) in cases {
        let text = SLIDER_CRANK.replacen(from, &to, 1);
        assert_ne!(text, SLIDER_CRANK);
        let mut bad = m.clone();
        edit(&mut bad);
        let rule = bad.validate().unwrap_err();
        assert_eq!(rule.key, key, "{rule}");
        same(&read_error(&text), &rule);
        let mut scene = good.clone();
        scene.mechanism = Some(bad);
        assert_eq!(scene.validate(), Err(rule.in_scene(&scene.name)));
    }
    // A flexure or a drive on its own names its own keys, which a mechanism puts in place.
    let mut f = m.flexures[0];
    f.beam.thickness = -0.0005;
    let e = f.validate().unwrap_err();
    assert_eq!(
        e.to_string(),
        "thickness: must be a finite number > 0, got -0.0005"
    );
    let nowhere = Drive::proportional([Coordinate::Loaded(0.0); 3], 3);
    assert_eq!(nowhere.validate().unwrap_err().key, "");
    // No drives: no line to name.
    let mut none = m;
    none.drives.clear();
    assert_eq!(none.validate().unwrap_err().key, "drives");
}

/// The beam's, the load paths' and the targets' rules: the same from a file and from code.
#[test]
fn scene_rules_are_the_same_from_a_file_and_from_code() {
    let good = Scene::builtin();
    type Edit = fn(&mut Scene);
    let cases: [(&str, &str, Edit, &str); 6] = [
        (
            "thickness = 0.0005",
            "thickness = -0.0005",
            |s| s.beam.thickness = -0.0005,
            "beam.thickness",
        ),
        (
            "length = 0.05 ",
            "length = 0.0001 ",
            |s| s.beam.length = 0.0001,
            "beam.thickness",
        ),
        (
            "effects = \"auto\"",
            "effects = [\"poisson\"]",
            |s| {
                let mut e = crate::beam::Effects::NONE;
                e.poisson = true;
                s.beam.effects = crate::scene::EffectsChoice::Fixed(e);
            },
            "beam.effects",
        ),
        (
            "steps = 5",
            "steps = 0",
            |s| s.loads[0].steps = 0,
            "loads[1].steps",
        ),
        (
            "alpha_y = 5.0",
            "alpha_y = 0.0",
            |s| s.loads[0].end.alpha_y = 0.0,
            "loads[1]",
        ),
        (
            "max_ang_err = 0.02",
            "max_ang_err = -1",
            |s| s.accuracy.max_ang_err = -1.0,
            "accuracy.max_ang_err",
        ),
    ];
    for (from, to, edit, key) in cases {
        let text = DEFAULT_SCENE_TOML.replacen(from, to, 1);
        assert_ne!(text, DEFAULT_SCENE_TOML, "{from}");
        let mut bad = good.clone();
        edit(&mut bad);
        let rule = bad.check_rules().unwrap_err();
        assert_eq!(rule.key, key, "{rule}");
        same(&read_error(&text), &rule);
    }
}

/// The dynamics keys (DESIGN §10) read, save and read again; a bad value is refused at its
/// line naming its key, by the same rule as in code; each body table only in its kind of
/// scene.
#[test]
fn dynamics_keys_read_and_round_trip() {
    let text = DEFAULT_SCENE_TOML.replacen(
        "poisson_ratio = 0.3",
        "poisson_ratio = 0.3\ndensity = 7850.0",
        1,
    ) + "\n[tip]\nmass = 0.002\ninertia = 1e-7\n";
    let text = text.replacen(
        "angle_weight = 1.0",
        "angle_weight = 1.0\nmodes = 3\nfrequency_weight = 0.5",
        1,
    );
    let text = text.replacen(
        "max_ang_err = 0.02",
        "max_ang_err = 0.02\nmax_freq_err = 0.02",
        1,
    );
    let scene = Scene::from_toml_str(&text, "dyn.toml").unwrap();
    assert_eq!(scene.beam.density, Some(7850.0));
    assert_eq!((scene.body.mass, scene.body.inertia), (0.002, 1e-7));
    assert_eq!((scene.fit.modes, scene.fit.frequency_weight), (3, 0.5));
    assert_eq!(scene.accuracy.max_freq_err, 0.02);
    let again = Scene::from_toml_str(&scene.to_toml(), "again").unwrap();
    assert_eq!(again, scene);
    // Defaults: no density, no body, statics only, 1 % on the frequencies.
    let plain = Scene::builtin();
    assert_eq!(plain.beam.density, None);
    assert!(plain.body.is_none());
    assert_eq!((plain.fit.modes, plain.fit.frequency_weight), (0, 1.0));
    assert_eq!(plain.accuracy.max_freq_err, 0.01);

    type Edit = fn(&mut Scene);
    let cases: [(&str, &str, Edit, &str); 4] = [
        (
            "density = 7850.0",
            "density = -1.0",
            |s| s.beam.density = Some(-1.0),
            "beam.density",
        ),
        (
            "mass = 0.002",
            "mass = nan",
            |s| s.body.mass = f64::NAN,
            "tip.mass",
        ),
        (
            "inertia = 1e-7",
            "inertia = -1e-7",
            |s| s.body.inertia = -1e-7,
            "tip.inertia",
        ),
        (
            "frequency_weight = 0.5",
            "frequency_weight = -0.5",
            |s| s.fit.frequency_weight = -0.5,
            "fit.frequency_weight",
        ),
    ];
    for (from, to, edit, key) in cases {
        let bad_text = text.replacen(from, to, 1);
        assert_ne!(bad_text, text, "{from}");
        let mut bad = scene.clone();
        edit(&mut bad);
        let rule = bad.check_rules().unwrap_err();
        assert_eq!(rule.key, key, "{rule}");
        same(&read_error(&bad_text), &rule);
    }
    let e = read_error(&text.replacen("modes = 3", "modes = -2", 1));
    assert_eq!(e.key.as_deref(), Some("fit.modes"));
    // A dynamic fit without the beam's density says to add it (DESIGN §10).
    let e = read_error(&text.replacen("density = 7850.0\n", "", 1));
    assert_eq!(e.key.as_deref(), Some("fit.modes"));
    assert!(e.to_string().contains("add `density"), "{e}");
    // A mechanism's body is its stage's; [tip] there is refused.
    let mech = SLIDER_CRANK.replacen(
        "point = [0.07, -0.02]",
        "point = [0.07, -0.02]\nmass = 0.1\ninertia = 2e-5",
        1,
    );
    let m = Scene::from_toml_str(&mech, "m.toml").unwrap();
    assert_eq!((m.body.mass, m.body.inertia), (0.1, 2e-5));
    assert_eq!(Scene::from_toml_str(&m.to_toml(), "again").unwrap(), m);
    let e = read_error(&mech.replacen("mass = 0.1", "mass = -0.1", 1));
    assert_eq!(e.key.as_deref(), Some("stage.mass"));
    let e = read_error(&(SLIDER_CRANK.to_string() + "[tip]\nmass = 1.0\n"));
    assert_eq!(e.key.as_deref(), Some("tip"));
}
