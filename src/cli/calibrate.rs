//! `prbfit calibrate`: one parameter of a data scene's beam fitted to its measurements
//! (DESIGN §9), reported with the residual before and after.

use std::fmt;
use std::time::Instant;

use anyhow::Result;
use serde::Serialize;

use prbfit::beam::Resolution;
use prbfit::eval::{
    calibrate, calibrate_mechanism, BeamParam, CalibrateError, Calibration, ErrorFigures,
};
use prbfit::mech::figures::MechFigures;

use super::args::CalibrateArgs;
use super::output::{emit, num, safe};
use super::{bad, load_scene, resolve_scene};

/// What `calibrate` found: `F` is the figures the beam is judged by (a cantilever's, or a
/// mechanism's beam mechanism's).
#[derive(Debug, Serialize)]
pub struct CalibrateOutput<F> {
    #[serde(flatten)]
    calibration: Calibration<F>,
    /// `value / nominal` (on a mechanism, the ratio every flexure's value was scaled by).
    ratio: f64,
    scene: String,
    data: String,
    seconds: f64,
}

/// How a report's line gives a beam's figures against the data.
pub trait FigureLine {
    /// What is judged ("beam", "beam mechanism").
    const WHAT: &'static str;
    /// The figures, after the label.
    fn line(&self) -> String;
}

impl FigureLine for ErrorFigures {
    const WHAT: &'static str = "beam";
    fn line(&self) -> String {
        format!(
            "rms pos {:.3e}, max pos {:.3e} L; rms ang {:.3e}, max ang {:.3e} rad; J {:.4e}",
            self.rms_pos_err, self.max_pos_err, self.rms_ang_err, self.max_ang_err, self.objective
        )
    }
}

impl FigureLine for MechFigures {
    const WHAT: &'static str = "beam mechanism";
    fn line(&self) -> String {
        format!(
            "max pos {:.3e} L, max ang {:.3e} rad, reaction rms {:.3e} max {:.3e}; J {:.4e}",
            self.max_pos_err,
            self.max_ang_err,
            self.rms_force_err,
            self.max_force_err,
            self.objective
        )
    }
}

impl<F: FigureLine> fmt::Display for CalibrateOutput<F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.calibration;
        let mechanism = F::WHAT != ErrorFigures::WHAT;
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
        for (label, e) in [("nominal", &c.nominal_figures), ("calibrated", &c.figures)] {
            writeln!(f, "{} against the data, {label:<10}: {}", F::WHAT, e.line())?;
        }
        writeln!(f, "{} evaluations, {:.2} s", c.evaluations, self.seconds)
    }
}

impl<F: Serialize + FigureLine> CalibrateOutput<F> {
    /// The report of `calibration` on `scene`'s data `data`, started at `t0`.
    fn emit(
        calibration: Calibration<F>,
        scene: &prbfit::scene::Scene,
        data: String,
        t0: Instant,
        json: bool,
    ) -> Result<()> {
        let out = CalibrateOutput {
            ratio: calibration.value / calibration.nominal,
            calibration,
            scene: scene.name.clone(),
            data,
            seconds: t0.elapsed().as_secs_f64(),
        };
        emit(&out, json)
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
        return CalibrateOutput::emit(calibration, &scene, data, t0, args.common.json);
    }
    let calibration = calibrate(&scene, param, Resolution::default())?;
    CalibrateOutput::emit(calibration, &scene, data, t0, args.common.json)
}
