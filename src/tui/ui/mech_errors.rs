//! A mechanism's error chart (DESIGN §8): the reaction error (% of each prescribed
//! coordinate's largest reaction) against the fraction of each drive, one line per drive,
//! with the scene's `max_force_err` as a red line; a mechanism with no prescribed coordinate
//! shows the stage position error (% of flexure 1's `L`) against `max_pos_err` instead. The
//! compared model as grey dots under the model's lines. On a mechanism data scene (DESIGN
//! §9) the errors are against the measured cases, and the beam mechanism's own error against
//! them is a grey line per drive under the model's, named in a legend on the bottom border.

use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::symbols::Marker;
use ratatui::widgets::{Block, Borders, Dataset, GraphType, Paragraph};
use ratatui::Frame;

use crate::plot::errors::bounds;
use crate::scene::Accuracy;

use super::super::app::App;
use super::super::worker::{CaseErrors, MechBaselineView, MechModelView};
use super::Palette;

/// Which error the chart shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MechErrorKind {
    /// The reaction error of the prescribed coordinates.
    Force,
    /// The stage position error of the loaded coordinates.
    Position,
}

/// What the mechanism error chart draws.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// The exact mechanism the model was judged on.
    pub exact: Option<&'a MechBaselineView>,
    /// The model's errors.
    pub model: Option<&'a MechModelView>,
    /// The compared model's, on the same exact mechanism.
    pub compare: Option<&'a MechModelView>,
    /// On a data scene, the beam mechanism's errors against the data, per drive (empty
    /// when it cannot follow the measured drives); `None` when the truth is the beam.
    pub beam: Option<Vec<Vec<CaseErrors>>>,
    /// The scene's targets.
    pub accuracy: Accuracy,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The mechanism error chart of `app`.
    pub fn new(app: &'a App) -> View<'a> {
        View {
            exact: app.mech_exact.as_deref(),
            model: app.mech_model.as_ref(),
            compare: app.shown_mech_compare().map(|(_, v)| v),
            beam: app.mech_exact.as_ref().and_then(|e| {
                let (w, w_f) = (app.scene.fit.angle_weight, app.scene.fit.force_weight);
                let judged = e.beam_against_data(w, w_f)?;
                let mut per_drive: Vec<Vec<CaseErrors>> = vec![Vec::new(); e.cases.len()];
                for c in judged.iter().flat_map(|j| &j.cases) {
                    if let Some(d) = per_drive.get_mut(c.path.wrapping_sub(1)) {
                        d.push(CaseErrors {
                            pos: c.pos_err,
                            ang: c.ang_err,
                            force: c.force_err,
                        });
                    }
                }
                Some(per_drive)
            }),
            accuracy: app.scene.accuracy,
            pal: Palette { mono: app.mono },
        }
    }
}

/// The error the chart shows for `exact`: the reaction error when any drive prescribes a
/// coordinate, else the position error.
pub fn kind_of(exact: &MechBaselineView) -> MechErrorKind {
    let prescribes = exact
        .mechanism
        .drives
        .iter()
        .any(|d| d.coordinates.iter().any(|c| c.is_prescribed()));
    if prescribes {
        MechErrorKind::Force
    } else {
        MechErrorKind::Position
    }
}

/// One series per drive, in %: the error against the drive's fraction, from rest.
fn series(
    errors: &[Vec<CaseErrors>],
    exact: &MechBaselineView,
    kind: MechErrorKind,
) -> Vec<Vec<(f64, f64)>> {
    let value = |e: &CaseErrors| match kind {
        MechErrorKind::Force => e.force * 100.0,
        MechErrorKind::Position => e.pos * 100.0,
    };
    errors
        .iter()
        .zip(&exact.cases)
        .map(|(errors, cases)| {
            std::iter::once((0.0, 0.0))
                .chain(
                    errors
                        .iter()
                        .zip(cases)
                        .map(|(e, c)| (c.fraction, value(e)))
                        .filter(|p| p.1.is_finite()),
                )
                .collect()
        })
        .collect()
}

/// Draws the mechanism error chart.
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    let pal = view.pal;
    let (Some(exact), Some(model)) = (view.exact, view.model) else {
        let block = Block::default().borders(Borders::ALL).title(" Errors ");
        frame.render_widget(Paragraph::new("").block(block), area);
        return;
    };
    let kind = kind_of(exact);
    let (title, unit, target) = match kind {
        MechErrorKind::Force => (
            " Reaction error ",
            "% of max",
            view.accuracy.max_force_err * 100.0,
        ),
        MechErrorKind::Position => (
            " Stage position error ",
            "%L",
            view.accuracy.max_pos_err * 100.0,
        ),
    };
    let mut block = Block::default().borders(Borders::ALL).title(title);
    if let Some(b) = &view.beam {
        let beam = b.iter().any(|d| !d.is_empty());
        block = block.title_bottom(super::errors::data_legend(pal, "─", beam));
    }
    let lines = series(&model.errors, exact, kind);
    let compared = view
        .compare
        .map(|c| series(&c.errors, exact, kind))
        .unwrap_or_default();
    let beam = view
        .beam
        .as_ref()
        .map(|b| series(b, exact, kind))
        .unwrap_or_default();
    let yb = bounds(
        lines
            .iter()
            .chain(&compared)
            .chain(&beam)
            .flatten()
            .map(|p| p.1),
    );
    let target_line = [(0.0, target), (1.0, target)];
    // The compared model and the beam mechanism against the data under the model's lines.
    let mut datasets = super::errors::layered(pal, &compared, &beam, &lines, false);
    // The target, where it falls inside the plotted range.
    if target <= yb[1] {
        datasets.push(
            Dataset::default()
                .marker(Marker::Braille)
                .graph_type(GraphType::Line)
                .style(pal.fg(Color::Red))
                .data(&target_line),
        );
    }
    super::errors::render_chart(frame, area, (datasets, block), "drive", unit, yb);
}
