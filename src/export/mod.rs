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
//! A mechanism scene (DESIGN §8) exports as the whole PRB mechanism ([`export_mechanism`]):
//! MuJoCo only so far ([`mjcf_mech`]); the other formats refuse it by name.

pub mod chain;
mod csv;
mod mjcf;
pub mod mjcf_mech;
mod sdf;
mod urdf;

use crate::eval::{evaluate, Baseline, ErrorFigures};
use crate::format::Format;
use crate::io::files::utc_timestamp;
use crate::io::{ModelFile, ModelFileError};
use crate::prb::PrbMatrix;
use crate::scene::{Mechanism, Scene};
use crate::text::xml_comment_safe;

use chain::Chain;

/// Everything an export needs.
pub struct ExportInput<'a> {
    /// The model's name.
    pub name: String,
    /// The model.
    pub matrix: &'a PrbMatrix,
    /// The scene it is exported for (its beam sets the SI values).
    pub scene: &'a Scene,
    /// The model judged on the scene (for the figures and the CSV).
    pub baseline: &'a Baseline,
    /// The fidelity of that baseline, for the provenance.
    pub fidelity: String,
    /// kg/m^3, for masses.
    pub density: f64,
}

/// Why an export failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExportError {
    /// The model cannot follow the scene's loads, so it has no figures to record.
    #[error("the model cannot follow the scene's loads: {0}")]
    Eval(String),
    /// A bad density.
    #[error("density must be a finite number > 0, got {}", crate::text::bounded(*.0))]
    Density(f64),
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

/// The text of the export in `format`.
pub fn export(input: &ExportInput, format: Format) -> Result<String, ExportError> {
    if !(input.density.is_finite() && input.density > 0.0) {
        return Err(ExportError::Density(input.density));
    }
    let weight = input.scene.fit.angle_weight;
    let evaluation = evaluate(input.matrix, input.baseline, weight)
        .map_err(|e| ExportError::Eval(e.to_string()))?;
    let chain = || Chain::new(input.matrix, &input.scene.beam, input.density);
    Ok(match format {
        Format::Toml => own(input, &evaluation.figures).to_toml()?,
        Format::Json => own(input, &evaluation.figures).to_json()?,
        Format::Mjcf => mjcf::write(&chain(), &header_comment(input)),
        Format::Urdf => urdf::write(&chain(), &header_comment(input)),
        Format::Sdf => sdf::write(&chain(), &header_comment(input)),
        Format::Csv => csv::write(
            input.matrix,
            input.baseline,
            &format!(
                "model {} ({}) on scene \"{}\"",
                input.name,
                input.matrix.to_text(),
                crate::text::sanitize_terminal(&input.scene.name).replace('"', "'")
            ),
        )?,
    })
}

/// Everything a mechanism export needs.
pub struct MechExportInput<'a> {
    /// The model's name.
    pub name: String,
    /// The model, in place of every flexure (scaled to each).
    pub matrix: &'a PrbMatrix,
    /// The scene, for the provenance and the targets.
    pub scene: &'a Scene,
    /// The scene's mechanism.
    pub mechanism: &'a Mechanism,
    /// The fidelity whose resolution the exact mechanism is solved at (model files record
    /// it).
    pub fidelity: crate::fidelity::Fidelity,
    /// kg/m^3, for masses.
    pub density: f64,
}

/// The formats that take a mechanism scene: MJCF holds the whole PRB mechanism; prbfit's own
/// model file (TOML, JSON) holds the model with its figures judged on the mechanism. URDF and
/// SDF have no loop closures of their own and CSV's load cases are the cantilever's.
pub fn mechanism_formats() -> &'static [Format] {
    &[Format::Mjcf, Format::Toml, Format::Json]
}

/// The text of the mechanism export in `format`.
pub fn export_mechanism(input: &MechExportInput, format: Format) -> Result<String, ExportError> {
    if !(input.density.is_finite() && input.density > 0.0) {
        return Err(ExportError::Density(input.density));
    }
    match format {
        Format::Mjcf => Ok(mjcf_mech::write(
            input.mechanism,
            input.matrix,
            input.density,
            &mechanism_comment(input),
        )),
        Format::Toml | Format::Json => {
            let file = mechanism_model_file(input)?;
            Ok(if format == Format::Json {
                file.to_json()?
            } else {
                file.to_toml()?
            })
        }
        Format::Urdf | Format::Sdf | Format::Csv => Err(ExportError::MechanismFormat {
            format,
            supported: mechanism_formats()
                .iter()
                .map(|f| f.name())
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}

/// The model file of a mechanism export: the model judged on the mechanism (the exact one at
/// the export's fidelity's resolution, the PRB one at the fit's tolerance), its figures and every
/// flexure's SI model recorded as a mechanism fit records them.
fn mechanism_model_file(input: &MechExportInput) -> Result<ModelFile, ExportError> {
    let scene = input.scene;
    // The truth: the exact mechanism, or a data scene's measured cases (DESIGN §9).
    let exact = crate::mech::measured::truth(scene, input.mechanism, input.fidelity.resolution())
        .map_err(|e| ExportError::Eval(format!("the exact mechanism: {e}")))?;
    let prb = crate::mech::prb::solve(input.mechanism, input.matrix, crate::fit::mech::MECH_TOL)
        .map_err(|e| ExportError::Eval(e.to_string()))?;
    let e = crate::mech::figures::compare(
        &input.mechanism.drives,
        &prb,
        &exact,
        scene.fit.angle_weight,
        scene.fit.force_weight,
    )
    .map_err(|e| ExportError::Eval(e.to_string()))?;
    let mut file = ModelFile::fitted_mechanism(
        input.matrix,
        scene,
        input.mechanism,
        &input.fidelity.to_string(),
        &e.figures,
    );
    file.name = input.name.clone();
    file.title = Some(format!(
        "{} ({}) judged on the mechanism {}",
        input.name,
        input.matrix.topology(),
        scene.name
    ));
    Ok(file)
}

/// The comment the mechanism's MJCF opens with: the model, the scene, the units, how to drive
/// it.
fn mechanism_comment(input: &MechExportInput) -> String {
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
        xml_comment_safe(&input.name),
        xml_comment_safe(&input.matrix.topology()),
        env!("CARGO_PKG_VERSION"),
        utc_timestamp(),
        xml_comment_safe(&input.scene.name),
        xml_comment_safe(&input.matrix.to_text()),
        xml_comment_safe(&mjcf_mech::describe_drives(input.mechanism)),
    )
}

fn own(input: &ExportInput, figures: &ErrorFigures) -> ModelFile {
    let mut file = ModelFile::fitted(input.matrix, input.scene, &input.fidelity, figures);
    file.name = input.name.clone();
    file.title = Some(format!(
        "{} for {}",
        input.matrix.topology(),
        input.scene.name
    ));
    file.source = Some(format!("prbfit {} export", env!("CARGO_PKG_VERSION")));
    file
}

/// The comment every XML export opens with: what the model is, for which scene, the units.
fn header_comment(input: &ExportInput) -> String {
    format!(
        "PRB model {} exported by prbfit {} ({}) for the scene \"{}\".\n     \
         Matrix (nondimensional): {}\n     \
         Units: m, kg, N m/rad (torsion springs), N/m (extension springs). The chain lies \
         along +x from the clamp at the origin; hinges turn about +z.",
        xml_comment_safe(&input.matrix.topology()),
        env!("CARGO_PKG_VERSION"),
        utc_timestamp(),
        xml_comment_safe(&input.scene.name),
        xml_comment_safe(&input.matrix.to_text()),
    )
}
