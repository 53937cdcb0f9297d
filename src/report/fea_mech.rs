//! `prbfit fea` on a mechanism scene (DESIGN §13): every flexure meshed, the stage a rigid
//! body, one CalculiX run per drive path, written as DESIGN §9's mechanism CSV (and the
//! decks beside it), with the beam mechanism of §8 alongside for comparison.

use std::fmt;
use std::time::{Duration, Instant};

use serde::Serialize;

use crate::beam::Resolution;
use crate::fea::mech::{self, MechFeaCase, MechFeaFailure};
use crate::fea::{Mesh, Section, Taper};
use crate::io::files::write_atomic;
use crate::mech::figures::reaction_scales;
use crate::mech::{exact, MechCase};
use crate::scene::{Coordinate, EffectsChoice, Mechanism, Scene};
use crate::study::EffectsDecision;

use super::fea::{deck_targets, write_decks, FeaArgs};
use super::{resolve_scene, safe, Control, DecisionLine, Progress, ReportError, Result};

/// One case: the FEA's stage and load (nondimensional, flexure 1's `L` and `E I0`) and the
/// beam mechanism's differences from it.
#[derive(Debug, Serialize)]
struct Case {
    path: usize,
    /// The drive fraction `k / steps`.
    fraction: f64,
    /// SI, as written to the CSV.
    fea_si: MechFeaCase,
    /// `[dx, dy, dphi]`, units of flexure 1's `L`, rad.
    stage: [f64; 3],
    /// `[alpha_x, alpha_y, beta]`.
    stage_load: [f64; 3],
    /// `|(dx, dy)_FEA - (dx, dy)_beam|`, units of L (none when the beam mechanism has no
    /// such case).
    #[serde(skip_serializing_if = "Option::is_none")]
    pos_diff: Option<f64>,
    /// `dphi_FEA - dphi_beam`, rad.
    #[serde(skip_serializing_if = "Option::is_none")]
    ang_diff: Option<f64>,
    /// The largest reaction difference over the prescribed coordinates, each as a fraction
    /// of its largest beam reaction over the scene, floored as the figures floor it (DESIGN §8's
    /// `e_force`).
    #[serde(skip_serializing_if = "Option::is_none")]
    force_diff: Option<f64>,
}

/// What `prbfit fea` did on a mechanism (its fields are the `--json` object's).
#[derive(Debug, Serialize)]
pub struct MechFeaReport {
    scene: String,
    output: String,
    decks: Vec<String>,
    section: Section,
    /// Where the section came from: `"scene"` (it follows the scene's flexures) or `"flag"`
    /// (`--section`, the beam mechanism beside it then made of the same section).
    section_from: &'static str,
    /// How the beam mechanism beside the FEA matches the section, in words.
    like_with_like: String,
    /// Per flexure.
    meshes: Vec<Mesh>,
    taper: Taper,
    /// Which stage coordinates the drives prescribe (`[x, y, phi]`).
    prescribed: [bool; 3],
    beam_effects: Vec<&'static str>,
    effects_decision: Option<EffectsDecision>,
    /// Why the beam mechanism is not beside the FEA, when it is not.
    #[serde(skip_serializing_if = "Option::is_none")]
    beam_error: Option<String>,
    cases: Vec<Case>,
    failures: Vec<MechFeaFailure>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_pos_diff: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_ang_diff: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_force_diff: Option<f64>,
    ccx_seconds: f64,
    seconds: f64,
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".into(), |v| format!("{v:.2e}"))
}

impl fmt::Display for MechFeaReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "scene: {}", safe(&self.scene))?;
        let meshes: Vec<String> = self.meshes.iter().map(ToString::to_string).collect();
        let taper = if self.taper.is_uniform() {
            String::new()
        } else {
            format!(
                " tapered to {} x the root thickness at the tip (the beam beside it uniform);",
                self.taper
            )
        };
        writeln!(
            f,
            "CalculiX: {} model of the mechanism, flexures of {} C3D20R elements (along x \
             through x across), the stage a rigid body;{taper} beam mechanism beside it: \
             effects [{}]",
            self.section,
            meshes.join(", "),
            self.beam_effects.join(",")
        )?;
        writeln!(f, "like with like: {}", self.like_with_like)?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        // Reactions are starred: the load columns of the prescribed coordinates.
        let star = |c: usize, load: bool| {
            if load && self.prescribed[c] {
                "*"
            } else {
                ""
            }
        };
        writeln!(
            f,
            "{:>4} {:>6} | {:>9} {:>9} {:>9} | {:>9} {:>9} {:>9} | {:>9} {:>9} {:>9}",
            "path",
            "frac",
            format!("dx/L{}", star(0, false)),
            format!("dy/L{}", star(1, false)),
            format!("dphi{}", star(2, false)),
            format!("alpha_x{}", star(0, true)),
            format!("alpha_y{}", star(1, true)),
            format!("beta{}", star(2, true)),
            "pos diff",
            "ang diff",
            "force diff"
        )?;
        for c in &self.cases {
            writeln!(
                f,
                "{:>4} {:>6.3} | {:>9.5} {:>9.5} {:>9.5} | {:>9.4} {:>9.4} {:>9.4} | {:>9} {:>9} {:>9}",
                c.path,
                c.fraction,
                c.stage[0],
                c.stage[1],
                c.stage[2],
                c.stage_load[0],
                c.stage_load[1],
                c.stage_load[2],
                opt(c.pos_diff),
                opt(c.ang_diff),
                opt(c.force_diff)
            )?;
        }
        writeln!(
            f,
            "(FEA; * = a reaction the drive supplies; loads in flexure 1's E I0 / L^2 and E I0 / L)"
        )?;
        match &self.beam_error {
            Some(e) => writeln!(f, "beam mechanism: not solved ({})", safe(e))?,
            None => writeln!(
                f,
                "FEA vs beam mechanism: max position difference {} L, max angle difference {} \
                 rad, max reaction difference {} of the largest",
                opt(self.max_pos_diff),
                opt(self.max_ang_diff),
                opt(self.max_force_diff)
            )?,
        }
        for x in &self.failures {
            writeln!(
                f,
                "drive path {} stopped at case {} of {}: {}",
                x.path,
                x.case,
                x.cases,
                safe(&x.message)
            )?;
        }
        for d in &self.decks {
            writeln!(f, "deck: {}", safe(d))?;
        }
        writeln!(
            f,
            "wrote {} ({} cases{}; ccx {:.1} s, all {:.1} s)",
            safe(&self.output),
            self.cases.len(),
            if self.failures.is_empty() {
                ""
            } else {
                ", INCOMPLETE: marked in the file"
            },
            self.ccx_seconds,
            self.seconds
        )
    }
}

impl MechFeaReport {
    /// When a drive path stopped early: the one-line message saying which case, why, and
    /// where the cases before it went (the CLI's exit status 1 after the report).
    pub fn incomplete(&self) -> Option<String> {
        self.failures.first().map(|x| {
            format!(
                "the FEA of drive path {} stopped at case {} of {}: {}; the {} cases solved \
                 before it are in {}, the incomplete path marked",
                x.path,
                x.case,
                x.cases,
                x.message,
                self.cases.len(),
                self.output
            )
        })
    }
}

/// `prbfit fea` on a mechanism scene (DESIGN §13): writes the CSV and the decks, and
/// compares the FEA with the beam mechanism. A drive path that stops early is in the
/// report ([`MechFeaReport::incomplete`]), its solved cases in the CSV.
pub fn fea_mechanism(
    scene: &Scene,
    args: &FeaArgs,
    ctl: &mut Control<'_>,
) -> Result<MechFeaReport> {
    let t0 = Instant::now();
    let Some(mechanism) = &scene.mechanism else {
        return Err(ReportError::input(format!(
            "\"{}\": not a mechanism scene (its FEA is super::fea::fea's)",
            safe(&scene.name)
        )));
    };
    if args.timeout == 0 {
        return Err(ReportError::input("--timeout: must be at least 1 second"));
    }
    mech::check_drives(mechanism).map_err(|e| ReportError::input(e.to_string()))?;
    // Like with like (issue 26 item 5), as the cantilever's FEA: the section follows the
    // scene's flexures (their effects decided), or the beam mechanism beside the FEA follows
    // the section given.
    let (resolved, decision) = resolve_scene(scene, &ctl.cancel)?;
    let resolved_mechanism = resolved
        .mechanism
        .clone()
        .unwrap_or_else(|| mechanism.clone());
    let (section, section_from, beam_mechanism, like_with_like) =
        like_with_like(resolved_mechanism, args.section);
    let meshes = mech::flexure_meshes(mechanism, args.mesh, section, args.taper)
        .map_err(|e| ReportError::input(format!("--mesh {}: {e}", args.mesh)))?;
    let n = mechanism.drives.len();
    let deck_files = deck_targets(args, n)?;
    let decks = mech::mechanism_decks(mechanism, &meshes, section, args.taper);
    let (deck_names, ccx) = write_decks(args, &deck_files, &decks, &ctl.cancel)?;
    let progress = &mut *ctl.progress;
    let run = mech::solve_mechanism(
        mechanism,
        &meshes,
        section,
        args.taper,
        &ccx,
        Duration::from_secs(args.timeout),
        &mut |path, _| progress(&Progress::Fea { path, paths: n }),
    );
    let beam = exact::solver(&beam_mechanism, Resolution::default())
        .and_then(|s| s.with_cancel(&ctl.cancel).solve_all(&beam_mechanism));
    // A cancelled run (in CalculiX's runs or in the beam mechanism beside them) writes no
    // CSV: its paths are cut short, and the caller discards it.
    if ctl.cancel.is_cancelled() {
        return Err(ReportError::solve("cancelled: no CSV was written"));
    }
    write_atomic(
        &args.output,
        mech::mechanism_csv(mechanism, &run, args.taper).as_bytes(),
        args.force,
    )?;
    let beam_effects = beam_mechanism
        .flexures
        .first()
        .map(|f| f.beam.model().effects.names())
        .unwrap_or_default();
    let (beam_cases, beam_error) = match beam {
        Ok(c) => (Some(c), None),
        Err(e) => (None, Some(e.to_string())),
    };
    let cases = compare(mechanism, &run.cases, beam_cases.as_deref());
    let max = |g: fn(&Case) -> Option<f64>| {
        cases
            .iter()
            .filter_map(g)
            .map(f64::abs)
            .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))))
    };
    let report = MechFeaReport {
        scene: scene.name.clone(),
        output: args.output.display().to_string(),
        decks: deck_names,
        section,
        section_from,
        like_with_like,
        meshes,
        taper: args.taper,
        prescribed: mechanism
            .drives
            .first()
            .map_or([false; 3], |d| d.coordinates.map(|c| c.is_prescribed())),
        beam_effects,
        effects_decision: decision,
        beam_error,
        max_pos_diff: max(|c| c.pos_diff),
        max_ang_diff: max(|c| c.ang_diff),
        max_force_diff: max(|c| c.force_diff),
        cases,
        failures: run.failures.clone(),
        ccx_seconds: run.ccx_seconds,
        seconds: t0.elapsed().as_secs_f64(),
    };
    Ok(report)
}

/// Pairs each FEA case with the beam mechanism's (when it has it), nondimensional.
fn compare(
    mechanism: &Mechanism,
    fea: &[MechFeaCase],
    beam: Option<&[Vec<MechCase>]>,
) -> Vec<Case> {
    let disp = mechanism.factors([Coordinate::Prescribed(0.0); 3]);
    let load = mechanism.factors([Coordinate::Loaded(0.0); 3]);
    // Each prescribed coordinate's reaction scale: its largest beam reaction, floored.
    let scales = beam.map_or([None; 3], |b| reaction_scales(&mechanism.drives, b));
    fea.iter()
        .map(|c| {
            let stage: [f64; 3] = std::array::from_fn(|i| c.stage[i] * disp[i]);
            let stage_load: [f64; 3] = std::array::from_fn(|i| c.stage_load[i] * load[i]);
            let steps = mechanism
                .drives
                .get(c.path - 1)
                .map_or(1, |d| d.steps.max(1));
            let other = beam
                .and_then(|b| b.get(c.path - 1))
                .and_then(|p| p.get(c.case - 1));
            let force_diff = other.and_then(|b| {
                (0..3)
                    .filter_map(|i| scales[i].map(|s| (i, s)))
                    .map(|(i, s)| (stage_load[i] - b.stage_load[i]).abs() / s)
                    .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))))
            });
            Case {
                path: c.path,
                fraction: c.case as f64 / f64::from(steps),
                fea_si: *c,
                stage,
                stage_load,
                pos_diff: other.map(|b| (stage[0] - b.stage[0]).hypot(stage[1] - b.stage[1])),
                ang_diff: other.map(|b| stage[2] - b.stage[2]),
                force_diff,
            }
        })
        .collect()
}

/// The section of a mechanism's FEA and the beam mechanism beside it (`resolved`: the
/// scene's, effects decided), with where the section came from and how they match, in
/// words. Without `--section` the section follows the flexures: `solid` when one keeps plane
/// strain, else `plane-stress`, and the beam mechanism is the scene's. With it, every
/// flexure's plane strain is set as the section has it (plane stress: off; solid and plane
/// strain: on, each flexure's plate fraction from its width and ends, as the beam mechanism
/// models a wide flexure).
fn like_with_like(
    mut resolved: Mechanism,
    given: Option<Section>,
) -> (Section, &'static str, Mechanism, String) {
    let keeps = resolved
        .flexures
        .iter()
        .any(|f| f.beam.effects.resolve().plane_strain);
    let Some(section) = given else {
        let (section, why) = if keeps {
            (
                Section::Solid,
                "the solid section, as the scene's flexures keep plane strain",
            )
        } else {
            (
                Section::PlaneStress,
                "the plane-stress section, as the scene's flexures are narrow (no plane strain)",
            )
        };
        return (
            section,
            "scene",
            resolved,
            format!("{why}; the beam mechanism beside it is the scene's"),
        );
    };
    let (wants, how) = match section {
        Section::PlaneStress => (false, "plane strain off"),
        Section::Solid => (true, "plane strain on, each plate fraction from the width"),
        Section::PlaneStrain => (
            true,
            "plane strain on, each plate fraction from the width (not the unbounded plate's)",
        ),
    };
    let all_match = resolved
        .flexures
        .iter()
        .all(|f| f.beam.effects.resolve().plane_strain == wants);
    for f in &mut resolved.flexures {
        let e = f.beam.effects.resolve().with_plane_strain(wants);
        f.beam.effects = EffectsChoice::Fixed(e);
    }
    let note = if all_match && section != Section::PlaneStrain {
        format!("--section {section}; the beam mechanism beside it is the scene's ({how})")
    } else {
        format!(
            "--section {section}; the beam mechanism beside it is the scene's with {how}, to match"
        )
    };
    (section, "flag", resolved, note)
}
