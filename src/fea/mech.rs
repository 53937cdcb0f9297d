//! FEA of whole mechanisms (DESIGN §13): every flexure of a mechanism scene meshed as the
//! cantilever is ([`super::deck`]), the stage a rigid body, one CalculiX analysis per drive
//! path with one `NLGEOM` step per case, read back as DESIGN §9's mechanism CSV.
//!
//! # The model
//! - **Flexures**: each a slab of C3D20R bricks in its own frame (root at its clamp, along
//!   its unloaded direction), placed in the scene's plane; its root face fixed (the clamp),
//!   its section model, taper and material as the cantilever's ([`super::Section`]). Flexure
//!   `i` has `round(n L_i / L_1)` bricks along it (at least 2), so every flexure's bricks
//!   are about as long as flexure 1's.
//! - **Stage**: a `*RIGID BODY` whose reference node sits at the stage point `P` and whose
//!   rotation node carries its rotation about z. Loads act there (`*CLOAD`: dead loads, as
//!   in §8); prescribed coordinates are `*BOUNDARY` values there, whose reactions (`RF`) are
//!   the drive's, read back in every case.
//! - **Joints**: a `clamped` tip face belongs to the stage's rigid body (tied). A `pinned`
//!   or `link` tip face is a rigid body of its own (reference node at the section's centre,
//!   rotation free: the hinge), joined to a node of the stage (at the unloaded tip for a
//!   pin, at `link_to` for a coupler) by stiff springs: a pin by a pair of springs along x
//!   and y between coincident nodes, a coupler by an axial spring (`SPRINGA`, along the line
//!   between its nodes as they move). Springs and not CalculiX's multi-point constraints:
//!   a constraint between two rigid bodies' nodes makes one body's reference node depend on
//!   another's, and ccx 2.20 then solves the motion but misreports the stage's reactions
//!   (measured: a pinned flexure under a stage force reported half the moment equilibrium
//!   requires). A joint's springs are [`JOINT_STIFFNESS`] times its flexure's `E I / L^3`
//!   stiff, so under a force `alpha E I / L^2` it stretches by `alpha / JOINT_STIFFNESS`
//!   of `L`: 1e-5 L at `alpha = 10`, a tenth of the default mesh's error or less. Stiffer
//!   springs were tried: at 1e4 times a brick's axial stiffness (about 1e10 `E I / L^3`)
//!   ccx 2.20 could not converge the slider-crank's first case (its residual test, relative
//!   to the mean force, cannot be met through a spring that stiff), and at 1e8 it needed
//!   four times the increments of 1e6.
//! - **Plane models** hold every node in its plane (the stage's and joints' reference nodes
//!   too); the **solid** models half the width with the symmetry plane at z = 0 for every
//!   flexure, so loads are halved and reactions doubled.
//! - **Steps**: one per case, from the previous case's loads and prescribed values to its
//!   own; each drive path a separate analysis from the unloaded state.
//!
//! A failed case keeps the cases before it: [`solve_mechanism`] returns them with the
//! failure (which drive, which case, ccx's last words), and [`mechanism_csv`] marks the
//! drive where it stopped.

use std::fmt::Write as _;
use std::time::Duration;

use serde::Serialize;

use super::deck::{material, modelled_width, node_set, Slab, STEP_HEAD};
use super::{dat, Ccx, CcxError, Mesh, MeshError, Section, Taper, MAX_BRICKS};
use crate::scene::{Attach, Coordinate, Drive, DrivePath, Mechanism, COORDINATE_KEYS};

/// The springs of a pin or a coupler are this many times as stiff as their flexure's
/// `E I / L^3` (of the modelled width).
pub const JOINT_STIFFNESS: f64 = 1e6;

/// The node sets the deck prints: the stage point and the stage's rotation node.
const STAGE_SET: &str = "NSTAGE";
const STAGE_ROT_SET: &str = "NSTAGEROT";

/// One case of a drive path as CalculiX solved it, SI.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MechFeaCase {
    /// The drive path, 1-based.
    pub path: usize,
    /// The case within its path, 1-based.
    pub case: usize,
    /// The drive's inputs `[x, y, phi]`, each of its coordinate's kind (m or N, rad or N m).
    pub drive: [f64; 3],
    /// The stage pose `[dx, dy, dphi]` of the stage point, m and rad.
    pub stage: [f64; 3],
    /// The load on the stage at its point `[Fx, Fy, Mz]`, N and N m: the given load, or the
    /// drive's reaction for a prescribed coordinate.
    pub stage_load: [f64; 3],
}

/// Where a drive path's analysis stopped.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MechFeaFailure {
    /// The drive path, 1-based.
    pub path: usize,
    /// The first case without a result, 1-based.
    pub case: usize,
    /// The path's cases.
    pub cases: usize,
    /// Why: CalculiX's message (its `*ERROR` line or the tail of its log).
    pub message: String,
}

/// Every drive path's cases, and where any stopped.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MechFeaRun {
    /// The cases solved, in path order.
    pub cases: Vec<MechFeaCase>,
    /// The paths that stopped before their end.
    pub failures: Vec<MechFeaFailure>,
    /// CalculiX's wall-clock seconds over all paths.
    pub ccx_seconds: f64,
}

/// Why a mechanism cannot be modelled as asked.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{key}: {message}")]
pub struct MechFeaError {
    /// The scene key or command-line option at fault.
    pub key: String,
    /// What is wrong.
    pub message: String,
}

/// The mesh of each flexure for density `n` (bricks along flexure 1): `round(n L_i / L_1)`
/// along flexure `i` (at least 2), through and across as [`Mesh::for_tapered_beam`] makes
/// them; all the flexures together at most [`MAX_BRICKS`].
pub fn flexure_meshes(
    mechanism: &Mechanism,
    n: u32,
    section: Section,
    taper: Taper,
) -> Result<Vec<Mesh>, MeshError> {
    let (l1, _) = mechanism.scale();
    let meshes = mechanism
        .flexures
        .iter()
        .map(|f| {
            let along = (f64::from(n) * f.beam.length / l1).round().max(2.0);
            let along = if n < 2 {
                n
            } else {
                along.min(f64::from(u32::MAX)) as u32
            };
            Mesh::for_tapered_beam(along, &f.beam, section, taper)
        })
        .collect::<Result<Vec<Mesh>, MeshError>>()?;
    let bricks: u128 = meshes.iter().map(Mesh::bricks).sum();
    if bricks > u128::from(MAX_BRICKS) {
        return Err(MeshError(format!(
            "density {n} makes {bricks} elements over the {} flexures, more than the \
             {MAX_BRICKS} allowed: choose a smaller density",
            meshes.len()
        )));
    }
    Ok(meshes)
}

/// A drive path's cases, SI, each coordinate of the drive's kind.
pub fn drive_cases(drive: &Drive) -> Vec<[Coordinate; 3]> {
    let path = DrivePath {
        end: drive.coordinates,
        steps: drive.steps.max(1),
        rows: drive.rows.clone(),
    };
    (1..=path.steps)
        .map(|k| path.at(f64::from(k) / f64::from(path.steps)))
        .collect()
}

/// Checks that one CSV can hold every drive path: every drive prescribes the same
/// coordinates (the file's columns name each coordinate's kind once).
pub fn check_drives(mechanism: &Mechanism) -> Result<(), MechFeaError> {
    let kinds = |d: &Drive| d.coordinates.map(|c| c.is_prescribed());
    let Some(first) = mechanism.drives.first().map(kinds) else {
        return Ok(());
    };
    for (i, d) in mechanism.drives.iter().enumerate().skip(1) {
        if kinds(d) != first {
            return Err(MechFeaError {
                key: format!("drives[{}]", i + 1),
                message: "prescribes other stage coordinates than drives[1]: the FEA's CSV \
                          (DESIGN §9) names each coordinate's kind once for all its paths, so \
                          every drive must prescribe the same ones; put this drive in a scene \
                          of its own"
                    .into(),
            });
        }
    }
    Ok(())
}

/// The deck of one drive path of `mechanism`: the flexures meshed by `meshes` (one per
/// flexure, [`flexure_meshes`]), the stage and its joints, and one `*STEP` per case of
/// `cases` (SI, [`drive_cases`]).
pub fn mechanism_deck(
    mechanism: &Mechanism,
    meshes: &[Mesh],
    section: Section,
    taper: Taper,
    cases: &[[Coordinate; 3]],
) -> String {
    let mut out = String::new();
    let share = match section {
        Section::Solid => 0.5,
        Section::PlaneStress | Section::PlaneStrain => 1.0,
    };
    let _ = writeln!(
        out,
        "** prbfit: {} model of a mechanism of {} flexures, the stage a rigid body with its \
         reference node at P = ({:e}, {:e}) m",
        section.name(),
        mechanism.flexures.len(),
        mechanism.stage_point[0],
        mechanism.stage_point[1]
    );
    if !taper.is_uniform() {
        let _ = writeln!(
            out,
            "** tapered: every flexure's thickness from t0 at its clamp to {taper} t0 at its tip"
        );
    }
    let _ = writeln!(out, "*HEADING\nprbfit mechanism");
    // The flexures' slabs, placed in the plane.
    let (mut nodes, mut elements) = (0, 0);
    let mut stage_members: Vec<usize> = Vec::new();
    let mut bending: Vec<f64> = Vec::new();
    for (i, (f, mesh)) in mechanism.flexures.iter().zip(meshes).enumerate() {
        let slab = Slab {
            beam: &f.beam,
            mesh,
            section,
            taper,
            nodes,
            elements,
        };
        let (s, c) = f.angle.sin_cos();
        let root = f.root;
        let _ = writeln!(
            out,
            "** flexure {}: root ({:e}, {:e}) m, {:.6} deg, {}",
            i + 1,
            root[0],
            root[1],
            f.angle.to_degrees(),
            match f.attach {
                Attach::Clamped => "clamped to the stage",
                Attach::Pinned => "pinned to the stage",
                Attach::Link { .. } => "joined to the stage by a coupler",
            }
        );
        let _ = writeln!(out, "*NODE");
        slab.write_nodes(&mut out, &|[x, y, z]| {
            [root[0] + c * x - s * y, root[1] + s * x + c * y, z]
        });
        let name = i + 1;
        slab.write_elements(&mut out, &format!("EF{name}"));
        let sets = slab.sets();
        node_set(&mut out, &format!("NROOT{name}"), &sets.root);
        node_set(&mut out, &format!("NPLANE{name}"), &sets.plane);
        node_set(&mut out, &format!("NTIP{name}"), &sets.tip);
        let (e, nu) = material(&f.beam, section);
        let _ = writeln!(
            out,
            "*MATERIAL, NAME=MF{name}\n*ELASTIC\n{e:.12e}, {nu:.12e}\n\
             *SOLID SECTION, ELSET=EF{name}, MATERIAL=MF{name}"
        );
        let (width, _) = modelled_width(&f.beam, section);
        let bending_stiffness = e * width * f.beam.thickness.powi(3) / 12.0 / f.beam.length.powi(3);
        if f.attach == Attach::Clamped {
            stage_members.extend(&sets.tip);
        }
        bending.push(bending_stiffness);
        nodes += slab.node_count();
        elements += slab.element_count();
    }
    // The stage's reference and rotation nodes, then per pin or coupler its tip's reference
    // and rotation nodes and the stage's node it is joined to.
    let p = mechanism.stage_point;
    let (stage_ref, stage_rot) = (nodes + 1, nodes + 2);
    let mut next = nodes + 2;
    let _ = writeln!(
        out,
        "*NODE\n{stage_ref}, {:.12e}, {:.12e}, 0\n{stage_rot}, {:.12e}, {:.12e}, 0",
        p[0], p[1], p[0], p[1]
    );
    struct Joint {
        flexure: usize,
        stiffness: f64,
        tip_ref: usize,
        tip_rot: usize,
        stage_node: usize,
        pin: bool,
    }
    let mut joints = Vec::new();
    for (i, f) in mechanism.flexures.iter().enumerate() {
        let (to, pin) = match f.attach {
            Attach::Clamped => continue,
            Attach::Pinned => (f.tip(), true),
            Attach::Link { to } => (to, false),
        };
        let tip = f.tip();
        let j = Joint {
            flexure: i + 1,
            stiffness: JOINT_STIFFNESS * bending[i],
            tip_ref: next + 1,
            tip_rot: next + 2,
            stage_node: next + 3,
            pin,
        };
        next += 3;
        let _ = writeln!(
            out,
            "{}, {:.12e}, {:.12e}, 0\n{}, {:.12e}, {:.12e}, 0\n{}, {:.12e}, {:.12e}, 0",
            j.tip_ref, tip[0], tip[1], j.tip_rot, tip[0], tip[1], j.stage_node, to[0], to[1]
        );
        stage_members.push(j.stage_node);
        joints.push(j);
    }
    for j in &joints {
        let (name, k) = (j.flexure, j.stiffness);
        let _ = writeln!(
            out,
            "*RIGID BODY, NSET=NTIP{name}, REF NODE={}, ROT NODE={}",
            j.tip_ref, j.tip_rot
        );
        elements += 1;
        if j.pin {
            let _ = writeln!(
                out,
                "*ELEMENT, TYPE=SPRING2, ELSET=EPINX{name}\n{elements}, {}, {}\n\
                 *SPRING, ELSET=EPINX{name}\n1, 1\n{k:.12e}",
                j.tip_ref, j.stage_node
            );
            elements += 1;
            let _ = writeln!(
                out,
                "*ELEMENT, TYPE=SPRING2, ELSET=EPINY{name}\n{elements}, {}, {}\n\
                 *SPRING, ELSET=EPINY{name}\n2, 2\n{k:.12e}",
                j.tip_ref, j.stage_node
            );
        } else {
            let _ = writeln!(
                out,
                "*ELEMENT, TYPE=SPRINGA, ELSET=ELINK{name}\n{elements}, {}, {}\n\
                 *SPRING, ELSET=ELINK{name}\n{k:.12e}",
                j.tip_ref, j.stage_node
            );
        }
    }
    node_set(&mut out, "NSTAGEBODY", &stage_members);
    node_set(&mut out, STAGE_SET, &[stage_ref]);
    node_set(&mut out, STAGE_ROT_SET, &[stage_rot]);
    let _ = writeln!(
        out,
        "*RIGID BODY, NSET=NSTAGEBODY, REF NODE={stage_ref}, ROT NODE={stage_rot}\n*BOUNDARY"
    );
    for i in 1..=mechanism.flexures.len() {
        let _ = writeln!(out, "NROOT{i}, 1, 3\nNPLANE{i}, 3, 3");
    }
    let _ = writeln!(out, "{stage_ref}, 3, 3\n{stage_rot}, 1, 2");
    for j in &joints {
        let _ = writeln!(out, "{}, 3, 3\n{}, 1, 2", j.tip_ref, j.tip_rot);
    }
    // The stage's three coordinates: the reference node's x and y, the rotation node's z.
    let dofs = [(stage_ref, 1), (stage_ref, 2), (stage_rot, 3)];
    for case in cases {
        let _ = write!(out, "{STEP_HEAD}");
        let prescribed: Vec<String> = case
            .iter()
            .zip(dofs)
            .filter_map(|(c, (node, dof))| match c {
                Coordinate::Prescribed(v) => Some(format!("{node}, {dof}, {dof}, {v:.12e}")),
                Coordinate::Loaded(_) => None,
            })
            .collect();
        if !prescribed.is_empty() {
            let _ = writeln!(out, "*BOUNDARY\n{}", prescribed.join("\n"));
        }
        let loaded: Vec<String> = case
            .iter()
            .zip(dofs)
            .filter_map(|(c, (node, dof))| match c {
                Coordinate::Loaded(v) => Some(format!("{node}, {dof}, {:.12e}", v * share)),
                Coordinate::Prescribed(_) => None,
            })
            .collect();
        if !loaded.is_empty() {
            let _ = writeln!(out, "*CLOAD\n{}", loaded.join("\n"));
        }
        let _ = writeln!(
            out,
            "*NODE PRINT, NSET={STAGE_SET}\nU, RF\n*NODE PRINT, NSET={STAGE_ROT_SET}\nU, RF\n\
             *END STEP"
        );
    }
    out
}

/// The deck of every drive path of `mechanism`.
pub fn mechanism_decks(
    mechanism: &Mechanism,
    meshes: &[Mesh],
    section: Section,
    taper: Taper,
) -> Vec<String> {
    mechanism
        .drives
        .iter()
        .map(|d| mechanism_deck(mechanism, meshes, section, taper, &drive_cases(d)))
        .collect()
}

/// Solves every drive path of `mechanism` with `ccx` (one run per path, each under
/// `timeout`); `on_path(k, seconds)` hears when path `k` (1-based) is done. A path that
/// stops keeps its converged cases and is listed in the run's failures; the other paths
/// are still solved.
pub fn solve_mechanism(
    mechanism: &Mechanism,
    meshes: &[Mesh],
    section: Section,
    taper: Taper,
    ccx: &Ccx,
    timeout: Duration,
    on_path: &mut dyn FnMut(usize, f64),
) -> MechFeaRun {
    let scale = match section {
        Section::Solid => 2.0,
        Section::PlaneStress | Section::PlaneStrain => 1.0,
    };
    let mut run = MechFeaRun {
        cases: Vec::new(),
        failures: Vec::new(),
        ccx_seconds: 0.0,
    };
    for (k, drive) in mechanism.drives.iter().enumerate() {
        let path = k + 1;
        let cases = drive_cases(drive);
        let deck = mechanism_deck(mechanism, meshes, section, taper, &cases);
        let started = std::time::Instant::now();
        let (dat, failure) = match ccx.run_partial(&deck, timeout) {
            Ok(o) => (o.dat, None),
            // Cancelled: no path after this one is run, and the caller discards the run.
            Err(f) if matches!(f.error, CcxError::Cancelled) => {
                run.failures.push(MechFeaFailure {
                    path,
                    case: 1,
                    cases: cases.len(),
                    message: f.error.to_string(),
                });
                break;
            }
            Err(f) => (f.dat, Some(f.error.to_string())),
        };
        let seconds = started.elapsed().as_secs_f64();
        let done = dat::finished_steps(&dat, cases.len(), STAGE_SET);
        let ends = dat::stage_ends(&dat, done, STAGE_SET, STAGE_ROT_SET).unwrap_or_default();
        for (i, (case, end)) in cases.iter().zip(&ends).enumerate() {
            let mut stage = end.pose;
            let mut stage_load = end.reaction.map(|v| v * scale);
            for c in 0..3 {
                match case[c] {
                    // The input itself, not its printed echo (seven digits).
                    Coordinate::Prescribed(v) => stage[c] = v,
                    Coordinate::Loaded(v) => stage_load[c] = v,
                }
            }
            run.cases.push(MechFeaCase {
                path,
                case: i + 1,
                drive: case.map(|c| c.value()),
                stage,
                stage_load,
            });
        }
        if ends.len() < cases.len() {
            run.failures.push(MechFeaFailure {
                path,
                case: ends.len() + 1,
                cases: cases.len(),
                message: failure.unwrap_or_else(|| {
                    "ccx finished without a result for this case (no converged increment \
                     reached its end)"
                        .into()
                }),
            });
        }
        run.ccx_seconds += seconds;
        on_path(path, seconds);
    }
    run
}

/// The run as DESIGN §9's mechanism CSV, SI: `path`, the drive's inputs named as its
/// `[[drives]]` keys (`dx` or `fx`, `dy` or `fy`, `dphi` or `mz`, by `mechanism`'s first
/// drive), then `stage_dx, stage_dy, stage_dphi, stage_fx, stage_fy, stage_mz`. A path that
/// stopped early is marked by `#` comments (readers skip them): one at the top naming every
/// such path, one after its last row.
pub fn mechanism_csv(mechanism: &Mechanism, run: &MechFeaRun, taper: Taper) -> String {
    let mut out = String::new();
    if !taper.is_uniform() {
        let _ = writeln!(
            out,
            "# prbfit fea --taper {taper}: every flexure's thickness tapered linearly from the \
             scene's at its clamp to {taper} times it at its tip, width constant"
        );
    }
    for f in &run.failures {
        let _ = writeln!(
            out,
            "# INCOMPLETE: drive path {} stopped at case {} of {} (ccx: {}); its rows end at \
             case {}",
            f.path,
            f.case,
            f.cases,
            f.message.replace('\n', " "),
            f.case - 1
        );
    }
    let kinds = mechanism
        .drives
        .first()
        .map_or([false; 3], |d| d.coordinates.map(|c| c.is_prescribed()));
    let inputs: Vec<&str> = COORDINATE_KEYS
        .iter()
        .zip(kinds)
        .map(|(&(d, l), p)| if p { d } else { l })
        .collect();
    let _ = writeln!(
        out,
        "path,{},stage_dx,stage_dy,stage_dphi,stage_fx,stage_fy,stage_mz",
        inputs.join(",")
    );
    for (i, c) in run.cases.iter().enumerate() {
        let values: Vec<String> = c
            .drive
            .iter()
            .chain(&c.stage)
            .chain(&c.stage_load)
            .map(|v| format!("{v:e}"))
            .collect();
        let _ = writeln!(out, "{},{}", c.path, values.join(","));
        let last_of_path = run.cases.get(i + 1).is_none_or(|n| n.path != c.path);
        if last_of_path {
            if let Some(f) = run.failures.iter().find(|f| f.path == c.path) {
                let _ = writeln!(
                    out,
                    "# drive path {} stopped here: case {} of {} did not converge",
                    f.path, f.case, f.cases
                );
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn mechanism(file: &str) -> Mechanism {
        let path = format!("{}/assets/scenes/{file}", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).unwrap();
        Scene::from_toml_str(&text, &path)
            .unwrap()
            .mechanism
            .unwrap()
    }

    fn deck_of(m: &Mechanism, section: Section) -> String {
        let meshes = flexure_meshes(m, 4, section, Taper::UNIFORM).unwrap();
        mechanism_decks(m, &meshes, section, Taper::UNIFORM).remove(0)
    }

    #[test]
    fn clamped_tips_are_tied_to_the_stage() {
        let m = mechanism("parallel-stage.toml");
        let text = deck_of(&m, Section::PlaneStress);
        // Two slabs of 4 bricks (56 nodes each), then the stage's two nodes.
        assert!(text.contains("REF NODE=113, ROT NODE=114"), "{text}");
        assert_eq!(text.matches("*RIGID BODY").count(), 1);
        let body = text.split("*NSET, NSET=NSTAGEBODY\n").nth(1).unwrap();
        let members = body.split('*').next().unwrap().matches(',').count();
        assert_eq!(members, 16, "both tip faces, 8 nodes each");
        // One step per case; the sideways force on the reference node, the moment none.
        assert_eq!(text.matches("*STEP, NLGEOM").count(), 8);
        assert!(text.contains("113, 2, 2.500000000000e0"), "{text}");
        assert!(!text.contains("*BOUNDARY\n113"));
        // The flexures sit at their roots: the lower one's first node.
        assert!(text.contains("57, 0.000000000000e0, -1.525000000000e-2, 0.000000000000e0"));
    }

    #[test]
    fn a_coupler_is_an_axial_spring_and_prescribed_coordinates_are_boundaries() {
        let m = mechanism("slider-crank.toml");
        let text = deck_of(&m, Section::PlaneStress);
        assert_eq!(text.matches("*RIGID BODY").count(), 2);
        assert!(text.contains("TYPE=SPRINGA"));
        // Its stiffness: 1e6 E I / L^3 of the flexure (plane stress: E* w t^3 / 12 / L^3
        // with the equivalent modulus).
        let b = &m.flexures[0].beam;
        let (e, _) = material(b, Section::PlaneStress);
        let k = JOINT_STIFFNESS * e * b.width * b.thickness.powi(3) / 12.0 / b.length.powi(3);
        assert!(text.contains(&format!("{k:.12e}")), "{text}");
        // Case 1 of 10: dy = 1.5 mm on the stage's reference node, dx and dphi held at 0.
        let step = text.split("*STEP").nth(1).unwrap();
        // One slab of 4 bricks (56 nodes): the stage's reference node is 57, its rotation 58.
        assert!(
            step.contains(
                "*BOUNDARY\n57, 1, 1, 0.000000000000e0\n57, 2, 2, 1.500000000000e-3\n\
                 58, 3, 3, 0.000000000000e0"
            ),
            "{step}"
        );
        assert!(!step.contains("*CLOAD"));
    }

    #[test]
    fn the_solid_halves_the_loads_and_the_csv_names_the_drive() {
        let m = mechanism("parallel-stage.toml");
        let solid = deck_of(&m, Section::Solid);
        let meshes = flexure_meshes(&m, 4, Section::Solid, Taper::UNIFORM).unwrap();
        assert_eq!(meshes[0].across, 2);
        assert!(solid.contains(", 2, 1.250000000000e0"), "{solid}");
        let run = MechFeaRun {
            cases: vec![MechFeaCase {
                path: 1,
                case: 1,
                drive: [0.0, 2.5, 0.0],
                stage: [0.0, 1e-3, 0.0],
                stage_load: [0.0, 2.5, 0.0],
            }],
            failures: vec![MechFeaFailure {
                path: 1,
                case: 2,
                cases: 8,
                message: "ccx failed".into(),
            }],
            ccx_seconds: 0.0,
        };
        let csv = mechanism_csv(&m, &run, Taper::UNIFORM);
        let lines: Vec<&str> = csv.lines().collect();
        assert!(lines[0].starts_with("# INCOMPLETE: drive path 1 stopped at case 2 of 8"));
        assert_eq!(
            lines[1],
            "path,fx,fy,mz,stage_dx,stage_dy,stage_dphi,stage_fx,stage_fy,stage_mz"
        );
        assert!(lines[3].starts_with("# drive path 1 stopped here"));
        // The file reads back as the mechanism's data.
        let data = crate::scene::data::parse_stage_csv(&csv, "fea.csv", &m).unwrap();
        assert_eq!(data.prescribed, [false; 3]);
        assert_eq!(data.paths[0].rows[0].stage[1], 1e-3);
    }
}
