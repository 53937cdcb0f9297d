//! The force–stroke chart of a mechanism scene: a grid of panels, one per output of each drive
//! ([`StrokePanel`]), the exact mechanism in grey with a dot at each case and each model in its
//! colour on top, the legend in the first panel.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::errors::bounds;
use super::{drawing, model_colour, rgb, PlotError, BEAM_RGB, FONT, MEASURED_RGB};

/// What a panel's ordinate is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    /// The reaction of a prescribed stage coordinate.
    Reaction,
    /// The motion of a loaded stage coordinate.
    Motion,
}

/// One panel: one output of one drive, beam and models.
#[derive(Debug, Clone, PartialEq)]
pub struct StrokePanel {
    /// The drive path, from 1.
    pub drive: usize,
    /// The stage coordinate: 0 `x`, 1 `y`, 2 `phi`.
    pub coordinate: usize,
    /// Reaction or motion.
    pub output: Output,
    /// Over the panel.
    pub title: String,
    /// The abscissa's name and unit.
    pub x_label: String,
    /// The ordinate's name and unit.
    pub y_label: String,
    /// The exact mechanism: `[abscissa, ordinate]` in SI (display units), from rest.
    pub beam: Vec<[f64; 2]>,
    /// Per model, in the models' order, as far as it got; empty when it could not move.
    pub models: Vec<Vec<[f64; 2]>>,
}

/// The force–stroke chart of a mechanism scene.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceStrokeChart {
    /// The legend's text per model, in order (a model that cannot follow every drive says
    /// so).
    pub legend: Vec<String>,
    /// Drive by drive, reactions before motions, `x`, `y`, `phi`.
    pub panels: Vec<StrokePanel>,
    /// The truth is measured data (DESIGN §9): its cases are drawn as markers, not a curve.
    pub measured: bool,
}

/// One panel's pixel size.
const PANEL: (u32, u32) = (680, 460);
/// Room for the figure's title above the panels.
const TITLE_HEIGHT: u32 = 50;

/// The legend's text for the beam.
pub const BEAM_LABEL: &str = "beam (exact)";
/// The legend's text for measured data.
pub const MEASURED_LABEL: &str = "measured";

/// Panels side by side for `panels` panels: one, two up to four, then three.
fn columns(panels: usize) -> usize {
    match panels {
        0 | 1 => 1,
        2..=4 => 2,
        _ => 3,
    }
}

/// The canvas of a figure with `panels` panels: (width, height).
pub fn canvas_size(panels: usize) -> (u32, u32) {
    let cols = columns(panels);
    let rows = panels.max(1).div_ceil(cols);
    // Bounded by the drives a scene may have; the casts cannot overflow for any real figure.
    let cols = u32::try_from(cols).unwrap_or(1);
    let rows = u32::try_from(rows).unwrap_or(1).min(64);
    ((PANEL.0 * cols).max(900), PANEL.1 * rows + TITLE_HEIGHT)
}

/// Draws the chart onto `area` (already titled): the panels in a grid, row by row.
pub fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &ForceStrokeChart,
) -> Result<(), PlotError> {
    let cols = columns(chart.panels.len());
    let rows = chart.panels.len().max(1).div_ceil(cols);
    let cells = area.split_evenly((rows, cols));
    for (i, (cell, p)) in cells.iter().zip(&chart.panels).enumerate() {
        panel(
            cell,
            p,
            (i == 0).then_some(chart.legend.as_slice()),
            chart.measured,
        )?;
    }
    Ok(())
}

/// One panel: the beam's curve (measured data's markers, when `measured`) and each model's;
/// the legend when `legend` is given.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &StrokePanel,
    legend: Option<&[String]>,
    measured: bool,
) -> Result<(), PlotError> {
    let finite = |q: &&[f64; 2]| q[0].is_finite() && q[1].is_finite();
    let all = || {
        p.beam
            .iter()
            .chain(p.models.iter().flatten())
            .filter(finite)
    };
    let xb = bounds(all().map(|q| q[0]));
    let yb = bounds(all().map(|q| q[1]));
    let area = area.margin(5, 10, 10, 20);
    let mut ctx = ChartBuilder::on(&area)
        .caption(p.title.as_str(), (FONT, 16))
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(xb[0]..xb[1], yb[0]..yb[1])
        .map_err(drawing)?;
    let (x_axis, y_axis) = (Axis::of(xb), Axis::of(yb));
    let x_format = move |v: &f64| tick(*v, x_axis);
    let y_format = move |v: &f64| tick(*v, y_axis);
    ctx.configure_mesh()
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .x_desc(p.x_label.as_str())
        .y_desc(p.y_label.as_str())
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(drawing)?;

    // The beam underneath, wider, with a dot per case (measured data: a cross per row, no
    // line); the models on top of it.
    let beam_pts: Vec<(f64, f64)> = p.beam.iter().filter(finite).map(|q| (q[0], q[1])).collect();
    let beam_style = rgb(BEAM_RGB).stroke_width(4);
    if measured {
        let mark = rgb(MEASURED_RGB).stroke_width(3);
        let anno = ctx
            .draw_series(beam_pts.iter().skip(1).map(|&q| Cross::new(q, 7, mark)))
            .map_err(drawing)?;
        if legend.is_some() {
            anno.label(MEASURED_LABEL)
                .legend(move |(x, y)| Cross::new((x + 12, y), 7, mark));
        }
    } else {
        let anno = ctx
            .draw_series(LineSeries::new(beam_pts.iter().copied(), beam_style))
            .map_err(drawing)?;
        if legend.is_some() {
            anno.label(BEAM_LABEL)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], beam_style));
        }
        ctx.draw_series(
            beam_pts
                .iter()
                .skip(1)
                .map(|&q| Circle::new(q, 4, rgb(BEAM_RGB).filled())),
        )
        .map_err(drawing)?;
    }

    for (m, curve) in p.models.iter().enumerate() {
        let style = model_colour(m).stroke_width(2);
        let pts: Vec<(f64, f64)> = curve.iter().filter(finite).map(|q| (q[0], q[1])).collect();
        let name = legend.and_then(|l| l.get(m)).cloned();
        // A model that could not move has no line, but the legend still names it.
        let anno = if pts.is_empty() {
            ctx.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
        } else {
            ctx.draw_series(LineSeries::new(pts.iter().copied(), style))
        }
        .map_err(drawing)?;
        if let Some(name) = name {
            anno.label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
        }
    }

    if legend.is_some() {
        // The corner the curve leaves empty: it runs from the origin towards its last point.
        let along_diagonal = p.beam.last().is_none_or(|q| (q[0] >= 0.0) == (q[1] >= 0.0));
        let position = if along_diagonal {
            SeriesLabelPosition::UpperLeft
        } else {
            SeriesLabelPosition::UpperRight
        };
        ctx.configure_series_labels()
            .position(position)
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(drawing)?;
    }
    Ok(())
}

/// Decimals that tell the ticks of an axis spanning `range` apart (about ten ticks).
fn digits(range: [f64; 2]) -> usize {
    let step = (range[1] - range[0]).abs() / 10.0;
    if step.is_finite() && step > 0.0 {
        // Bounded: a span of 1e-300 asks for 300 digits at most; no axis gets near it.
        (-step.log10().floor()).clamp(0.0, 12.0) as usize
    } else {
        1
    }
}

/// How an axis labels its ticks, chosen once for the axis.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Axis {
    /// Decimals of a plain label ([`digits`]).
    digits: usize,
    /// Every label in scientific form: the axis reaches 1e6 (an absurd modulus's stresses
    /// label as `8.5e21`, never as 22 digits; a heavy flexure's reactions as `8e5, 1e6,
    /// 1.2e6`, not `800000, 1e6, 1.2e6`).
    scientific: bool,
}

impl Axis {
    fn of(range: [f64; 2]) -> Axis {
        Axis {
            digits: digits(range),
            scientific: range[0].abs().max(range[1].abs()) >= 1e6,
        }
    }
}

/// A tick label on `axis`: plain with its decimals, a round-off `-0` printed as `0`, or
/// scientific.
fn tick(v: f64, axis: Axis) -> String {
    if axis.scientific {
        // Six significant digits, trailing zeros dropped: `6e5`, `1.2e6`, `8.47547e21`.
        return crate::text::scientific_prec(v, 6);
    }
    let digits = axis.digits;
    let text = format!("{v:.digits$}");
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_have_enough_digits_and_no_negative_zero() {
        assert_eq!(digits([0.0, 35.0]), 0);
        assert_eq!(digits([-0.8, 0.05]), 2);
        let plain = |digits| Axis {
            digits,
            scientific: false,
        };
        assert_eq!(tick(-1e-17, plain(2)), "0.00");
        assert_eq!(tick(-0.25, plain(2)), "-0.25");
        assert_eq!(tick(15.0, plain(0)), "15");
        // An axis that reaches 1e6 labels every tick alike.
        let big = Axis::of([0.0, 1.3e6]);
        assert!(big.scientific);
        let labels: Vec<String> = [6e5, 8e5, 1e6, 1.2e6]
            .iter()
            .map(|&v| tick(v, big))
            .collect();
        assert_eq!(labels, ["6e5", "8e5", "1e6", "1.2e6"]);
        let huge = Axis::of([0.0, 1e22]);
        assert_eq!(tick(8.475471848539104e21, huge), "8.47547e21");
        assert_eq!(tick(-2.5e6, Axis::of([-3e6, 0.0])), "-2.5e6");
        assert!(!Axis::of([0.0, 999_999.0]).scientific);
    }

    #[test]
    fn the_grid_grows_with_the_panels() {
        assert_eq!(canvas_size(1), (900, PANEL.1 + TITLE_HEIGHT));
        assert_eq!(canvas_size(2), (2 * PANEL.0, PANEL.1 + TITLE_HEIGHT));
        assert_eq!(canvas_size(3), (2 * PANEL.0, 2 * PANEL.1 + TITLE_HEIGHT));
        assert_eq!(canvas_size(6), (3 * PANEL.0, 2 * PANEL.1 + TITLE_HEIGHT));
    }
}
