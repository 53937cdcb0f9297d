//! The tip-error chart: for every load path, each model's tip position error (% of L) and
//! tip angle error (degrees) against the fraction of the path's end load, with the scene's
//! accuracy targets as dashed lines. Colour tells the models apart, the marker the paths.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::{drawing, model_colour, rgb, PlotError, FONT, TARGET_RGB};

/// What the error chart draws.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorsChart {
    /// One label per load path ("path 1: αx = 0, αy = 5, β = 0").
    pub paths: Vec<String>,
    /// Each model's curves, in the models' order.
    pub models: Vec<ModelErrors>,
    /// `[accuracy] max_pos_err`, % of L.
    pub target_pos_percent: f64,
    /// `[accuracy] max_ang_err`, degrees.
    pub target_ang_deg: f64,
}

/// One model's error curves.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelErrors {
    /// The legend's text.
    pub name: String,
    /// One per load path.
    pub curves: Vec<ErrorCurve>,
}

/// One model along one load path, from zero load to where it got.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorCurve {
    /// Index into [`ErrorsChart::paths`].
    pub path: usize,
    /// In load order.
    pub points: Vec<ErrorPoint>,
}

/// The tip error at one case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorPoint {
    /// The case's load as a fraction of the path's end load.
    pub fraction: f64,
    /// `e_pos`, % of L.
    pub pos_err_percent: f64,
    /// `e_ang`, degrees (signed).
    pub ang_err_deg: f64,
}

/// Which error a panel shows.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Quantity {
    Position,
    Angle,
}

impl Quantity {
    fn of(self, p: &ErrorPoint) -> f64 {
        match self {
            Quantity::Position => p.pos_err_percent,
            Quantity::Angle => p.ang_err_deg,
        }
    }
}

/// Draws the chart onto `area`: position error above, angle error below.
pub fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &ErrorsChart,
) -> Result<(), PlotError> {
    let area = area
        .titled("Tip error against load", (FONT, 18))
        .map_err(drawing)?;
    let (_, h) = area.dim_in_pixel();
    let (top, bottom) = area.split_vertically(h / 2);
    panel(&top, chart, Quantity::Position)?;
    panel(&bottom, chart, Quantity::Angle)
}

/// One panel: every model's curve along every path, and the target lines.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &ErrorsChart,
    quantity: Quantity,
) -> Result<(), PlotError> {
    let (y_desc, target) = match quantity {
        Quantity::Position => ("tip position error (% of L)", chart.target_pos_percent),
        Quantity::Angle => ("tip angle error (degrees)", chart.target_ang_deg),
    };
    // The angle error has a sign; the target bounds it on both sides.
    let targets: Vec<f64> = match quantity {
        Quantity::Position => vec![target],
        Quantity::Angle => vec![target, -target],
    };
    let values = chart
        .models
        .iter()
        .flat_map(|m| &m.curves)
        .flat_map(|c| &c.points)
        .map(|p| quantity.of(p));
    let yb = bounds(values.chain(targets.iter().copied()));
    let area = area.margin(5, 5, 5, 20);
    let mut ctx = ChartBuilder::on(&area)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, yb[0]..yb[1])
        .map_err(drawing)?;
    ctx.configure_mesh()
        .x_desc("fraction of the load path's end load")
        .y_desc(y_desc)
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(drawing)?;

    let target_style = rgb(TARGET_RGB).stroke_width(2);
    for (i, &t) in targets.iter().enumerate() {
        if !t.is_finite() {
            continue;
        }
        let anno = ctx
            .draw_series(DashedLineSeries::new(
                [(0.0, t), (1.0, t)],
                10,
                6,
                target_style,
            ))
            .map_err(drawing)?;
        if i == 0 && quantity == Quantity::Position {
            anno.label("target").legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (9, 0)], target_style)
                    + PathElement::new(vec![(15, 0), (24, 0)], target_style)
            });
        }
    }

    for (m, model) in chart.models.iter().enumerate() {
        let style = model_colour(m).stroke_width(2);
        for (c, curve) in model.curves.iter().enumerate() {
            let pts: Vec<(f64, f64)> = curve
                .points
                .iter()
                .map(|p| (p.fraction, quantity.of(p)))
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            let anno = ctx
                .draw_series(LineSeries::new(pts.iter().copied(), style))
                .map_err(drawing)?;
            if c == 0 && quantity == Quantity::Position {
                anno.label(model.name.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
            }
            draw_markers(
                &mut ctx,
                curve.path,
                &pts[1.min(pts.len())..],
                model_colour(m),
            )?;
        }
    }

    // The paths' markers in the legend, in grey, when there is more than one path.
    if quantity == Quantity::Position && chart.paths.len() > 1 {
        for (i, label) in chart.paths.iter().enumerate() {
            let anno = ctx
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(drawing)?
                .label(label.as_str());
            let grey = RGBColor(0x50, 0x50, 0x50);
            // One closure type per marker: plotters' legend takes one element type.
            match i % MARKERS {
                0 => anno.legend(move |(x, y)| Circle::new((x + 12, y), 4, grey.filled())),
                1 => anno.legend(move |(x, y)| TriangleMarker::new((x + 12, y), 5, grey.filled())),
                2 => anno.legend(move |(x, y)| {
                    Rectangle::new([(x + 8, y - 4), (x + 16, y + 4)], grey.filled())
                }),
                _ => anno.legend(move |(x, y)| Cross::new((x + 12, y), 4, grey.stroke_width(2))),
            };
        }
    }

    if quantity == Quantity::Position {
        ctx.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(drawing)?;
    }
    Ok(())
}

/// Distinct markers before they repeat.
const MARKERS: usize = 4;

/// Path `path`'s marker at each point: circle, triangle, square, cross, then round again.
pub(super) fn draw_markers<DB: DrawingBackend>(
    ctx: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    path: usize,
    points: &[(f64, f64)],
    colour: RGBColor,
) -> Result<(), PlotError> {
    let pts = points.iter().copied();
    match path % MARKERS {
        0 => ctx.draw_series(pts.map(|p| Circle::new(p, 4, colour.filled()))),
        1 => ctx.draw_series(pts.map(|p| TriangleMarker::new(p, 5, colour.filled()))),
        2 => ctx.draw_series(
            pts.map(|p| EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], colour.filled())),
        ),
        _ => ctx.draw_series(pts.map(|p| Cross::new(p, 4, colour.stroke_width(2)))),
    }
    .map(|_| ())
    .map_err(drawing)
}

/// Axis bounds holding every finite value and zero, with a little headroom (the plots and
/// the UI's error charts share it).
pub fn bounds(values: impl Iterator<Item = f64>) -> [f64; 2] {
    let (mut lo, mut hi) = (0.0_f64, 0.0_f64);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if hi - lo < 1e-12 {
        hi = lo + 1.0;
    }
    let pad = 0.08 * (hi - lo);
    [if lo < 0.0 { lo - pad } else { lo }, hi + pad]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_hold_zero_and_the_values() {
        assert_eq!(bounds([].into_iter()), [0.0, 1.08]);
        let b = bounds([0.5, 2.0, f64::NAN].into_iter());
        assert!(b[0] == 0.0 && b[1] > 2.0);
        let b = bounds([-1.0, 0.3].into_iter());
        assert!(b[0] < -1.0 && b[1] > 0.3);
    }
}
