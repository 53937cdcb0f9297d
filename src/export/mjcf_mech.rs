//! MuJoCo MJCF of a whole PRB mechanism (DESIGN §8): every flexure replaced by the PRB
//! matrix scaled to it, the rigid stage, the couplers, the loop closures and the drive, in SI
//! units. Verified in MuJoCo by `tests/mujoco_mech.rs`: driven along the scene's drive paths
//! and damped to rest, the stage pose and the drive's reaction match `prbfit eval` on the
//! same scene (pose to 1e-6 L, reaction to 1e-4 of its largest value).
//!
//! # What the file holds
//! - Flexure `i` is the PRB chain of the single-chain MJCF export with every name prefixed
//!   `f{i}_` (bodies `f{i}_segment{n}`, spring joints `f{i}_theta{n}`, `f{i}_delta{n}`),
//!   clamped to the world at its `root`, turned by its `angle` about +z, its springs the
//!   matrix scaled to *that* flexure's `L`, `E I0` and `E A0` exactly as the PRB mechanism
//!   solver scales it (`K_theta = k_theta E I0 / L`, `K_ex = k_ex E A0 / L`, lengths
//!   `gamma L`; `springref = 0`). A site `f{i}_tip` marks its free end.
//! - The stage is the body `stage` at the stage point `P` with three joints in this order:
//!   `stage_x`, `stage_y` (slides along world x and y, m) and `stage_phi` (a hinge about +z
//!   through `P`, rad), so that their positions *are* the stage pose `(dx, dy, dphi)` of
//!   DESIGN §8 and their generalized forces are the load at `P` (`Fx`, `Fy`, `Mz`). The site
//!   `stage` marks `P`.
//! - A clamped tip is a `weld` equality between the flexure's last body and the stage; a
//!   pinned tip a `connect` at the tip; a coupler (`link`) the body `f{i}_coupler` hinged at
//!   the tip (joint `f{i}_pin`, no spring) whose far end is a `connect` onto the stage.
//!   Every closure holds in the unloaded pose the file is written in.
//! - The drive: a loaded coordinate is a generalized force on its stage joint
//!   (`qfrc_applied`); a prescribed one is the equality `drive_x`, `drive_y` or `drive_phi`, a
//!   `joint` equality that holds the stage joint at `polycoef[0]` (m or rad, set at run time
//!   through `eq_data`). Its reaction is that equality's constraint force, read from
//!   `efc_force` (times its row of `efc_J`, which is +-1 on the stage joint). The three drive
//!   equalities are always written, active for the coordinates drive 1 prescribes.
//!
//! # Stiff closures
//! MuJoCo's constraints are soft: at rest an equality is violated by
//! `r = (1 - d) a0 / (d k)` where `a0` is the acceleration the springs would give the
//! constraint, `d` the impedance and `k = d / (d_max^2 tau^2 zeta^2)` the reference stiffness
//! from `solref = (tau, zeta)`. The file asks for the stiffest MuJoCo allows: `d = 0.9999`
//! (MuJoCo's largest impedance) everywhere (`solimp = "0.9999 0.9999 0.001 0.5 2"`), and
//! `tau` = two time steps (the smallest `tau` MuJoCo accepts without disabling its `refsafe`
//! check), critically damped. The time step is 1/100 of `1 / omega_max`
//! ([`STEP_FRACTION`]; `omega_max` the highest natural frequency of any flexure's chain as
//! written, clamped at its root and free at its tip, which bounds the whole mechanism's:
//! [`time_step`]), so a closure settles about
//! 50 times faster than any spring moves and `r` is about `1e-4 (0.02 / omega_max)^2 a0`,
//! i.e. `4e-8` of `a0 / omega_max^2`, the springs' own deflection scale. The largest is a
//! weld's twist under the tip moment (the last link's rotational inertia is the smallest):
//! `tests/mujoco_mech.rs` measures at most 1.2e-8 rad of twist, 4.7e-9 L of gap and a
//! stage pose within 4.4e-9 L of prbfit's (with twice this time step, 4 times more: `r`
//! goes with its square; the time step from each spring over the inertia beyond it, which
//! underestimates `omega_max`, gave 3e-8 rad and 1.1e-8 L). Forces at rest are exact
//! whatever the softness (they balance the springs at the pose reached), so the reactions
//! agree to 5.4e-8. The time step's cost is the settling: a few 1e5 to 1.2e6 steps per case
//! (seconds). Stiff closures also mean a drive
//! target must move in small steps: a jump asks for accelerations past MuJoCo's `1e10`
//! guard, which resets the simulation (the check moves it every 10 steps). The integrator is
//! `implicitfast`;
//! gravity and contacts are off. Masses are the matrix's mus of each flexure's `rho A0 L`
//! (DESIGN §10, [`super::chain`]), the stage's the scene's `[stage] mass` and `inertia` (flexure
//! 1's mass when it gives none); couplers are boxes of the density (prbfit's modes take
//! them massless: a coupler's mass is a difference between the two).

use std::fmt::Write as _;

use crate::prb::PrbMatrix;
use crate::scene::{Attach, Body, Coordinate, Mechanism};

use super::chain::{g, ident, Chain};
pub use super::chain::{time_step, STEP_FRACTION};
use super::mjcf::{write_chain, ChainPlacement};

/// The impedance every equality asks for (MuJoCo clamps larger values to this).
pub const IMPEDANCE: f64 = 0.9999;
/// The closures' time constant in time steps (MuJoCo's `refsafe` lower limit).
pub const CLOSURE_STEPS: f64 = 2.0;

/// The names of the stage joints and of the drive equalities on them, per coordinate.
pub const STAGE_JOINTS: [(&str, &str); 3] = [
    ("stage_x", "drive_x"),
    ("stage_y", "drive_y"),
    ("stage_phi", "drive_phi"),
];

/// The MJCF document of `mechanism` with `matrix` in place of every flexure, links of
/// `density` (kg/m^3), `comment` at the top.
/// `stage` is the stage's mass and inertia (`[stage]`); with neither given the stage gets
/// flexure 1's mass and that as a rod's inertia, since a simulator refuses a massless moving
/// body. `Err` for a model too stiff to simulate at a practical time step
/// ([`time_step`]).
pub fn write(
    mechanism: &Mechanism,
    matrix: &PrbMatrix,
    density: f64,
    stage: &Body,
    comment: &str,
) -> Result<String, super::ExportError> {
    let chains: Vec<Chain> = mechanism
        .flexures
        .iter()
        .map(|f| Chain::new(matrix, &f.beam, density, &Body::default()))
        .collect();
    let step = time_step(&chains, STEP_FRACTION)?;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<mujoco model=\"prbfit_mechanism_{}\">",
        ident(&matrix.topology())
    );
    let _ = writeln!(out, "  <!-- {comment} -->");
    let _ = writeln!(out, "  <compiler angle=\"radian\" autolimits=\"true\"/>");
    let _ = writeln!(
        out,
        "  <option gravity=\"0 0 0\" timestep=\"{}\" integrator=\"implicitfast\"/>",
        g(step)
    );
    let _ = writeln!(
        out,
        "  <default>\n    <geom contype=\"0\" conaffinity=\"0\"/>\n    \
         <equality solref=\"{} 1\" solimp=\"{imp} {imp} 0.001 0.5 2\"/>\n  </default>",
        g(CLOSURE_STEPS * step),
        imp = IMPEDANCE
    );
    let _ = writeln!(out, "  <worldbody>");
    for (i, (f, chain)) in mechanism.flexures.iter().zip(&chains).enumerate() {
        let prefix = format!("f{}_", i + 1);
        let placement = ChainPlacement {
            prefix: &prefix,
            root: f.root,
            angle: f.angle,
        };
        write_chain(
            &mut out,
            chain,
            &placement,
            "    ",
            |out, indent, length| {
                let _ = writeln!(
                    out,
                    "{indent}<site name=\"{prefix}tip\" pos=\"{} 0 0\"/>",
                    g(length)
                );
                if let Attach::Link { to } = f.attach {
                    let tip = f.tip();
                    let (dx, dy) = (to[0] - tip[0], to[1] - tip[1]);
                    let length_c = dx.hypot(dy);
                    // The coupler's frame: x along the unloaded coupler, in the flexure's frame.
                    let turn = dy.atan2(dx) - f.angle;
                    let (s, c) = (turn / 2.0).sin_cos();
                    let mass = density * length_c * f.beam.width * f.beam.thickness;
                    let inner = format!("{indent}  ");
                    let _ = writeln!(
                        out,
                        "{indent}<body name=\"{prefix}coupler\" pos=\"{} 0 0\" quat=\"{} 0 0 {}\">",
                        g(length),
                        g(c),
                        g(s)
                    );
                    let _ = writeln!(
                        out,
                        "{inner}<joint name=\"{prefix}pin\" type=\"hinge\" axis=\"0 0 1\"/>"
                    );
                    let _ = writeln!(
                    out,
                    "{inner}<geom name=\"{prefix}coupler\" type=\"box\" pos=\"{} 0 0\" size=\"{} {} {}\" mass=\"{}\"/>",
                    g(length_c / 2.0),
                    g(length_c / 2.0),
                    g(f.beam.thickness / 2.0),
                    g(f.beam.width / 2.0),
                    g(mass)
                );
                    let _ = writeln!(
                        out,
                        "{inner}<site name=\"{prefix}coupler_end\" pos=\"{} 0 0\"/>",
                        g(length_c)
                    );
                    let _ = writeln!(out, "{indent}</body>");
                }
            },
        );
    }
    write_stage(&mut out, mechanism, density, stage);
    let _ = writeln!(out, "  </worldbody>");
    write_equalities(&mut out, mechanism, &chains);
    let _ = writeln!(out, "</mujoco>");
    Ok(out)
}

/// The stage body: three joints whose positions are the stage pose; the scene's stage mass
/// and inertia (about P), or flexure 1's mass when it gives neither. A part left at 0 gets
/// [`super::chain::MASS_FLOOR`] of flexure 1's: MuJoCo refuses a massless moving body.
fn write_stage(out: &mut String, mechanism: &Mechanism, density: f64, stage: &Body) {
    let [px, py] = mechanism.stage_point;
    let b = mechanism.flexures.first().map(|f| f.beam);
    let (mass, inertia) = b.map_or((1.0, 1.0), |b| {
        let m = density * b.length * b.width * b.thickness;
        let i = m * b.length * b.length / 12.0;
        if stage.is_none() {
            (m, i)
        } else {
            (
                stage.mass.max(super::chain::MASS_FLOOR * m),
                stage.inertia.max(super::chain::MASS_FLOOR * i),
            )
        }
    });
    let _ = writeln!(
        out,
        "    <body name=\"stage\" pos=\"{} {} 0\">",
        g(px),
        g(py)
    );
    for ((joint, _), axis) in STAGE_JOINTS.iter().zip(["1 0 0", "0 1 0", "0 0 1"]) {
        let kind = if *joint == "stage_phi" {
            "hinge"
        } else {
            "slide"
        };
        let _ = writeln!(
            out,
            "      <joint name=\"{joint}\" type=\"{kind}\" axis=\"{axis}\"/>"
        );
    }
    let _ = writeln!(
        out,
        "      <inertial pos=\"0 0 0\" mass=\"{}\" diaginertia=\"{i} {i} {i}\"/>",
        g(mass),
        i = g(inertia)
    );
    let _ = writeln!(out, "      <site name=\"stage\" pos=\"0 0 0\"/>");
    let _ = writeln!(out, "    </body>");
}

/// The loop closures (one per flexure) and the three drive equalities.
fn write_equalities(out: &mut String, mechanism: &Mechanism, chains: &[Chain]) {
    let _ = writeln!(out, "  <equality>");
    let p = mechanism.stage_point;
    for (i, (f, chain)) in mechanism.flexures.iter().zip(chains).enumerate() {
        let n = i + 1;
        let last = chain.segments.last();
        let body = last.map_or_else(String::new, |s| format!("f{n}_{}", s.link()));
        let tip_x = last.map_or(0.0, |s| s.length);
        let _ = match f.attach {
            Attach::Clamped => {
                // The weld point is the tip, given in the stage's frame.
                let tip = f.tip();
                writeln!(
                    out,
                    "    <weld name=\"f{n}_clamp\" body1=\"{body}\" body2=\"stage\" anchor=\"{} {} 0\"/>",
                    g(tip[0] - p[0]),
                    g(tip[1] - p[1])
                )
            }
            Attach::Pinned => writeln!(
                out,
                "    <connect name=\"f{n}_pin\" body1=\"{body}\" body2=\"stage\" anchor=\"{} 0 0\"/>",
                g(tip_x)
            ),
            Attach::Link { to } => {
                let tip = f.tip();
                writeln!(
                    out,
                    "    <connect name=\"f{n}_link\" body1=\"f{n}_coupler\" body2=\"stage\" anchor=\"{} 0 0\"/>",
                    g((to[0] - tip[0]).hypot(to[1] - tip[1]))
                )
            }
        };
    }
    let first = mechanism.drives.first().map(|d| d.coordinates);
    for (c, (joint, name)) in STAGE_JOINTS.iter().enumerate() {
        let active = first.is_some_and(|d| d[c].is_prescribed());
        let _ = writeln!(
            out,
            "    <joint name=\"{name}\" joint1=\"{joint}\" polycoef=\"0 0 0 0 0\" active=\"{active}\"/>"
        );
    }
    let _ = writeln!(out, "  </equality>");
}

/// How the header describes drive paths: each coordinate prescribed or loaded, SI.
pub fn describe_drives(mechanism: &Mechanism) -> String {
    let mut out = String::new();
    for (k, d) in mechanism.drives.iter().enumerate() {
        let parts: Vec<String> = d
            .coordinates
            .iter()
            .zip(crate::scene::COORDINATE_KEYS)
            .zip(["m", "m", "rad"])
            .zip(["N", "N", "N m"])
            .map(|(((c, (dk, lk)), du), lu)| match c {
                Coordinate::Prescribed(v) => format!("{dk} = {} {du} prescribed", g(*v)),
                Coordinate::Loaded(v) => format!("{lk} = {} {lu}", g(*v)),
            })
            .collect();
        let _ = write!(
            out,
            "{}drive {}: {}, {} steps",
            if k == 0 { "" } else { "; " },
            k + 1,
            parts.join(", "),
            d.steps
        );
    }
    out
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used, clippy::expect_used)] // tests: a failure should panic

    use super::*;
    use crate::export::chain::frequency_range;
    use crate::scene::{BeamSpec, Drive, EffectsChoice, Flexure};
    use roxmltree::{Document, Node};

    /// Three flexures of different sizes, directions and attachments (clamped, pinned, a
    /// coupler), drive 1 prescribing `dy` only.
    fn mixed() -> Mechanism {
        let beam = |length: f64, thickness: f64, youngs_modulus: f64| BeamSpec {
            length,
            width: 0.01,
            thickness,
            youngs_modulus,
            poisson_ratio: 0.3,
            shear_coefficient: None,
            density: None,
            effects: EffectsChoice::Auto,
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
                flexure([0.0, 0.03], 0.0, Attach::Clamped, beam(0.1, 0.001, 2e9)),
                flexure([0.0, -0.03], 10.0, Attach::Pinned, beam(0.12, 0.0008, 3e9)),
                flexure(
                    [0.12, 0.1],
                    -80.0,
                    Attach::Link { to: [0.09, 0.0] },
                    beam(0.08, 0.001, 2e9),
                ),
            ],
            stage_point: [0.1, 0.03],
            drives: vec![Drive::proportional(
                [
                    Coordinate::Loaded(1.0),
                    Coordinate::Prescribed(0.01),
                    Coordinate::Loaded(0.0),
                ],
                4,
            )],
        }
    }

    const SU_3R_EX: &str = "0.10,inf,inf; 0.35,3.51,40; 0.40,2.99,inf; 0.15,2.58,inf";

    fn numbers(s: &str) -> Vec<f64> {
        s.split_whitespace().map(|v| v.parse().unwrap()).collect()
    }

    /// A body's or site's planar pose `(x, y, angle)` in its parent's frame.
    fn local(n: Node) -> [f64; 3] {
        let p = n.attribute("pos").map_or(vec![0.0; 3], numbers);
        let angle = n.attribute("quat").map_or(0.0, |q| {
            let q = numbers(q);
            assert_eq!((q[1], q[2]), (0.0, 0.0), "a turn about z only");
            2.0 * q[3].atan2(q[0])
        });
        [p[0], p[1], angle]
    }

    /// `child` (in `parent`'s frame) in the world.
    fn compose(parent: [f64; 3], child: [f64; 3]) -> [f64; 3] {
        let (s, c) = parent[2].sin_cos();
        [
            parent[0] + c * child[0] - s * child[1],
            parent[1] + s * child[0] + c * child[1],
            parent[2] + child[2],
        ]
    }

    /// The world pose of the frame of `n` if it is a body, else of its body (the unloaded
    /// mechanism: joints at zero). roxmltree's ancestors start with the node itself.
    fn world(n: Node) -> [f64; 3] {
        n.ancestors()
            .filter(|a| a.has_tag_name("body"))
            .collect::<Vec<_>>()
            .into_iter()
            .rev()
            .fold([0.0; 3], |pose, b| compose(pose, local(b)))
    }

    fn named<'a, 'i>(doc: &'a Document<'i>, tag: &str, name: &str) -> Node<'a, 'i> {
        doc.descendants()
            .find(|n| n.has_tag_name(tag) && n.attribute("name") == Some(name))
            .unwrap_or_else(|| panic!("no {tag} named {name}"))
    }

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-12
    }

    #[test]
    fn every_loop_closes_in_the_unloaded_pose_it_is_written_in() {
        let m = mixed();
        let matrix = PrbMatrix::parse(SU_3R_EX).unwrap();
        let text = write(&m, &matrix, 1000.0, &Body::default(), "test").unwrap();
        let doc = Document::parse(&text).expect("well-formed XML");
        let site = |name: &str| {
            let s = named(&doc, "site", name);
            let p = compose(world(s), local(s));
            [p[0], p[1]]
        };
        assert!(close(site("stage"), m.stage_point));
        for (i, f) in m.flexures.iter().enumerate() {
            let n = i + 1;
            assert!(close(site(&format!("f{n}_tip")), f.tip()), "flexure {n}");
            let first = named(&doc, "body", &format!("f{n}_segment1"));
            let pose = compose([0.0; 3], local(first));
            assert!((pose[2] - f.angle).abs() < 1e-12);
        }
        assert!(close(site("f3_coupler_end"), [0.09, 0.0]));
        // Each closure's anchor is where both of its bodies meet.
        let p = m.stage_point;
        let weld = named(&doc, "weld", "f1_clamp");
        let a = numbers(weld.attribute("anchor").unwrap());
        assert_eq!(weld.attribute("body2"), Some("stage"));
        assert!(close([p[0] + a[0], p[1] + a[1]], m.flexures[0].tip()));
        for (name, at) in [("f2_pin", m.flexures[1].tip()), ("f3_link", [0.09, 0.0])] {
            let c = named(&doc, "connect", name);
            let body1 = named(&doc, "body", c.attribute("body1").unwrap());
            let a = numbers(c.attribute("anchor").unwrap());
            let w = compose(world(body1), [a[0], a[1], 0.0]);
            assert!(close([w[0], w[1]], at), "{name}: {w:?} vs {at:?}");
        }
    }

    #[test]
    fn springs_are_scaled_to_each_flexure_and_the_drive_is_the_scenes() {
        let m = mixed();
        let matrix = PrbMatrix::parse(SU_3R_EX).unwrap();
        let text = write(&m, &matrix, 1000.0, &Body::default(), "test").unwrap();
        let doc = Document::parse(&text).unwrap();
        let count = |tag: &str| doc.descendants().filter(|n| n.has_tag_name(tag)).count();
        // 4 segments per flexure, one coupler, the stage.
        assert_eq!(count("body"), 3 * 4 + 1 + 1);
        // 3 hinges and 1 slide per flexure, the coupler's pin, 3 stage joints, 3 drive
        // equalities (also `joint` elements).
        assert_eq!(count("joint"), 3 * 4 + 1 + 3 + 3);
        assert_eq!((count("weld"), count("connect")), (1, 2));
        for (i, f) in m.flexures.iter().enumerate() {
            let b = &f.beam;
            let ei_l = b.youngs_modulus * b.second_moment() / b.length;
            let ea_l = b.youngs_modulus * b.area() / b.length;
            let stiffness = |name: String| {
                numbers(named(&doc, "joint", &name).attribute("stiffness").unwrap())[0]
            };
            let n = i + 1;
            let rel = |a: f64, e: f64| ((a - e) / e).abs() < 1e-14;
            assert!(rel(stiffness(format!("f{n}_theta2")), 3.51 * ei_l));
            assert!(rel(stiffness(format!("f{n}_theta4")), 2.58 * ei_l));
            assert!(rel(stiffness(format!("f{n}_delta2")), 40.0 * ea_l));
        }
        // Drive 1 prescribes dy alone.
        let active = |name: &str| named(&doc, "joint", name).attribute("active");
        assert_eq!(active("drive_x"), Some("false"));
        assert_eq!(active("drive_y"), Some("true"));
        assert_eq!(active("drive_phi"), Some("false"));
        assert_eq!(
            named(&doc, "joint", "drive_y").attribute("joint1"),
            Some("stage_y")
        );
        // The closures' time constant is two of the file's time steps.
        let step = numbers(
            doc.descendants()
                .find(|n| n.has_tag_name("option"))
                .unwrap()
                .attribute("timestep")
                .unwrap(),
        )[0];
        let solref = numbers(
            doc.descendants()
                .find(|n| n.has_tag_name("equality") && n.attribute("solref").is_some())
                .unwrap()
                .attribute("solref")
                .unwrap(),
        );
        assert!((solref[0] - CLOSURE_STEPS * step).abs() < 1e-12 * step);
        assert!(
            step > 0.0
                && step
                    == time_step(
                        &m.flexures
                            .iter()
                            .map(|f| Chain::new(&matrix, &f.beam, 1000.0, &Body::default()))
                            .collect::<Vec<_>>(),
                        STEP_FRACTION
                    )
                    .unwrap()
        );
    }

    #[test]
    fn the_time_step_follows_the_fastest_spring() {
        let m = mixed();
        let chains = |matrix: &str| -> Vec<Chain> {
            let matrix = PrbMatrix::parse(matrix).unwrap();
            m.flexures
                .iter()
                .map(|f| Chain::new(&matrix, &f.beam, 1000.0, &Body::default()))
                .collect()
        };
        // Four times the springs: half the time step.
        let soft = time_step(&chains("0.1,inf,inf; 0.9,2,inf"), STEP_FRACTION).unwrap();
        let stiff = time_step(&chains("0.1,inf,inf; 0.9,8,inf"), STEP_FRACTION).unwrap();
        assert!((soft / stiff - 2.0).abs() < 1e-12);
    }

    /// The mechanism's time step rests on Rayleigh's principle: the closures and the stage
    /// only lower the highest frequency below its flexures' free chains'. Checked on the
    /// parallel stage (Su's 3R, a stage of a flexure's mass, every coordinate loaded):
    /// prbfit's PRB mechanism modes, in SI, stay below the chains' highest frequency, so
    /// `omega dt <= STEP_FRACTION` for every one of them.
    #[test]
    fn the_mechanisms_frequencies_stay_below_its_free_chains() {
        let scene = crate::scene::Scene::from_toml_str(
            include_str!("../../assets/scenes/parallel-stage.toml"),
            "parallel-stage.toml",
        )
        .unwrap();
        let mech = scene.mechanism.unwrap();
        let matrix =
            PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf").unwrap();
        let rho = 7850.0;
        let chains: Vec<Chain> = mech
            .flexures
            .iter()
            .map(|f| Chain::new(&matrix, &f.beam, rho, &Body::default()))
            .collect();
        let dt = time_step(&chains, STEP_FRACTION).unwrap();
        let b = &mech.flexures[0].beam;
        let rho_a = rho * b.area();
        let unit = (b.youngs_modulus * b.second_moment() / (rho_a * b.length.powi(4))).sqrt();
        let stage = crate::prb::TipBody {
            mass: 1.0,
            inertia: 1.0 / 12.0,
        };
        let state = crate::mech::prb_modes::unloaded_state_held(&mech, &matrix, [false; 3]);
        let omegas = crate::mech::prb_modes::prb_modes(&mech, &matrix, &state, stage).unwrap();
        assert!(omegas.len() >= 3, "{omegas:?}");
        let highest = omegas.iter().fold(0.0_f64, |a, &w| a.max(w)) * unit;
        let chain_max = chains
            .iter()
            .filter_map(frequency_range)
            .fold(0.0_f64, |a, (_, hi)| a.max(hi));
        eprintln!(
            "{} PRB mechanism frequencies, highest {highest:.4e} rad/s; free chains' highest \
             {chain_max:.4e} rad/s",
            omegas.len()
        );
        assert!(highest <= chain_max, "{highest} vs {chain_max}");
        assert!(highest * dt <= STEP_FRACTION, "{}", highest * dt);
    }
}
