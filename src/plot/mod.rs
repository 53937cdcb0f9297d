//! Charts for reports (`prbfit plot`): what the terminal UI shows, drawn as SVG or PNG.
//!
//! The work is split in two so that a new chart kind is a new file:
//! - [`data`] turns the library's results (a [`Baseline`](crate::eval::Baseline) and the PRB
//!   models followed along it) into plain data structs that say *what to draw*: the
//!   deformed centre lines and linkages ([`ShapesChart`]), the tip errors along each load path
//!   ([`ErrorsChart`]). It is the only part that solves anything.
//! - [`mech`] does the same for a mechanism scene (DESIGN §8): the exact mechanism and each
//!   model's PRB mechanism along the drives, as the force–stroke chart ([`ForceStrokeChart`]:
//!   reactions against the stroke, stage motion against the load).
//! - [`shapes`], [`errors`] and [`strokes`] each draw one of those structs onto a plotters
//!   drawing area, knowing nothing about solving; [`render`] lays the panels out on one
//!   canvas and encodes it (SVG text, or a PNG from the bitmap backend).
//!
//! Colours: the beam is grey, each model has its own colour from [`MODEL_RGB`] (the first is
//! "the model", the others are compared with it), the scene's accuracy targets are red dashed
//! lines. Text in PNGs is drawn with DejaVu Sans compiled into the binary (the `dejavu`
//! crate, with its licence), so rendering never depends on the fonts a machine has; SVGs name
//! the generic `sans-serif` family and the viewer picks the face.

pub mod data;
pub mod errors;
pub mod mech;
pub mod shapes;
pub mod stress;
pub mod strokes;

use std::fmt;
use std::path::Path;
use std::str::FromStr;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use serde::Serialize;

use crate::prb::PrbMatrix;

pub use errors::{ErrorCurve, ErrorPoint, ErrorsChart, ModelErrors};
pub use shapes::{equal_aspect_bounds, Linkage, ModelShapes, ShapesChart};
pub use stress::{StressChart, StressCurve};
pub use strokes::{ForceStrokeChart, Output, StrokePanel};

/// Which charts a figure holds. `shapes` and `errors` are a cantilever scene's, `force` and
/// `motion` a mechanism scene's, `stress` both's (not measured data's); `all` is every chart
/// the scene has but the stress chart.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ChartKind {
    /// The deformed shapes of one load path, beam and linkages.
    Shapes,
    /// Tip position and angle error against the load, every load path.
    Errors,
    /// A mechanism's reactions (prescribed stage coordinates) against the stroke.
    Force,
    /// A mechanism's stage motion (loaded stage coordinates) against the load.
    Motion,
    /// The largest fibre stress against the load, every path (DESIGN §11).
    Stress,
    /// Every chart of the scene: shapes and errors side by side for a cantilever, reactions
    /// and motions for a mechanism.
    #[default]
    All,
}

impl ChartKind {
    /// Every kind, in the order `--help` lists them.
    pub const ALL: [ChartKind; 6] = [
        ChartKind::Shapes,
        ChartKind::Errors,
        ChartKind::Force,
        ChartKind::Motion,
        ChartKind::Stress,
        ChartKind::All,
    ];

    /// Whether the figure has a mechanism's reaction panels.
    pub fn has_force(self) -> bool {
        matches!(self, ChartKind::Force | ChartKind::All)
    }

    /// Whether the figure has a mechanism's motion panels.
    pub fn has_motion(self) -> bool {
        matches!(self, ChartKind::Motion | ChartKind::All)
    }

    /// Whether the figure has the shapes panel.
    pub fn has_shapes(self) -> bool {
        matches!(self, ChartKind::Shapes | ChartKind::All)
    }

    /// Whether the figure has the error panels.
    pub fn has_errors(self) -> bool {
        matches!(self, ChartKind::Errors | ChartKind::All)
    }
}

impl fmt::Display for ChartKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ChartKind::Shapes => "shapes",
            ChartKind::Errors => "errors",
            ChartKind::Force => "force",
            ChartKind::Motion => "motion",
            ChartKind::Stress => "stress",
            ChartKind::All => "all",
        })
    }
}

impl FromStr for ChartKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "shapes" => Ok(ChartKind::Shapes),
            "errors" => Ok(ChartKind::Errors),
            "force" => Ok(ChartKind::Force),
            "motion" => Ok(ChartKind::Motion),
            "stress" => Ok(ChartKind::Stress),
            "all" => Ok(ChartKind::All),
            other => Err(format!(
                "unknown chart kind `{other}` (expected shapes, errors, force, motion, stress or \
                 all)"
            )),
        }
    }
}

/// The image format, from the output file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ImageFormat {
    /// Scalable vector graphics (text).
    Svg,
    /// A bitmap, PNG-encoded.
    Png,
}

impl ImageFormat {
    /// The extensions understood, for messages.
    pub const EXTENSIONS: &'static str = ".svg or .png";

    /// The format a file name asks for (case-insensitive extension), if any.
    pub fn from_path(path: &Path) -> Option<ImageFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "svg" => Some(ImageFormat::Svg),
            "png" => Some(ImageFormat::Png),
            _ => None,
        }
    }
}

impl fmt::Display for ImageFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ImageFormat::Svg => "svg",
            ImageFormat::Png => "png",
        })
    }
}

/// Why a figure could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlotError {
    /// The figure asks for a load path the scene does not have.
    #[error("load path {path} does not exist: the scene has {count} load path(s)")]
    NoSuchPath {
        /// 1-based, as asked.
        path: usize,
        /// Load paths in the scene.
        count: usize,
    },
    /// The kind is not one this scene's figures have (`shapes` and `errors` are for
    /// cantilever scenes, `force` and `motion` for mechanism scenes).
    #[error(
        "--kind {kind} is not a chart of {}: use {}",
        if *mechanism { "a mechanism scene" } else { "a cantilever scene" },
        if *mechanism {
            "force (reactions against the stroke), motion (stage motion against the load) or all"
        } else {
            "shapes, errors or all"
        }
    )]
    KindNotForScene {
        /// The kind asked for.
        kind: ChartKind,
        /// Whether the scene is a mechanism.
        mechanism: bool,
    },
    /// The mechanism has nothing of the kind asked for (a `force` chart with no prescribed
    /// coordinate carrying a reaction, a `motion` chart with no loaded coordinate that moves).
    #[error(
        "--kind {kind}: \"{scene}\" has nothing to draw: {}",
        match kind {
            ChartKind::Force => "no drive prescribes a stage coordinate that carries a reaction \
                                 (try --kind motion)",
            ChartKind::Motion => "no drive loads a stage coordinate that moves (try --kind force)",
            _ => "no drive prescribes a coordinate with a reaction or loads one that moves",
        }
    )]
    NothingToDraw {
        /// The kind asked for.
        kind: ChartKind,
        /// The scene's name.
        scene: String,
    },
    /// A stress chart of measured data, which has no stress.
    #[error(
        "--kind stress: \"{scene}\" is a data scene, and measured data has no stress (plot \
         the scene of the beam itself)"
    )]
    NoStress {
        /// The scene's name.
        scene: String,
    },
    /// The exact (beam) mechanism could not follow a drive: there is no reference to draw.
    #[error("the exact (beam) mechanism: {0}")]
    Exact(crate::mech::MechError),
    /// More models than distinct colours.
    #[error("at most {max} models fit in one figure, got {got}")]
    TooManyModels {
        /// The limit ([`MODEL_RGB`]'s length).
        max: usize,
        /// Models given.
        got: usize,
    },
    /// The embedded font could not be read (a build problem, not a user's).
    #[error("the embedded font could not be loaded")]
    Font,
    /// The drawing library failed.
    #[error("drawing the chart: {0}")]
    Draw(String),
    /// The PNG encoder failed.
    #[error("encoding the PNG: {0}")]
    Encode(String),
}

/// The beam's colour.
pub const BEAM_RGB: (u8, u8, u8) = (0x60, 0x60, 0x60);
/// Measured data's markers: magenta, apart from every model's colour.
pub const MEASURED_RGB: (u8, u8, u8) = (0xc0, 0x00, 0xa0);
/// The models' colours, in order: the first is "the model".
pub const MODEL_RGB: [(u8, u8, u8); 6] = [
    (0x1F, 0x77, 0xB4), // blue
    (0xFF, 0x7F, 0x0E), // orange
    (0x2C, 0xA0, 0x2C), // green
    (0x94, 0x67, 0xBD), // purple
    (0x8C, 0x56, 0x4B), // brown
    (0x17, 0xBE, 0xCF), // cyan
];
/// The accuracy targets' colour.
pub const TARGET_RGB: (u8, u8, u8) = (0xD6, 0x27, 0x28);

/// A palette entry as a plotters colour.
pub(crate) fn rgb((r, g, b): (u8, u8, u8)) -> RGBColor {
    RGBColor(r, g, b)
}

/// Model `i`'s colour.
pub(crate) fn model_colour(i: usize) -> RGBColor {
    rgb(MODEL_RGB[i % MODEL_RGB.len()])
}

/// The font family every text is drawn in (registered from the embedded DejaVu Sans).
pub(crate) const FONT: &str = "sans-serif";

/// A model to draw: its name in the legend and its matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotModel {
    /// The legend's text.
    pub name: String,
    /// The PRB matrix.
    pub matrix: PrbMatrix,
}

/// A load path (or a mechanism's drive path) a model could not follow to its end: it is
/// drawn as far as it got.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Unfollowed {
    /// The model's name.
    pub model: String,
    /// The load path (a mechanism's drive), 1-based.
    pub path: usize,
    /// Cases of the path the model reached.
    pub reached: usize,
    /// Cases of the path.
    pub steps: usize,
    /// Why it stopped, when the solver says (mechanism drives).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// A whole figure: its title and the panels its kind asks for.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Which panels.
    pub kind: ChartKind,
    /// Over the whole canvas.
    pub title: String,
    /// The deformed shapes, when the kind has them.
    pub shapes: Option<ShapesChart>,
    /// The tip errors, when the kind has them.
    pub errors: Option<ErrorsChart>,
    /// A mechanism's reactions against the stroke and motions against the load.
    pub force_stroke: Option<ForceStrokeChart>,
    /// The stress against the load (`--kind stress`).
    pub stress: Option<StressChart>,
    /// Load paths some model could not follow to the end.
    pub unfollowed: Vec<Unfollowed>,
}

/// Pixel sizes of the canvas of a cantilever scene's figure for each kind: (width, height).
/// (A mechanism's figure is sized by its panels: [`Figure::size`].)
pub fn canvas_size(kind: ChartKind) -> (u32, u32) {
    match kind {
        ChartKind::Shapes => (900, 650),
        ChartKind::Errors => (900, 800),
        ChartKind::Stress => (900, 650),
        ChartKind::All => (1600, 800),
        ChartKind::Force | ChartKind::Motion => strokes::canvas_size(1),
    }
}

impl Figure {
    /// The canvas's pixel size: (width, height).
    pub fn size(&self) -> (u32, u32) {
        match (&self.force_stroke, &self.stress) {
            (Some(chart), None) => strokes::canvas_size(chart.panels.len()),
            _ => canvas_size(self.kind),
        }
    }
}

/// Registers the embedded font with plotters once per process. Text layout needs it for
/// both backends (plotters measures labels to place them), and the bitmap backend draws
/// the glyphs with it.
fn register_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        let bytes = dejavu::sans::regular();
        plotters::style::register_font(FONT, FontStyle::Normal, bytes).is_ok()
            && plotters::style::register_font(FONT, FontStyle::Bold, bytes).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(PlotError::Font)
    }
}

/// A plotters error as ours.
pub(crate) fn drawing(e: impl fmt::Display) -> PlotError {
    PlotError::Draw(e.to_string())
}

/// Draws `figure` onto `root`: the shapes on the left, the errors on the right (or either
/// alone on the whole canvas).
fn draw_figure<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figure: &Figure,
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(drawing)?;
    let root = root
        .titled(&figure.title, (FONT, 22).into_font().style(FontStyle::Bold))
        .map_err(drawing)?;
    if let Some(chart) = &figure.stress {
        stress::draw(&root, chart)?;
        return root.present().map_err(drawing);
    }
    if let Some(chart) = &figure.force_stroke {
        strokes::draw(&root, chart)?;
        return root.present().map_err(drawing);
    }
    match (&figure.shapes, &figure.errors) {
        (Some(s), Some(e)) => {
            let (w, _) = root.dim_in_pixel();
            let (left, right) = root.split_horizontally(w / 2);
            shapes::draw(&left, s)?;
            errors::draw(&right, e)?;
        }
        (Some(s), None) => shapes::draw(&root, s)?,
        (None, Some(e)) => errors::draw(&root, e)?,
        (None, None) => {}
    }
    root.present().map_err(drawing)
}

/// The figure as an image file's bytes.
pub fn render(figure: &Figure, format: ImageFormat) -> Result<Vec<u8>, PlotError> {
    register_font()?;
    let (w, h) = figure.size();
    match format {
        ImageFormat::Svg => {
            let mut text = String::new();
            {
                let root = SVGBackend::with_string(&mut text, (w, h)).into_drawing_area();
                draw_figure(&root, figure)?;
            }
            Ok(text.into_bytes())
        }
        ImageFormat::Png => {
            let mut pixels = vec![0_u8; w as usize * h as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut pixels, (w, h)).into_drawing_area();
                draw_figure(&root, figure)?;
            }
            encode_png(&pixels, w, h)
        }
    }
}

/// RGB pixels, row by row, as a PNG file.
fn encode_png(pixels: &[u8], w: u32, h: u32) -> Result<Vec<u8>, PlotError> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let encode = |e: png::EncodingError| PlotError::Encode(e.to_string());
    let mut writer = encoder.write_header().map_err(encode)?;
    writer.write_image_data(pixels).map_err(encode)?;
    writer.finish().map_err(encode)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_come_from_the_extension() {
        assert_eq!(
            ImageFormat::from_path(Path::new("a/fig.svg")),
            Some(ImageFormat::Svg)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("FIG.PNG")),
            Some(ImageFormat::Png)
        );
        assert_eq!(ImageFormat::from_path(Path::new("fig.pdf")), None);
        assert_eq!(ImageFormat::from_path(Path::new("fig")), None);
    }

    #[test]
    fn kinds_round_trip() {
        for k in ChartKind::ALL {
            assert_eq!(k.to_string().parse::<ChartKind>(), Ok(k));
        }
        assert!("bars".parse::<ChartKind>().is_err());
    }

    #[test]
    fn the_embedded_font_loads() {
        assert_eq!(register_font(), Ok(()));
    }
}
