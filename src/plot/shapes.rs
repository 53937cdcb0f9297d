//! The deformed-shapes chart: the beam's centre line for every case of one load path, with
//! each PRB model's linkage (links as straight segments, revolute joints as dots) over it,
//! in units of L with x and y at the same scale, so a bend looks like the bend it is.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{drawing, model_colour, rgb, PlotError, BEAM_RGB, FONT, MEASURED_RGB};

/// What the shapes chart draws.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapesChart {
    /// Above the panel (which load path, its end load).
    pub title: String,
    /// The beam's centre line `(x, y)` for each case of the path, units of L (on a data
    /// scene, the scene's nominal beam at the measured loads, when it was solved).
    pub beam: Vec<Vec<[f64; 2]>>,
    /// A data scene's measured tips `(a, b)` of the path (DESIGN §9), units of L: drawn as
    /// markers, the truth; empty for a beam scene.
    pub measured: Vec<[f64; 2]>,
    /// Each model's linkages, in the models' order.
    pub models: Vec<ModelShapes>,
}

/// One model's linkages over the cases it reached.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelShapes {
    /// The legend's text.
    pub name: String,
    /// One per reached case.
    pub linkages: Vec<Linkage>,
}

/// A PRB chain in one configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Linkage {
    /// The root, then each segment's end (the last is the tip), units of L.
    pub points: Vec<[f64; 2]>,
    /// The revolute joints (drawn as dots), units of L.
    pub joints: Vec<[f64; 2]>,
}

impl ShapesChart {
    /// Every point drawn, and the root.
    fn points(&self) -> Vec<[f64; 2]> {
        let mut all = vec![[0.0, 0.0]];
        all.extend(self.beam.iter().flatten());
        all.extend(&self.measured);
        for m in &self.models {
            for l in &m.linkages {
                all.extend(&l.points);
            }
        }
        all
    }
}

/// Axis ranges `(x, y)` that hold every finite point with a margin and give x and y the same
/// scale on a plotting area of `width` x `height` pixels: the range per pixel is the same
/// along both axes, the data centred along the roomier one.
pub fn equal_aspect_bounds(points: &[[f64; 2]], width: u32, height: u32) -> ([f64; 2], [f64; 2]) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in points
        .iter()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
    {
        x0 = x0.min(p[0]);
        x1 = x1.max(p[0]);
        y0 = y0.min(p[1]);
        y1 = y1.max(p[1]);
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    // A lone point still gets a view of 1% of L around it.
    let span = (x1 - x0).max(y1 - y0).max(0.01);
    let pad = 0.06 * span;
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let (w, h) = (f64::from(width.max(1)), f64::from(height.max(1)));
    // Units of L per pixel: enough for the wider of the two extents.
    let per_pixel = ((x1 - x0 + 2.0 * pad) / w).max((y1 - y0 + 2.0 * pad) / h);
    let (hx, hy) = (0.5 * per_pixel * w, 0.5 * per_pixel * h);
    ([cx - hx, cx + hx], [cy - hy, cy + hy])
}

/// Room for the tick labels and axis titles, pixels.
const X_LABEL_AREA: u32 = 50;
const Y_LABEL_AREA: u32 = 70;

/// Draws the chart onto `area`.
pub fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &ShapesChart,
) -> Result<(), PlotError> {
    let area = area
        .titled(&chart.title, (FONT, 18))
        .map_err(drawing)?
        .margin(5, 15, 5, 20);
    // The plotting area is what is left after the label areas; its shape sets the ranges.
    let (w, h) = area.dim_in_pixel();
    let (xb, yb) = equal_aspect_bounds(
        &chart.points(),
        w.saturating_sub(Y_LABEL_AREA),
        h.saturating_sub(X_LABEL_AREA),
    );
    let mut ctx = ChartBuilder::on(&area)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(xb[0]..xb[1], yb[0]..yb[1])
        .map_err(drawing)?;
    ctx.configure_mesh()
        .x_desc("x / L")
        .y_desc("y / L")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(drawing)?;

    // The clamp at the root: a short wall across the beam.
    let wall = 0.04 * (yb[1] - yb[0]);
    ctx.draw_series(std::iter::once(PathElement::new(
        vec![(0.0, -wall), (0.0, wall)],
        BLACK.stroke_width(4),
    )))
    .map_err(drawing)?;

    let beam_style = rgb(BEAM_RGB).stroke_width(2);
    let beam_label = if chart.measured.is_empty() {
        "beam"
    } else {
        "beam (the scene's, nominal)"
    };
    for (i, line) in chart.beam.iter().enumerate() {
        let anno = ctx
            .draw_series(LineSeries::new(finite(line), beam_style))
            .map_err(drawing)?;
        if i == 0 {
            anno.label(beam_label)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], beam_style));
        }
    }

    for (m, model) in chart.models.iter().enumerate() {
        let style = model_colour(m).stroke_width(2);
        let dot = model_colour(m).filled();
        // The legend entry stands alone: a model that reached no case of this path is
        // still named.
        ctx.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
            .map_err(drawing)?
            .label(model.name.as_str())
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (24, 0)], style)
                    + Circle::new((12, 0), 4, dot)
            });
        for link in &model.linkages {
            ctx.draw_series(LineSeries::new(finite(&link.points), style))
                .map_err(drawing)?;
            ctx.draw_series(finite(&link.joints).map(|p| Circle::new(p, 4, dot)))
                .map_err(drawing)?;
        }
    }

    // The measured tips last, on top: the truth.
    if !chart.measured.is_empty() {
        let mark = rgb(MEASURED_RGB).stroke_width(3);
        ctx.draw_series(finite(&chart.measured).map(|p| Cross::new(p, 7, mark)))
            .map_err(drawing)?
            .label("measured tip")
            .legend(move |(x, y)| Cross::new((x + 12, y), 7, mark));
    }

    ctx.configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((FONT, 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(drawing)
}

/// The finite points, as plotters' coordinates (a non-finite point would be drawn at the
/// edge of the chart).
fn finite(points: &[[f64; 2]]) -> impl Iterator<Item = (f64, f64)> + Clone + '_ {
    points
        .iter()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .map(|p| (p[0], p[1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scale(b: ([f64; 2], [f64; 2]), w: u32, h: u32) -> (f64, f64) {
        (
            (b.0[1] - b.0[0]) / f64::from(w),
            (b.1[1] - b.1[0]) / f64::from(h),
        )
    }

    #[test]
    fn equal_aspect_bounds_keep_x_and_y_at_one_scale() {
        let shapes: [&[[f64; 2]]; 4] = [
            // A straight beam: all x, no y.
            &[[0.0, 0.0], [0.5, 0.0], [1.0, 0.0]],
            // A beam curled up past vertical.
            &[[0.0, 0.0], [0.6, 0.3], [0.7, 0.7], [0.4, 0.9]],
            // A compressed, buckled shape: tall and narrow.
            &[[0.0, 0.0], [0.05, 0.5], [-0.02, 1.0]],
            // One point, and junk to ignore.
            &[[0.3, 0.3], [f64::NAN, 2.0], [1.0, f64::INFINITY]],
        ];
        for pts in shapes {
            for (w, h) in [(700, 500), (300, 900), (640, 640), (1, 1)] {
                let b = equal_aspect_bounds(pts, w, h);
                let (sx, sy) = scale(b, w, h);
                assert!(
                    (sx - sy).abs() <= 1e-9 * sx.max(sy),
                    "x {sx} and y {sy} per pixel for {pts:?} on {w}x{h}"
                );
                for p in pts.iter().filter(|p| p[0].is_finite() && p[1].is_finite()) {
                    assert!(b.0[0] < p[0] && p[0] < b.0[1], "{p:?} outside x {:?}", b.0);
                    assert!(b.1[0] < p[1] && p[1] < b.1[1], "{p:?} outside y {:?}", b.1);
                }
                assert!(b.0.iter().chain(&b.1).all(|v| v.is_finite()));
            }
        }
    }

    #[test]
    fn equal_aspect_bounds_of_nothing_are_the_unit_square() {
        let b = equal_aspect_bounds(&[], 400, 400);
        assert!(b.0[0] < 0.0 && b.0[1] > 1.0 && b.1[0] < 0.0 && b.1[1] > 1.0);
    }
}
