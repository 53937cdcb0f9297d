//! Exporting a PRB model where designers use it: prbfit's own model file (TOML, JSON), MuJoCo
//! (MJCF), URDF, SDF 1.10, and CSV of the load cases.
//!
//! The scene supplies the beam, so every format also carries SI values:
//! segment lengths `gamma L`, torsion springs `K_theta = k_theta E I0 / L` (N m/rad) and
//! extension springs `K_ex = k_ex E A0 / L` (N/m). Each chain lies along +x from the clamp
//! (the world origin) in its unloaded pose; revolute joints turn about +z.
//!
//! Masses come from the beam's cross-section and a density (default 1000 kg/m^3): they matter
//! only for dynamics, never for the static equilibrium the model was fitted for.
//!
//! One file per format; the simulator formats all write the one link/joint description of
//! [`chain`].
//!
//! A mechanism scene (DESIGN §8) exports as the whole PRB mechanism: MuJoCo ([`mjcf_mech`])
//! and prbfit's own model file; the other formats refuse it by name. Which writer serves
//! which scene is `crate::study::Study::export`'s choice; this module holds the writers.

pub mod chain;
pub mod csv;
pub mod mjcf;
pub mod mjcf_mech;
pub mod sdf;
pub mod urdf;

use crate::format::Format;
use crate::io::files::utc_timestamp;
use crate::io::ModelFileError;
use crate::prb::PrbMatrix;
use crate::scene::{Mechanism, Scene};
use crate::text::xml_comment_safe;

/// Why an export failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExportError {
    /// The model cannot follow the scene's loads, so it has no figures to record.
    #[error("the model cannot follow the scene's loads: {0}")]
    Eval(String),
    /// A bad density, and why ([`crate::scene::rules::density`]).
    #[error("density {0}")]
    Density(String),
    /// The model's highest natural frequency is so far above its lowest that MuJoCo's
    /// time step ([`chain::time_step`]) would make a run impractical.
    #[error("{}", too_stiff(*ratio, *steps, *limit))]
    TooStiff {
        /// The highest over the lowest natural frequency.
        ratio: f64,
        /// The time steps per period of the lowest mode.
        steps: f64,
        /// [`chain::MAX_STEPS_PER_PERIOD`].
        limit: f64,
    },
    /// The model file could not be written as text.
    #[error(transparent)]
    ModelFile(#[from] ModelFileError),
    /// A format that cannot hold a mechanism (yet).
    #[error(
        "a mechanism scene exports as the whole PRB mechanism in {supported} only, not as \
         {format} ({format} takes cantilever scenes)"
    )]
    MechanismFormat {
        /// The format asked for.
        format: Format,
        /// The formats that take a mechanism, as the message lists them.
        supported: String,
    },
}

/// The formats that take a mechanism scene: MJCF holds the whole PRB mechanism; prbfit's own
/// model file (TOML, JSON) holds the model with its figures judged on the mechanism. URDF and
/// SDF have no loop closures of their own and CSV's load cases are the cantilever's.
pub fn mechanism_formats() -> &'static [Format] {
    &[Format::Mjcf, Format::Toml, Format::Json]
}

/// The comment the mechanism's MJCF opens with: the model, the scene, the units, how to drive
/// it.
pub fn mechanism_comment(
    name: &str,
    matrix: &PrbMatrix,
    scene: &Scene,
    mechanism: &Mechanism,
) -> String {
    format!(
        "PRB mechanism: model {} ({}) exported by prbfit {} ({}) in place of every flexure of \
         the mechanism scene \"{}\".\n     \
         Matrix (nondimensional, scaled to each flexure's own L, E I0, E A0): {}\n     \
         Units: m, kg, rad, N, N m. Flexure i is the chain f<i>_segment1.. clamped at its root; \
         the stage is the body `stage` at the stage point P (site `stage`), its joints stage_x, \
         stage_y (m) and stage_phi (rad) are the stage pose (dx, dy, dphi).\n     \
         Drive: a loaded coordinate is a generalized force on its stage joint \
         (data.qfrc_applied); a prescribed one is the joint equality drive_x / drive_y / \
         drive_phi (set data.eq_active, and model.eq_data[id][0] to the target, ramped from \
         0), whose constraint force (efc_force times its efc_J row) is the reaction; as \
         written, the equalities of the coordinates drive 1 prescribes are active. Move \
         targets and loads in small steps (a jump trips MuJoCo's acceleration guard: the \
         closures are stiff) and add joint damping to settle to rest.\n     \
         Scene drives: {}",
        xml_comment_safe(name),
        xml_comment_safe(&matrix.topology()),
        env!("CARGO_PKG_VERSION"),
        utc_timestamp(),
        xml_comment_safe(&scene.name),
        xml_comment_safe(&matrix.to_text()),
        xml_comment_safe(&mjcf_mech::describe_drives(mechanism)),
    )
}

/// The comment every XML export opens with: what the model is, for which scene, the units.
pub fn header_comment(matrix: &PrbMatrix, scene: &Scene) -> String {
    format!(
        "PRB model {} exported by prbfit {} ({}) for the scene \"{}\".\n     \
         Matrix (nondimensional): {}\n     \
         Units: m, kg, N m/rad (torsion springs), N/m (extension springs). The chain lies \
         along +x from the clamp at the origin; hinges turn about +z.",
        xml_comment_safe(&matrix.topology()),
        env!("CARGO_PKG_VERSION"),
        utc_timestamp(),
        xml_comment_safe(&scene.name),
        xml_comment_safe(&matrix.to_text()),
    )
}

/// [`ExportError::TooStiff`]'s message: the frequencies' spread, or that they could not be
/// computed at all (infinite).
fn too_stiff(ratio: f64, steps: f64, limit: f64) -> String {
    if steps.is_finite() {
        format!(
            "the model's highest natural frequency is {ratio:.3e} times its lowest (a link with a \
             tiny mu on a stiff spring): MuJoCo would need {steps:.2e} time steps per period of \
             the first mode (the export's limit is {limit:.0e}); raise the smallest mus"
        )
    } else {
        "the model's natural frequencies cannot be computed (its links' masses or springs are \
         beyond what a double holds), so no time step can be chosen"
            .to_string()
    }
}

impl From<chain::TooStiff> for ExportError {
    fn from(e: chain::TooStiff) -> ExportError {
        ExportError::TooStiff {
            ratio: e.ratio,
            steps: e.steps_per_period,
            limit: chain::MAX_STEPS_PER_PERIOD,
        }
    }
}
