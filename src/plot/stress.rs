//! The stress chart (`plot --kind stress`, DESIGN §11): along every load path or drive, the
//! largest fibre stress of each flexure (MPa) against the fraction of the path's end load
//! (a drive's stroke): the truth's (the beam or beam mechanism, grey) and each model's own
//! estimate (its colour, [`crate::prb::PrbSolver::max_stress`]), the marker telling the paths
//! apart and a mechanism's second and later flexures dashed; the allowable stress a red
//! dashed line and each path's stroke limit a red dotted vertical line. Every kind of scene
//! goes through the study, so a cantilever's and a mechanism's charts are one code. Measured
//! data has no stress, so a data scene has no such chart.

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::study::Study;

use super::errors::{bounds, draw_markers};
use super::{
    drawing, model_colour, rgb, ChartKind, Figure, PlotError, PlotModel, Unfollowed, BEAM_RGB,
    FONT, MODEL_RGB, TARGET_RGB,
};

/// What the stress chart draws.
#[derive(Debug, Clone, PartialEq)]
pub struct StressChart {
    /// One label per path ("path 1", "drive 2").
    pub paths: Vec<String>,
    /// The truth's curves.
    pub truth: Vec<StressCurve>,
    /// Each model's curves, in the models' order, with its legend name.
    pub models: Vec<(String, Vec<StressCurve>)>,
    /// The distinct allowable stresses, MPa.
    pub allowable: Vec<f64>,
    /// Each path's stroke limit (fraction), where it has one.
    pub limits: Vec<Option<f64>>,
    /// Whether the x axis is a drive's stroke (a mechanism) or a load path's end load.
    pub mechanism: bool,
}

/// One flexure along one path.
#[derive(Debug, Clone, PartialEq)]
pub struct StressCurve {
    /// Index into [`StressChart::paths`].
    pub path: usize,
    /// From 0.
    pub flexure: usize,
    /// `(fraction, MPa)` in path order, the unloaded state first.
    pub points: Vec<(f64, f64)>,
}

/// The curves of `cases` (per path, each case's flexures' stresses in units of each
/// flexure's `youngs`), one per path and flexure, from the unloaded state.
fn curves<'a>(
    paths: impl Iterator<Item = (usize, &'a [crate::mech::MechCase])>,
    youngs: &[f64],
) -> Vec<StressCurve> {
    let mut out = Vec::new();
    for (p, cases) in paths {
        for (f, e) in youngs.iter().enumerate() {
            let mut points = vec![(0.0, 0.0)];
            points.extend(cases.iter().filter_map(|c| {
                let s = c.flexures.get(f)?.stress?;
                Some((c.fraction, s.max * e / 1e6))
            }));
            out.push(StressCurve {
                path: p,
                flexure: f,
                points,
            });
        }
    }
    out
}

impl StressChart {
    /// The chart of `study` with `models` (each judged over the cases it can follow).
    /// [`PlotError::NoStress`] on measured data.
    pub fn build(study: &Study, models: &[PlotModel]) -> Result<StressChart, PlotError> {
        if study.is_measured() {
            return Err(PlotError::NoStress {
                scene: study.scene().name.clone(),
            });
        }
        let mechanism = study.scene().mechanism.is_some();
        let flexures = &study.mechanism().flexures;
        let youngs: Vec<f64> = flexures.iter().map(|f| f.beam.youngs_modulus).collect();
        let truth = curves(
            study
                .truth()
                .iter()
                .enumerate()
                .map(|(p, c)| (p, c.as_slice())),
            &youngs,
        );
        let mut out_models = Vec::with_capacity(models.len());
        for m in models {
            // A model that follows nothing has no curve (eval and the other kinds say why).
            let cases = study.judge_followed(&m.matrix).map(|j| j.cases);
            let mut per_path: Vec<Vec<crate::mech::MechCase>> =
                vec![Vec::new(); study.truth().len()];
            for c in cases.unwrap_or_default() {
                if let Some(p) = per_path.get_mut(c.path - 1) {
                    p.push(c.model);
                }
            }
            let c = curves(
                per_path.iter().enumerate().map(|(p, c)| (p, c.as_slice())),
                &youngs,
            );
            out_models.push((m.name.clone(), c));
        }
        let mut allowable: Vec<f64> = flexures
            .iter()
            .filter_map(|f| f.beam.allowable_stress)
            .map(|a| a / 1e6)
            .collect();
        allowable.sort_by(f64::total_cmp);
        allowable.dedup();
        let limits = study
            .stroke_limits()
            .map(|l| l.iter().map(|l| l.fraction).collect())
            .unwrap_or_else(|| vec![None; study.truth().len()]);
        let word = if mechanism { "drive" } else { "path" };
        Ok(StressChart {
            paths: (1..=study.truth().len())
                .map(|p| format!("{word} {p}"))
                .collect(),
            truth,
            models: out_models,
            allowable,
            limits,
            mechanism,
        })
    }
}

impl Figure {
    /// The stress figure (`--kind stress`) of `study` with `models`; a model that stops
    /// short of a path's end is drawn as far as it got, and listed.
    pub fn stress(study: &Study, models: &[PlotModel]) -> Result<Figure, PlotError> {
        if models.len() > MODEL_RGB.len() {
            return Err(PlotError::TooManyModels {
                max: MODEL_RGB.len(),
                got: models.len(),
            });
        }
        let chart = StressChart::build(study, models)?;
        let mut unfollowed = Vec::new();
        for (name, curves) in &chart.models {
            for (p, cases) in study.truth().iter().enumerate() {
                // The unloaded point is not a case.
                let reached = curves
                    .iter()
                    .find(|c| c.path == p)
                    .map_or(0, |c| c.points.len() - 1);
                if reached < cases.len() {
                    unfollowed.push(Unfollowed {
                        model: name.clone(),
                        path: p + 1,
                        reached,
                        steps: cases.len(),
                        reason: None,
                    });
                }
            }
        }
        Ok(Figure {
            kind: ChartKind::Stress,
            title: study.scene().name.clone(),
            shapes: None,
            errors: None,
            force_stroke: None,
            stress: Some(chart),
            unfollowed,
        })
    }
}

/// Draws the chart onto `area`.
pub fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &StressChart,
) -> Result<(), PlotError> {
    let area = area
        .titled("Largest fibre stress against load", (FONT, 18))
        .map_err(drawing)?;
    let values = chart
        .truth
        .iter()
        .chain(chart.models.iter().flat_map(|(_, c)| c))
        .flat_map(|c| c.points.iter().map(|p| p.1));
    let yb = bounds(values.chain(chart.allowable.iter().copied()));
    let area = area.margin(5, 5, 5, 20);
    let mut ctx = ChartBuilder::on(&area)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..1.0, yb[0]..yb[1])
        .map_err(drawing)?;
    ctx.configure_mesh()
        .x_desc(if chart.mechanism {
            "fraction of the drive's stroke"
        } else {
            "fraction of the load path's end load"
        })
        .y_desc("largest fibre stress (MPa)")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(drawing)?;

    let target = rgb(TARGET_RGB).stroke_width(2);
    for (i, &a) in chart.allowable.iter().enumerate() {
        let anno = ctx
            .draw_series(DashedLineSeries::new([(0.0, a), (1.0, a)], 10, 6, target))
            .map_err(drawing)?;
        if i == 0 {
            anno.label("allowable stress").legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (9, 0)], target)
                    + PathElement::new(vec![(15, 0), (24, 0)], target)
            });
        }
    }
    let limit_style = rgb(TARGET_RGB).stroke_width(1);
    let mut labelled = false;
    for l in chart.limits.iter().flatten() {
        let anno = ctx
            .draw_series(DashedLineSeries::new(
                [(*l, yb[0]), (*l, yb[1])],
                3,
                4,
                limit_style,
            ))
            .map_err(drawing)?;
        if !labelled {
            labelled = true;
            anno.label("stroke limit").legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (4, 0)], limit_style)
                    + PathElement::new(vec![(10, 0), (14, 0)], limit_style)
            });
        }
    }

    let series = std::iter::once(("beam".to_string(), rgb(BEAM_RGB), &chart.truth)).chain(
        chart
            .models
            .iter()
            .enumerate()
            .map(|(m, (name, c))| (name.clone(), model_colour(m), c)),
    );
    for (name, colour, curves) in series {
        let style = colour.stroke_width(2);
        for (k, curve) in curves.iter().enumerate() {
            let pts: Vec<(f64, f64)> = curve
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            if curve.flexure == 0 {
                let anno = ctx
                    .draw_series(LineSeries::new(pts.iter().copied(), style))
                    .map_err(drawing)?;
                if k == 0 {
                    anno.label(name.as_str())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
                }
            } else {
                ctx.draw_series(DashedLineSeries::new(pts.iter().copied(), 8, 4, style))
                    .map_err(drawing)?;
            }
            draw_markers(&mut ctx, curve.path, &pts[1.min(pts.len())..], colour)?;
        }
    }
    ctx.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(drawing)
}
