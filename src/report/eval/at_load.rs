//! `eval --load`: the models against the cantilever's beam at one load, the PRB model's
//! stress estimate beside the beam's (DESIGN §11).

use std::fmt;

use serde::Serialize;

use crate::beam::{BeamSolver, Load, Resolution, TipPose};
use crate::eval::CaseError;
use crate::prb::PrbSolver;
use crate::scene::Scene;

use super::super::stage::{refuse_flag, LOADS_ARE_DRIVES};
use super::super::{mpa, num, safe, Control, ReportError, Result};
use super::{named_models, EvalArgs, OneOrMany};

/// A model at one load.
#[derive(Debug, Serialize)]
pub struct AtLoad {
    model: String,
    prb: String,
    load: Load,
    #[serde(flatten)]
    tip: TipPose,
    pos_err: f64,
    ang_err: f64,
    beam: TipPose,
    /// The PRB model's stress estimate (DESIGN §11), Pa, and where, `s / L`.
    #[serde(skip_serializing_if = "Option::is_none")]
    max_stress: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_stress_at: Option<f64>,
    /// The beam's largest fibre stress, Pa, and where.
    #[serde(skip_serializing_if = "Option::is_none")]
    beam_max_stress: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    beam_max_stress_at: Option<f64>,
    /// `(sigma_PRB - sigma_beam) / sigma_beam`.
    #[serde(skip_serializing_if = "Option::is_none")]
    stress_err: Option<f64>,
}

/// `eval --load`.
#[derive(Debug, Serialize)]
#[serde(transparent)]
pub struct AtLoadReport(OneOrMany<AtLoad>);

impl fmt::Display for AtLoadReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rows = self.0.rows();
        let Some(first) = rows.first() else {
            return Ok(());
        };
        writeln!(f, "load: {}", first.load)?;
        writeln!(
            f,
            "{:<12} {:>11} {:>11} {:>11} | {:>10} {:>10}",
            "model", "a", "b", "phi", "pos_err", "ang_err"
        )?;
        let beam = first.beam;
        writeln!(
            f,
            "{:<12} {:>11.7} {:>11.7} {:>11.7} |",
            "beam", beam.a, beam.b, beam.phi
        )?;
        for r in rows {
            writeln!(
                f,
                "{:<12} {:>11.7} {:>11.7} {:>11.7} | {:>10.3e} {:>10.3e}",
                safe(&r.model),
                r.tip.a,
                r.tip.b,
                r.tip.phi,
                r.pos_err,
                r.ang_err
            )?;
        }
        for r in rows {
            if let (Some(p), Some(pa), Some(b), Some(ba), Some(e)) = (
                r.max_stress,
                r.max_stress_at,
                r.beam_max_stress,
                r.beam_max_stress_at,
                r.stress_err,
            ) {
                writeln!(
                    f,
                    "{} stress: PRB {} MPa at s/L {pa:.3}, beam {} MPa at s/L {ba:.3}; \
                     error {e:.2e} of the beam's",
                    safe(&r.model),
                    mpa(p, 1),
                    mpa(b, 1)
                )?;
            }
        }
        Ok(())
    }
}

/// `eval --load`: the models against the cantilever's beam at one load.
pub(super) fn at_load(
    args: &EvalArgs,
    scene: &Scene,
    load: Load,
    ctl: &mut Control<'_>,
) -> Result<AtLoadReport> {
    if scene.mechanism.is_some() {
        return Err(refuse_flag("--load", scene, LOADS_ARE_DRIVES));
    }
    if let Some(truth) = &scene.truth {
        return Err(ReportError::input(format!(
            "--load: \"{}\" is a data scene: its load cases are the rows of {} (judge the \
             model over them without --load)",
            safe(&scene.name),
            safe(&truth.file)
        )));
    }
    let (scene, _) = super::super::resolve_scene(scene, &ctl.cancel)?;
    let models = named_models(args, &scene)?;
    let beam = scene.beam.model();
    let solver = BeamSolver::new(beam, Resolution::with_tol(args.tol))
        .map_err(|e| ReportError::input(format!("--tol {}: {e}", num(args.tol))))?;
    let sol = solver
        .solve(load)
        .map_err(|e| ReportError::failed_in("baseline beam", &e))?;
    let mut rows = Vec::new();
    for (name, m) in models {
        let prb = PrbSolver::new(&m, beam.axial_compliance())
            .solve(load)
            .map_err(|e| ReportError::failed_in(format!("model {name}"), &e))?;
        let case = CaseError::new(load, sol.tip, prb.tip);
        let e = scene.beam.youngs_modulus;
        let prb_stress =
            PrbSolver::new(&m, beam.axial_compliance()).max_stress(&beam, load, &prb.q);
        let stress_err = match (prb_stress, sol.stress) {
            (Some(p), Some(b)) if b.max > 0.0 => Some((p.max - b.max) / b.max),
            _ => None,
        };
        rows.push(AtLoad {
            max_stress: prb_stress.map(|s| s.max * e),
            max_stress_at: prb_stress.map(|s| s.at),
            beam_max_stress: sol.stress.map(|s| s.max * e),
            beam_max_stress_at: sol.stress.map(|s| s.at),
            stress_err,
            model: name,
            prb: m.to_text(),
            load,
            tip: case.prb,
            pos_err: case.pos_err,
            ang_err: case.ang_err,
            beam: case.beam,
        });
    }
    Ok(AtLoadReport(OneOrMany::new(rows)))
}
