//! `prbfit fea`: the scene's beam as a CalculiX model along the scene's load paths, written
//! as DESIGN §9's CSV (and the decks beside it), with the beam of §2 alongside for comparison.

use std::fmt;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde::Serialize;

use crate::beam::{BeamModel, Load, Resolution, TipPose};
use crate::cancel::CancelToken;
use crate::eval::Baseline;
use crate::fea::{self, Ccx, CcxError, FeaCase, FeaError, Mesh, Section, Taper};
use crate::io::files::{check_target, write_atomic};
use crate::scene::Scene;
use crate::study::EffectsDecision;

use super::{resolve_scene, safe, Control, DecisionLine, Progress, ReportError, Result};

/// `fea`'s arguments (the CLI's flags).
#[derive(Debug, Clone, PartialEq)]
pub struct FeaArgs {
    /// The CSV to write (`-o`).
    pub output: PathBuf,
    /// Elements along the beam (`--mesh`).
    pub mesh: u32,
    /// The section model (`--section`); `None`: the scene's (solid when its beam keeps plane
    /// strain once `auto` is decided, else plane stress).
    pub section: Option<Section>,
    /// Tip thickness over root thickness (`--taper`).
    pub taper: Taper,
    /// Where to write the CalculiX deck; default: beside the output, extension .inp.
    pub deck: Option<PathBuf>,
    /// Overwrite the output and the decks if they exist.
    pub force: bool,
    /// Time limit of each CalculiX run, seconds.
    pub timeout: u64,
}

impl FeaArgs {
    /// The arguments that write `output` with the defaults of the CLI's flags.
    pub fn new(output: PathBuf) -> FeaArgs {
        FeaArgs {
            output,
            mesh: 40,
            section: None,
            taper: Taper::default(),
            deck: None,
            force: false,
            timeout: 900,
        }
    }
}

/// One case: the load, the FEA tip and the beam's, in units of L.
#[derive(Debug, Serialize)]
pub struct Case {
    path: usize,
    load: Load,
    /// `[Fx, Fy, Mz]`, N, N, N m.
    load_si: [f64; 3],
    fea: TipPose,
    beam: TipPose,
    /// `|(a, b)_FEA - (a, b)_beam|`, units of L.
    pos_diff: f64,
    /// `phi_FEA - phi_beam`, rad.
    ang_diff: f64,
}

/// What `prbfit fea` did.
#[derive(Debug, Serialize)]
pub struct FeaReport {
    scene: String,
    output: String,
    decks: Vec<String>,
    section: Section,
    /// Where the section came from: `"scene"` (it follows the scene's beam) or `"flag"`
    /// (`--section`, the beam beside it then made of the same section).
    section_from: &'static str,
    /// How the beam beside the FEA matches the section, in words.
    like_with_like: String,
    mesh: Mesh,
    /// The tip thickness over the root thickness of the FEA model (1: uniform). The beam
    /// beside it is always the scene's uniform beam, of the root thickness.
    taper: Taper,
    /// The beam the FEA is compared with (the scene's effects, decided if `auto`).
    beam_effects: Vec<&'static str>,
    effects_decision: Option<EffectsDecision>,
    cases: Vec<Case>,
    max_pos_diff: f64,
    max_ang_diff: f64,
    ccx_seconds: f64,
    seconds: f64,
}

impl fmt::Display for FeaReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "scene: {}", safe(&self.scene))?;
        // A tapered model is compared with the uniform beam of its root thickness: say so
        // wherever the comparison is printed.
        let (model, beam, versus) = if self.taper.is_uniform() {
            (String::new(), "", "FEA vs beam")
        } else {
            (
                format!(
                    "tapered to {} x the root thickness at the tip; ",
                    self.taper
                ),
                "uniform, root thickness, ",
                "FEA (tapered) vs uniform beam (root thickness)",
            )
        };
        writeln!(
            f,
            "CalculiX: {} model, {} C3D20R elements (along x through x across); {model}beam \
             beside it: {beam}effects [{}]",
            self.section,
            self.mesh,
            self.beam_effects.join(",")
        )?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        writeln!(f, "like with like: {}", self.like_with_like)?;
        writeln!(
            f,
            "{:>4} {:>8} {:>8} {:>8} | {:>10} {:>10} {:>10} | {:>10} {:>10}",
            "path",
            "alpha_x",
            "alpha_y",
            "beta",
            "a FEA",
            "b FEA",
            "phi FEA",
            "pos diff",
            "ang diff"
        )?;
        for c in &self.cases {
            writeln!(
                f,
                "{:>4} {:>8.4} {:>8.4} {:>8.4} | {:>10.6} {:>10.6} {:>10.6} | {:>10.2e} {:>10.2e}",
                c.path,
                c.load.alpha_x,
                c.load.alpha_y,
                c.load.beta,
                c.fea.a,
                c.fea.b,
                c.fea.phi,
                c.pos_diff,
                c.ang_diff
            )?;
        }
        writeln!(
            f,
            "{versus}: max position difference {:.3e} L, max angle difference {:.3e} rad",
            self.max_pos_diff, self.max_ang_diff
        )?;
        for d in &self.decks {
            writeln!(f, "deck: {}", safe(d))?;
        }
        writeln!(
            f,
            "wrote {} ({} cases; ccx {:.1} s, all {:.1} s)",
            safe(&self.output),
            self.cases.len(),
            self.ccx_seconds,
            self.seconds
        )
    }
}

/// Writes each deck to its file (atomically) and finds CalculiX; without it, the error says
/// where the decks were written (they can be run by hand). Returns the decks' names and ccx.
pub(super) fn write_decks(
    args: &FeaArgs,
    deck_files: &[PathBuf],
    decks: &[String],
    cancel: &CancelToken,
) -> Result<(Vec<String>, Ccx)> {
    for (file, text) in deck_files.iter().zip(decks) {
        write_atomic(file, text.as_bytes(), args.force)?;
    }
    let deck_names: Vec<String> = deck_files.iter().map(|d| d.display().to_string()).collect();
    let ccx = match Ccx::find() {
        Ok(c) => c.with_cancel(cancel),
        Err(e @ CcxError::NotInstalled) => {
            return Err(ReportError::solve(format!(
                "{e}; the deck was written to {}",
                deck_names.join(", ")
            )))
        }
        Err(e) => return Err(ReportError::failed(&e)),
    };
    Ok((deck_names, ccx))
}

/// The deck files of `n` paths (or drives), one per path, beside the output unless `--deck`
/// names them; every file refused before any work: an existing output or deck without
/// `--force`, or a deck that would overwrite the CSV.
pub(super) fn deck_targets(args: &FeaArgs, n: usize) -> Result<Vec<PathBuf>> {
    let deck_base = args
        .deck
        .clone()
        .unwrap_or_else(|| args.output.with_extension("inp"));
    let deck_files: Vec<PathBuf> = (1..=n).map(|k| deck_path(&deck_base, k, n)).collect();
    check_target(&args.output, args.force)?;
    for d in &deck_files {
        if d == &args.output {
            return Err(ReportError::input(format!(
                "--deck {}: the deck would overwrite the CSV output",
                d.display()
            )));
        }
        check_target(d, args.force)?;
    }
    Ok(deck_files)
}

/// Where path `k` (1-based) of `n` goes: `deck` itself for one path, else `deck` with
/// `-path{k}` before its extension.
pub(super) fn deck_path(deck: &Path, k: usize, n: usize) -> PathBuf {
    if n == 1 {
        return deck.to_path_buf();
    }
    let stem = deck
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "deck".into());
    let ext = deck
        .extension()
        .map(|e| format!(".{}", e.to_string_lossy()))
        .unwrap_or_default();
    deck.with_file_name(format!("{stem}-path{k}{ext}"))
}

/// `prbfit fea` on `scene`: writes the CSV and the decks, and compares the FEA with the beam.
pub fn fea(scene: &Scene, args: &FeaArgs, ctl: &mut Control<'_>) -> Result<FeaReport> {
    let t0 = Instant::now();
    if scene.mechanism.is_some() {
        return Err(ReportError::input(format!(
            "\"{}\": {} (its report is the mechanism FEA's, report::fea_mech)",
            safe(&scene.name),
            FeaError::Mechanism
        )));
    }
    if args.timeout == 0 {
        return Err(ReportError::input("--timeout: must be at least 1 second"));
    }
    // The section follows the scene's beam (its effects decided), or the beam beside the
    // FEA follows the section given: like is compared with like (issue 26 item 5).
    let (resolved, decision) = resolve_scene(scene, &ctl.cancel)?;
    let keeps_plane_strain = resolved.beam.effects.resolve().plane_strain;
    let (section, section_from) = match args.section {
        Some(s) => (s, "flag"),
        None if keeps_plane_strain => (Section::Solid, "scene"),
        None => (Section::PlaneStress, "scene"),
    };
    let (beam_model, like_with_like) = beside(&resolved, section, args.section.is_some());
    let mesh = Mesh::for_tapered_beam(args.mesh, &scene.beam, section, args.taper)
        .map_err(|e| ReportError::input(format!("--mesh {}: {e}", args.mesh)))?;
    let n = scene.loads.len();
    let deck_files = deck_targets(args, n)?;
    let decks =
        fea::scene_decks(scene, &mesh, section, args.taper).map_err(|e| ReportError::failed(&e))?;
    let (deck_names, ccx) = write_decks(args, &deck_files, &decks, &ctl.cancel)?;
    let mut ccx_seconds = 0.0;
    let progress = &mut *ctl.progress;
    let fea_cases = fea::solve_scene(
        scene,
        &mesh,
        section,
        args.taper,
        &ccx,
        Duration::from_secs(args.timeout),
        &mut |path, seconds| {
            ccx_seconds += seconds;
            progress(&Progress::Fea { path, paths: n });
        },
    )
    .map_err(|e| {
        ReportError::failed_in(format!("the FEA (decks: {})", deck_names.join(", ")), &e)
    })?;
    let baseline = Baseline::solve(
        beam_model,
        &resolved.loads,
        Resolution::default(),
        &ctl.cancel,
        &mut |_, _| {},
    );
    // Cancelled (in CalculiX's runs or in the beam beside them): no CSV. The FEA's CSV is
    // written even when the beam beside it fails: it is the FEA's result.
    if ctl.cancel.is_cancelled() {
        return Err(ReportError::solve("cancelled: no CSV was written"));
    }
    write_atomic(
        &args.output,
        fea::csv(&fea_cases, args.taper).as_bytes(),
        args.force,
    )?;
    let baseline = baseline.map_err(|e| ReportError::failed_in("the beam beside the FEA", &e))?;
    let cases = compare(&fea_cases, &baseline, scene.beam.length);
    let max = |f: fn(&Case) -> f64| cases.iter().map(f).fold(0.0, f64::max);
    let report = FeaReport {
        scene: scene.name.clone(),
        output: args.output.display().to_string(),
        decks: deck_names,
        section,
        section_from,
        like_with_like,
        mesh,
        taper: args.taper,
        beam_effects: baseline.model.effects.names(),
        effects_decision: decision,
        max_pos_diff: max(|c| c.pos_diff),
        max_ang_diff: max(|c| c.ang_diff.abs()),
        cases,
        ccx_seconds,
        seconds: t0.elapsed().as_secs_f64(),
    };
    Ok(report)
}

/// The beam to print beside an FEA of `section` on the scene `resolved` (effects decided),
/// and how it matches, in words: the scene's own when the section followed it (`given`
/// false); else the scene's with plane strain set as the section has it (plane stress: off;
/// solid: on, the plate fraction from the width; plane strain: on, the unboundedly wide
/// section's plate modulus).
fn beside(resolved: &Scene, section: Section, given: bool) -> (BeamModel, String) {
    let model = resolved.beam.model();
    let keeps = model.effects.plane_strain;
    if !given {
        let why = if keeps {
            "the solid section, as the scene's beam keeps plane strain"
        } else {
            "the plane-stress section, as the scene's beam is narrow (no plane strain)"
        };
        return (model, format!("{why}; the beam beside it is the scene's"));
    }
    let (wants, how) = match section {
        Section::PlaneStress => (false, "plane strain off"),
        Section::Solid => (true, "plane strain on, the plate fraction from the width"),
        Section::PlaneStrain => (true, "plane strain on, the plate modulus E/(1-nu^2)"),
    };
    let effects = model.effects.with_plane_strain(wants);
    let matched = BeamModel::new(model.slenderness, model.nu, Some(model.kappa), effects)
        .map(|m| match section {
            Section::PlaneStrain => m,
            _ => m.with_width_ratio(resolved.beam.width / resolved.beam.thickness),
        })
        .unwrap_or(model);
    let note = if wants == keeps && section != Section::PlaneStrain {
        format!("--section {section}; the beam beside it is the scene's ({how})")
    } else {
        format!("--section {section}; the beam beside it is the scene's with {how}, to match")
    };
    (matched, note)
}

/// Pairs each FEA case with the beam's solution of the same case.
fn compare(fea_cases: &[FeaCase], baseline: &Baseline, length: f64) -> Vec<Case> {
    fea_cases
        .iter()
        .zip(&baseline.solutions)
        .map(|(c, s)| {
            let tip = TipPose {
                a: c.x / length,
                b: c.y / length,
                phi: c.theta,
            };
            Case {
                path: c.path,
                load: c.load,
                load_si: c.load_si,
                fea: tip,
                beam: s.tip,
                pos_diff: (tip.a - s.tip.a).hypot(tip.b - s.tip.b),
                ang_diff: tip.phi - s.tip.phi,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decks_of_several_paths_are_numbered() {
        let d = Path::new("out/data.inp");
        assert_eq!(deck_path(d, 1, 1), PathBuf::from("out/data.inp"));
        assert_eq!(deck_path(d, 2, 3), PathBuf::from("out/data-path2.inp"));
        assert_eq!(
            deck_path(Path::new("deck"), 1, 2),
            PathBuf::from("deck-path1")
        );
    }
}
