//! `prbfit calibrate`: one parameter of a data scene's beam fitted to its measurements
//! (DESIGN §9), reported with the residual before and after.

use std::fmt;
use std::time::Instant;

use serde::Serialize;

use crate::beam::Resolution;
use crate::mech::figures::Figures;
use crate::scene::Scene;
use crate::study::calibrate::{calibrate, BeamParam, CalibrateError, Calibration};

use super::{num, resolve_scene, safe, Control, ReportError, Result};

/// `calibrate`'s arguments (the CLI's flags).
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrateArgs {
    /// The beam parameter fitted: `youngs_modulus` or `thickness` (`--param`).
    pub param: String,
}

impl Default for CalibrateArgs {
    fn default() -> CalibrateArgs {
        CalibrateArgs {
            param: "youngs_modulus".to_string(),
        }
    }
}

/// The parameter `args` names; bad input naming `--param` if none.
pub fn param(args: &CalibrateArgs) -> Result<BeamParam> {
    BeamParam::from_name(&args.param).ok_or_else(|| {
        ReportError::input(format!(
            "--param {}: the parameters that can be calibrated are youngs_modulus and thickness",
            safe(&args.param)
        ))
    })
}

/// What `calibrate` found: the beam's (a mechanism's beam mechanism's) figures against the
/// data before and after.
#[derive(Debug, Serialize)]
pub struct CalibrateOutput {
    #[serde(flatten)]
    calibration: Calibration,
    /// `value / nominal` (on a mechanism, the ratio every flexure's value was scaled by).
    ratio: f64,
    scene: String,
    data: String,
    seconds: f64,
    /// The scene is a mechanism (its beam mechanism is calibrated).
    #[serde(skip)]
    mechanism: bool,
}

/// A beam's (`mechanism`: a beam mechanism's) figures against the data, after the label.
fn figure_line(f: &Figures, mechanism: bool) -> String {
    if mechanism {
        format!(
            "max pos {:.3e} L, max ang {:.3e} rad, reaction rms {:.3e} max {:.3e}; J {:.4e}",
            f.max_pos_err,
            f.max_ang_err,
            f.rms_force_err.unwrap_or(0.0),
            f.max_force(),
            f.objective
        )
    } else {
        format!(
            "rms pos {:.3e}, max pos {:.3e} L; rms ang {:.3e}, max ang {:.3e} rad; J {:.4e}",
            f.rms_pos_err, f.max_pos_err, f.rms_ang_err, f.max_ang_err, f.objective
        )
    }
}

impl fmt::Display for CalibrateOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.calibration;
        let mechanism = self.mechanism;
        writeln!(
            f,
            "scene: {} ({}truth: measured data {})",
            safe(&self.scene),
            if mechanism { "mechanism; " } else { "" },
            safe(&self.data)
        )?;
        let unit = match c.param {
            BeamParam::YoungsModulus => "Pa",
            BeamParam::Thickness => "m",
        };
        let edge = if c.at_edge {
            "; at the edge of the searched range: the beam does not explain the data well"
        } else {
            ""
        };
        if mechanism {
            writeln!(
                f,
                "{} of every flexure scaled by {}: flexure 1's nominal {} {unit} -> calibrated \
                 {} {unit}{edge}",
                c.param.name(),
                num(self.ratio),
                num(c.nominal),
                num(c.value),
            )?;
        } else {
            writeln!(
                f,
                "{}: nominal {} {unit} -> calibrated {} {unit} ({}x){edge}",
                c.param.name(),
                num(c.nominal),
                num(c.value),
                num(self.ratio),
            )?;
        }
        let what = if mechanism { "beam mechanism" } else { "beam" };
        for (label, e) in [("nominal", &c.nominal_figures), ("calibrated", &c.figures)] {
            writeln!(
                f,
                "{what} against the data, {label:<10}: {}",
                figure_line(e, mechanism)
            )?;
        }
        writeln!(f, "{} evaluations, {:.2} s", c.evaluations, self.seconds)
    }
}

/// `prbfit calibrate` on `scene`.
pub fn calibrate_scene(
    scene: &Scene,
    args: &CalibrateArgs,
    ctl: &mut Control<'_>,
) -> Result<CalibrateOutput> {
    let param = param(args)?;
    let Some(truth) = &scene.truth else {
        return Err(ReportError::input(format!(
            "\"{}\": {}",
            safe(&scene.name),
            CalibrateError::NoData
        )));
    };
    let data = truth.file.clone();
    let (scene, _) = resolve_scene(scene, &ctl.cancel)?;
    let t0 = Instant::now();
    let calibration =
        calibrate(&scene, param, Resolution::default()).map_err(|e| ReportError::failed(&e))?;
    let out = CalibrateOutput {
        ratio: calibration.value / calibration.nominal,
        calibration,
        scene: scene.name.clone(),
        data,
        seconds: t0.elapsed().as_secs_f64(),
        mechanism: scene.mechanism.is_some(),
    };
    Ok(out)
}
