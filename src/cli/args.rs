//! The command line's shape (DESIGN §6): subcommands, their flags, and the help text.

use std::path::PathBuf;
use std::str::FromStr;

use clap::{Args, Parser, Subcommand};

use prbfit::beam::{Load, Resolution};
use prbfit::fea::{Section, Taper};
use prbfit::fidelity::Fidelity;
use prbfit::format::Format;
use prbfit::plot::ChartKind;

/// The whole command line.
#[derive(Parser)]
#[command(
    name = "prbfit",
    version,
    about = "Finds the best pseudo-rigid-body (PRB) model of a compliant cantilever beam",
    long_about = None
)]
pub struct Cli {
    /// What to do; none opens the terminal UI on the built-in scene.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Subcommand)]
pub enum Command {
    /// Solve the large-deflection baseline beam: one load, or every load case of the scene.
    Solve(SolveArgs),
    /// Judge PRB models against the beam: one load, or every load case of the scene.
    Eval(EvalArgs),
    /// Fit the free cells of a PRB matrix to the beam over the scene's loads.
    Fit(FitArgs),
    /// Fit the topology ladder and pick the simplest model that meets the scene's targets.
    Select(SelectArgs),
    /// Measure the speed/accuracy trade along each knob.
    Tradeoff(TradeoffArgs),
    /// Write a model for other tools: prbfit's model file, MuJoCo, URDF, SDF or CSV.
    Export(ExportArgs),
    /// Draw the UI's charts for reports: deformed shapes and tip errors, as SVG or PNG.
    Plot(PlotArgs),
    /// Fit one beam parameter (E or the thickness) to a data scene's measurements.
    Calibrate(CalibrateArgs),
    /// FEA of the scene's beam or mechanism with CalculiX (ccx) along its load or drive
    /// paths, written as measured-data CSV (DESIGN §9, §13), the beam beside it.
    Fea(FeaArgs),
    /// Natural frequencies of the scene's beam (or beam mechanism) and of PRB models about
    /// the same equilibria: unloaded, one tip load, or every case (DESIGN §10).
    Modes(ModesArgs),
    /// Open the terminal UI (the default with no command) on a scene file or the built-in one.
    Tui {
        /// Scene file (TOML); default: the built-in scene.
        scene: Option<PathBuf>,
        /// The scene file, given as every other command takes it (the same as SCENE).
        #[arg(long = "scene", value_name = "FILE", conflicts_with = "scene")]
        scene_flag: Option<PathBuf>,
    },
}

/// Options every subcommand shares.
#[derive(Args)]
pub struct Common {
    /// Scene file (TOML, DESIGN §5); default: the built-in scene.
    #[arg(long, value_name = "FILE")]
    pub scene: Option<PathBuf>,
    /// Print one JSON object on stdout instead of text.
    #[arg(long)]
    pub json: bool,
}

/// `prbfit solve`.
#[derive(Args)]
pub struct SolveArgs {
    #[command(flatten)]
    pub common: Common,
    /// One tip load, nondimensional: alpha_x, alpha_y, beta.
    #[arg(long, value_name = "AX,AY,BETA", value_parser = load_arg, allow_hyphen_values = true)]
    pub load: Option<Load>,
    /// Beam effects: a comma-separated list of shear, extension, poisson, plane_strain; or
    /// none; or all (shear, extension, poisson).
    #[arg(long, value_name = "LIST|none")]
    pub effects: Option<String>,
    /// Slenderness L/t0 (overrides the scene's beam).
    #[arg(long, value_name = "L_OVER_T", allow_negative_numbers = true)]
    pub slenderness: Option<f64>,
    /// Poisson's ratio (overrides the scene's beam).
    #[arg(long, value_name = "NU", allow_negative_numbers = true)]
    pub nu: Option<f64>,
    /// Shear coefficient kappa (default: Cowper's rectangle value for nu).
    #[arg(long, value_name = "K", allow_negative_numbers = true)]
    pub kappa: Option<f64>,
    /// Integrator tolerance: the speed/accuracy knob (tip error about 10x this or better).
    #[arg(long, value_name = "TOL", allow_negative_numbers = true, default_value_t = Resolution::default().tol)]
    pub tol: f64,
    /// Include the deformed shape (points along the beam) in the JSON output.
    #[arg(long)]
    pub shape: bool,
}

/// `prbfit eval`.
#[derive(Args)]
pub struct EvalArgs {
    #[command(flatten)]
    pub common: Common,
    /// A PRB matrix in text form, e.g. "0.15,inf,inf; 0.85,2.2525,inf" (repeatable).
    #[arg(long, value_name = "MATRIX", allow_hyphen_values = true)]
    pub prb: Vec<String>,
    /// A published model (howell-1r, su-3r, chen-3r) or a model file (repeatable). Without
    /// any model: the scene's [prb] matrix.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub model: Vec<String>,
    /// Judge one tip load instead of the scene's cases.
    #[arg(long, value_name = "AX,AY,BETA", value_parser = load_arg, allow_hyphen_values = true)]
    pub load: Option<Load>,
    /// Baseline integrator tolerance.
    #[arg(long, value_name = "TOL", allow_negative_numbers = true, default_value_t = Resolution::default().tol)]
    pub tol: f64,
}

/// `prbfit modes`.
#[derive(Args)]
pub struct ModesArgs {
    #[command(flatten)]
    pub common: Common,
    /// A PRB matrix in text form (repeatable).
    #[arg(long, value_name = "MATRIX", allow_hyphen_values = true)]
    pub prb: Vec<String>,
    /// A published model (howell-1r, su-3r, chen-3r) or a model file (repeatable). Without
    /// any model: the scene's [prb] matrix if it has one, else the beam alone.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub model: Vec<String>,
    /// How many of the lowest frequencies.
    #[arg(
        long,
        value_name = "N",
        default_value_t = 3,
        allow_negative_numbers = true
    )]
    pub count: usize,
    /// About the equilibrium under one tip load (cantilever scenes) instead of the unloaded
    /// one.
    #[arg(long, value_name = "AX,AY,BETA", value_parser = load_arg, allow_hyphen_values = true, conflicts_with = "cases")]
    pub load: Option<Load>,
    /// About every case of the scene's load paths or drives.
    #[arg(long)]
    pub cases: bool,
    /// Baseline integrator tolerance.
    #[arg(long, value_name = "TOL", allow_negative_numbers = true, default_value_t = Resolution::default().tol)]
    pub tol: f64,
}

/// `prbfit fit`.
#[derive(Args)]
pub struct FitArgs {
    #[command(flatten)]
    pub common: Common,
    /// Topology to fit, from the root: L, R, P, RP joined by - (e.g. L-R-R-R), or 1R..4R.
    /// Without it or --prb: the scene's [prb] matrix.
    #[arg(long, value_name = "TOPO", conflicts_with = "prb")]
    pub topology: Option<String>,
    /// Matrix to start from; cells ending in ! stay fixed.
    #[arg(long, value_name = "MATRIX", allow_hyphen_values = true)]
    pub prb: Option<String>,
    /// draft, normal or precise.
    #[arg(long, value_name = "LEVEL", default_value = "normal", value_parser = Fidelity::from_str)]
    pub fidelity: Fidelity,
    /// Seed of the random starts: the same seed gives the same fit.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub seed: u64,
    /// Save the fitted model (.toml or .json).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Overwrite the output file if it exists.
    #[arg(long)]
    pub force: bool,
}

/// `prbfit select`.
#[derive(Args)]
pub struct SelectArgs {
    #[command(flatten)]
    pub common: Common,
    /// draft, normal or precise.
    #[arg(long, value_name = "LEVEL", default_value = "normal", value_parser = Fidelity::from_str)]
    pub fidelity: Fidelity,
    /// Judge only the cases up to each path's stroke limit, where the stress first reaches
    /// the scene's allowable_stress (a model need not fit what the part cannot survive).
    #[arg(long)]
    pub within_stroke: bool,
}

/// `prbfit calibrate`.
#[derive(Args)]
pub struct CalibrateArgs {
    #[command(flatten)]
    pub common: Common,
    /// The beam parameter fitted: youngs_modulus or thickness.
    #[arg(long, value_name = "NAME", default_value = "youngs_modulus")]
    pub param: String,
}

/// `prbfit tradeoff`.
#[derive(Args)]
pub struct TradeoffArgs {
    #[command(flatten)]
    pub common: Common,
    /// The topology the sampling and fidelity knobs fit.
    #[arg(long, value_name = "TOPO", default_value = "L-R-R-R")]
    pub topology: String,
}

/// `prbfit export`.
#[derive(Args)]
#[command(group = clap::ArgGroup::new("which").args(["prb", "model"]))]
pub struct ExportArgs {
    #[command(flatten)]
    pub common: Common,
    /// A PRB matrix in text form.
    #[arg(long, value_name = "MATRIX", allow_hyphen_values = true)]
    pub prb: Option<String>,
    /// A published model (howell-1r, su-3r, chen-3r) or a model file. Without it or --prb:
    /// the scene's [prb] matrix.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub model: Option<String>,
    /// toml, json, mjcf, urdf, sdf or csv; default: from the output file's extension.
    #[arg(long, value_name = "F", value_parser = Format::from_str)]
    pub format: Option<Format>,
    /// The file to write.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: PathBuf,
    /// Overwrite the file if it exists.
    #[arg(long)]
    pub force: bool,
    /// Density for the masses, kg/m^3 (only dynamics depend on it); default: the scene's
    /// `[beam] density`, else 1000.
    #[arg(long, value_name = "KG_M3", allow_negative_numbers = true)]
    pub density: Option<f64>,
    /// Fidelity of the baseline the figures and the CSV come from.
    #[arg(long, value_name = "LEVEL", default_value = "normal", value_parser = Fidelity::from_str)]
    pub fidelity: Fidelity,
}

/// `prbfit plot`.
#[derive(Args)]
pub struct PlotArgs {
    #[command(flatten)]
    pub common: Common,
    /// A published model (howell-1r, su-3r, chen-3r) or a model file (repeatable). The first
    /// model given, by --model or --prb, is the model; the others are compared with it.
    /// Without any: the scene's [prb] matrix.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub model: Vec<String>,
    /// A PRB matrix in text form (repeatable).
    #[arg(long, value_name = "MATRIX", allow_hyphen_values = true)]
    pub prb: Vec<String>,
    /// The figure to write: .svg or .png.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: PathBuf,
    /// Overwrite the file if it exists.
    #[arg(long)]
    pub force: bool,
    /// Cantilever scenes: shapes (deformed shapes of one load path), errors (tip errors of
    /// every load path) or all (both, side by side). Mechanism scenes: force (each prescribed
    /// stage coordinate's reaction against the stroke), motion (each loaded coordinate's
    /// stage motion against the load) or all (both). Either: stress (each flexure's largest
    /// fibre stress against the load, every path, the models' estimates beside the truth's,
    /// with the allowable stress and the stroke limits).
    #[arg(long, value_name = "KIND", default_value = "all", value_parser = ChartKind::from_str)]
    pub kind: ChartKind,
    /// Fidelity of the baseline beam (and its load sampling).
    #[arg(long, value_name = "LEVEL", default_value = "normal", value_parser = Fidelity::from_str)]
    pub fidelity: Fidelity,
    /// The load path whose deformed shapes are drawn (1-based; cantilever scenes only).
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub path: usize,
}

/// `prbfit fea`.
#[derive(Args)]
pub struct FeaArgs {
    #[command(flatten)]
    pub common: Common,
    /// The CSV to write (DESIGN §9: path,fx,fy,mz,x,y,theta in SI; a mechanism's: path, the
    /// drive's inputs and stage_dx..stage_mz).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: PathBuf,
    /// Mesh density: elements along the beam, or along flexure 1 (through the thickness and across the width in
    /// proportion, at least one).
    #[arg(long, value_name = "N", default_value_t = 40)]
    pub mesh: u32,
    /// plane-stress (the beam of DESIGN §2), plane-strain (a very wide section) or solid
    /// (the 3D strip); default: the scene's, solid when its beam keeps plane strain (after
    /// `auto` is decided), else plane-stress. A section given here is compared with the beam
    /// of the same section.
    #[arg(long, value_name = "MODEL", value_parser = Section::from_str)]
    pub section: Option<Section>,
    /// Tip thickness over root thickness: the thickness tapers linearly from the scene's
    /// [beam] thickness at the clamp to R times it at the tip, the width constant (0.05 to
    /// 20; 1 is the uniform beam). The beam printed beside the FEA stays the uniform one.
    #[arg(long, value_name = "R", default_value = "1", value_parser = Taper::from_str)]
    pub taper: Taper,
    /// Where to write the CalculiX deck (one per load or drive path, numbered -pathK when there are
    /// several); default: beside the output, with extension .inp.
    #[arg(long, value_name = "FILE.inp")]
    pub deck: Option<PathBuf>,
    /// Overwrite the output and the decks if they exist.
    #[arg(long)]
    pub force: bool,
    /// Time limit of each CalculiX run (one per load or drive path), seconds.
    #[arg(long, value_name = "SECONDS", default_value_t = 900)]
    pub timeout: u64,
}

/// `--load AX,AY,BETA`: three finite numbers, each within the scene rules' reach
/// ([`prbfit::scene::MAX_NONDIMENSIONAL`]), as a scene's `[[loads]]` must be.
fn load_arg(text: &str) -> Result<Load, String> {
    let load = Load::parse(text)?;
    prbfit::scene::rules::single_load(&load)?;
    Ok(load)
}
