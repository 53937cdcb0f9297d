//! What to draw, built from the library's results: the beam's baseline and each PRB model
//! followed along the same load paths ([`Baseline::follow`], the loop every comparison goes
//! through). The drawing code reads only the structs made here.

use crate::text::bounded_prec;
use std::cell::RefCell;
use std::ops::ControlFlow;

use crate::eval::{Baseline, CaseError};
use crate::prb::{PrbMatrix, PrbSolver};
use crate::scene::Scene;

use super::errors::{ErrorCurve, ErrorPoint, ErrorsChart, ModelErrors};
use super::shapes::{Linkage, ModelShapes, ShapesChart};
use super::{ChartKind, Figure, PlotError, PlotModel, Unfollowed, MODEL_RGB};

/// One model's equilibrium at one case: its tip error and its linkage.
struct ModelCase {
    error: CaseError,
    points: Vec<[f64; 2]>,
}

impl Figure {
    /// The figure of `models` against `baseline` (the scene's beam over its load paths, as
    /// sampled): the shapes of load path `path` (1-based) and the errors of every path, as
    /// `kind` asks. A model that cannot follow a path is drawn up to where it stopped and
    /// listed in [`Figure::unfollowed`].
    pub fn build(
        scene: &Scene,
        baseline: &Baseline,
        models: &[PlotModel],
        path: usize,
        kind: ChartKind,
    ) -> Result<Figure, PlotError> {
        if !kind.has_shapes() && !kind.has_errors() {
            return Err(PlotError::KindNotForScene {
                kind,
                mechanism: false,
            });
        }
        let count = baseline.paths.len();
        if path == 0 || path > count {
            return Err(PlotError::NoSuchPath { path, count });
        }
        if models.len() > MODEL_RGB.len() {
            return Err(PlotError::TooManyModels {
                max: MODEL_RGB.len(),
                got: models.len(),
            });
        }
        // Where each path's cases start in the baseline.
        let mut offsets = Vec::with_capacity(count + 1);
        offsets.push(0);
        for p in &baseline.paths {
            let last = offsets.last().copied().unwrap_or(0);
            offsets.push((last + p.steps as usize).min(baseline.case_count()));
        }
        let mut unfollowed = Vec::new();
        let followed: Vec<Vec<Option<ModelCase>>> = models
            .iter()
            .map(|m| {
                let cases = follow(baseline, &m.matrix);
                for (i, w) in offsets.windows(2).enumerate() {
                    let reached = cases[w[0]..w[1]].iter().filter(|c| c.is_some()).count();
                    if reached < w[1] - w[0] {
                        unfollowed.push(Unfollowed {
                            model: m.name.clone(),
                            path: i + 1,
                            reached,
                            steps: w[1] - w[0],
                            reason: None,
                        });
                    }
                }
                cases
            })
            .collect();

        let shapes = kind.has_shapes().then(|| {
            let range = offsets[path - 1]..offsets[path];
            let end = baseline.paths[path - 1].end;
            ShapesChart {
                title: format!(
                    "Deformed shapes, load path {path} of {count} ({})",
                    load_label(end.alpha_x, end.alpha_y, end.beta)
                ),
                // A data scene's solutions are the measured tips, without shapes: the tips
                // are drawn as markers, and the beam beside them is added by
                // `Figure::with_beam_beside`.
                beam: if baseline.measured.is_some() {
                    Vec::new()
                } else {
                    baseline.solutions[range.clone()]
                        .iter()
                        .map(|s| s.shape.iter().map(|p| [p.x, p.y]).collect())
                        .collect()
                },
                measured: if baseline.measured.is_some() {
                    baseline.solutions[range.clone()]
                        .iter()
                        .map(|s| [s.tip.a, s.tip.b])
                        .collect()
                } else {
                    Vec::new()
                },
                models: models
                    .iter()
                    .zip(&followed)
                    .map(|(m, cases)| ModelShapes {
                        name: m.name.clone(),
                        linkages: cases[range.clone()]
                            .iter()
                            .flatten()
                            .map(|c| Linkage {
                                joints: joints(&m.matrix, &c.points),
                                points: c.points.clone(),
                            })
                            .collect(),
                    })
                    .collect(),
            }
        });

        let errors = kind.has_errors().then(|| ErrorsChart {
            paths: baseline
                .paths
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    format!(
                        "path {}: {}",
                        i + 1,
                        load_label(p.end.alpha_x, p.end.alpha_y, p.end.beta)
                    )
                })
                .collect(),
            models: models
                .iter()
                .zip(&followed)
                .map(|(m, cases)| ModelErrors {
                    name: m.name.clone(),
                    curves: offsets
                        .windows(2)
                        .enumerate()
                        .map(|(i, w)| error_curve(i, &cases[w[0]..w[1]]))
                        .collect(),
                })
                .collect(),
            target_pos_percent: scene.accuracy.max_pos_err * 100.0,
            target_ang_deg: scene.accuracy.max_ang_err.to_degrees(),
        });

        Ok(Figure {
            kind,
            title: scene.name.clone(),
            shapes,
            errors,
            force_stroke: None,
            stress: None,
            unfollowed,
        })
    }
}

impl Figure {
    /// The figure with `shapes` (one centre line per case of the drawn path, units of L) as
    /// the beam drawn beside a data scene's measured tips.
    pub fn with_beam_beside(mut self, shapes: Vec<Vec<[f64; 2]>>) -> Figure {
        if let Some(chart) = self.shapes.as_mut() {
            chart.beam = shapes;
        }
        self
    }
}

/// Every case of the baseline with the model's equilibrium there, or `None` past where the
/// model stopped on that path.
fn follow(baseline: &Baseline, matrix: &PrbMatrix) -> Vec<Option<ModelCase>> {
    let solver = PrbSolver::new(matrix, baseline.model.axial_compliance());
    // `follow` visits the reached cases in order and hands over the missed rest of a path,
    // so one running list lines up with the baseline's cases (both callbacks append to it).
    let cases: RefCell<Vec<Option<ModelCase>>> =
        RefCell::new(Vec::with_capacity(baseline.case_count()));
    let outcome = baseline.follow(
        &solver,
        |beam, prb| {
            cases.borrow_mut().push(Some(ModelCase {
                error: CaseError::new(prb.load, beam.tip, prb.tip),
                points: solver.joint_positions(prb.q),
            }))
        },
        |missed, _| {
            cases.borrow_mut().extend(missed.iter().map(|_| None));
            ControlFlow::Continue(())
        },
    );
    // With `Continue` the loop never stops early, so there is no error to report: the gaps
    // are the report.
    debug_assert!(outcome.is_ok());
    let mut cases = cases.into_inner();
    cases.resize_with(baseline.case_count(), || None);
    cases
}

/// The revolute joints of the chain: the root end of every row with a torsion spring
/// (`points` holds the root and each segment's end, so row i starts at point i).
fn joints(matrix: &PrbMatrix, points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    matrix
        .rows()
        .iter()
        .zip(points)
        .filter(|(row, _)| row.has_revolute())
        .map(|(_, p)| *p)
        .collect()
}

/// One path's errors, from zero load (where every model is exact) to the reached cases.
fn error_curve(path: usize, cases: &[Option<ModelCase>]) -> ErrorCurve {
    let steps = cases.len().max(1) as f64;
    let mut points = vec![ErrorPoint {
        fraction: 0.0,
        pos_err_percent: 0.0,
        ang_err_deg: 0.0,
    }];
    for (k, c) in cases.iter().enumerate() {
        let Some(c) = c else { break };
        points.push(ErrorPoint {
            fraction: (k + 1) as f64 / steps,
            pos_err_percent: c.error.pos_err * 100.0,
            ang_err_deg: c.error.ang_err.to_degrees(),
        });
    }
    ErrorCurve { path, points }
}

/// A load in the paper's symbols, for titles and legends.
fn load_label(alpha_x: f64, alpha_y: f64, beta: f64) -> String {
    format!(
        "αx = {}, αy = {}, β = {}",
        bounded_prec(alpha_x, 4),
        bounded_prec(alpha_y, 4),
        bounded_prec(beta, 4)
    )
}
