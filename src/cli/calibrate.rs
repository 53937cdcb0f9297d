//! `prbfit calibrate`: one parameter of a data scene's beam fitted to its measurements
//! (DESIGN §9), reported with the residual before and after.

use std::fmt;
use std::time::Instant;

use anyhow::Result;
use serde::Serialize;

use prbfit::beam::Resolution;
use prbfit::eval::{
    calibrate, calibrate_mechanism, BeamParam, CalibrateError, Calibration, MechCalibration,
};

use super::args::CalibrateArgs;
use super::output::{emit, num, safe};
use super::{bad, load_scene, resolve_scene};

/// What `calibrate` found.
#[derive(Debug, Serialize)]
pub struct CalibrateOutput {
    #[serde(flatten)]
    calibration: Calibration,
    /// `value / nominal`.
    ratio: f64,
    scene: String,
    data: String,
    seconds: f64,
}

impl fmt::Display for CalibrateOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.calibration;
        writeln!(
            f,
            "scene: {} (truth: measured data {})",
            safe(&self.scene),
            safe(&self.data)
        )?;
        let unit = match c.param {
            BeamParam::YoungsModulus => "Pa",
            BeamParam::Thickness => "m",
        };
        writeln!(
            f,
            "{}: nominal {} {unit} -> calibrated {} {unit} ({}x){}",
            c.param.name(),
            num(c.nominal),
            num(c.value),
            num(self.ratio),
            if c.at_edge {
                "; at the edge of the searched range: the beam does not explain the data well"
            } else {
                ""
            }
        )?;
        for (label, e) in [("nominal", &c.nominal_figures), ("calibrated", &c.figures)] {
            writeln!(
                f,
                "beam against the data, {label:<10}: rms pos {:.3e}, max pos {:.3e} L; rms ang \
                 {:.3e}, max ang {:.3e} rad; J {:.4e}",
                e.rms_pos_err, e.max_pos_err, e.rms_ang_err, e.max_ang_err, e.objective
            )?;
        }
        writeln!(f, "{} evaluations, {:.2} s", c.evaluations, self.seconds)
    }
}

/// What `calibrate` found on a mechanism data scene.
#[derive(Debug, Serialize)]
pub struct MechCalibrateOutput {
    #[serde(flatten)]
    calibration: MechCalibration,
    /// `value / nominal`, the ratio every flexure's value was scaled by.
    ratio: f64,
    scene: String,
    data: String,
    seconds: f64,
}

impl fmt::Display for MechCalibrateOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.calibration;
        writeln!(
            f,
            "scene: {} (mechanism; truth: measured data {})",
            safe(&self.scene),
            safe(&self.data)
        )?;
        let unit = match c.param {
            BeamParam::YoungsModulus => "Pa",
            BeamParam::Thickness => "m",
        };
        writeln!(
            f,
            "{} of every flexure scaled by {}: flexure 1's nominal {} {unit} -> calibrated {} \
             {unit}{}",
            c.param.name(),
            num(self.ratio),
            num(c.nominal),
            num(c.value),
            if c.at_edge {
                "; at the edge of the searched range: the beam does not explain the data well"
            } else {
                ""
            }
        )?;
        for (label, e) in [("nominal", &c.nominal_figures), ("calibrated", &c.figures)] {
            writeln!(
                f,
                "beam mechanism against the data, {label:<10}: max pos {:.3e} L, max ang {:.3e} \
                 rad, reaction rms {:.3e} max {:.3e}; J {:.4e}",
                e.max_pos_err, e.max_ang_err, e.rms_force_err, e.max_force_err, e.objective
            )?;
        }
        writeln!(f, "{} evaluations, {:.2} s", c.evaluations, self.seconds)
    }
}

/// Runs `prbfit calibrate`.
pub fn run(args: CalibrateArgs) -> Result<()> {
    let param = BeamParam::from_name(&args.param).ok_or_else(|| {
        bad(format!(
            "--param {}: the parameters that can be calibrated are youngs_modulus and thickness",
            safe(&args.param)
        ))
    })?;
    let scene = load_scene(&args.common)?;
    let Some(truth) = &scene.truth else {
        return Err(bad(format!(
            "\"{}\": {}",
            safe(&scene.name),
            CalibrateError::NoData
        )));
    };
    let data = truth.file.clone();
    let (scene, _) = resolve_scene(&scene)?;
    let t0 = Instant::now();
    if scene.mechanism.is_some() {
        let calibration = calibrate_mechanism(&scene, param, Resolution::default())?;
        let out = MechCalibrateOutput {
            ratio: calibration.value / calibration.nominal,
            calibration,
            scene: scene.name.clone(),
            data,
            seconds: t0.elapsed().as_secs_f64(),
        };
        return emit(&out, args.common.json);
    }
    let calibration = calibrate(&scene, param, Resolution::default())?;
    let out = CalibrateOutput {
        ratio: calibration.value / calibration.nominal,
        calibration,
        scene: scene.name.clone(),
        data,
        seconds: t0.elapsed().as_secs_f64(),
    };
    emit(&out, args.common.json)
}
