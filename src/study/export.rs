//! Exporting a model of a study (DESIGN §6): prbfit's own model file (TOML, JSON) with the
//! model's figures judged on the study's truth, the simulators' formats, and the CSV of the
//! cases. A cantilever exports as its chain (MJCF, URDF, SDF, CSV); a mechanism as the whole
//! PRB mechanism (MJCF); every scene as a model file. The writers are [`crate::export`]'s.

use crate::export::chain::Chain;
use crate::export::{
    csv, header_comment, mechanism_comment, mechanism_formats, mjcf, mjcf_mech, sdf, urdf,
    ExportError,
};
use crate::format::Format;
use crate::io::ModelFile;
use crate::prb::PrbMatrix;

use super::{Sampling, Study};

/// The links' density when neither the caller nor the scene's `[beam] density` gives one
/// (water's, kg/m^3: only the dynamics depend on it).
pub const DEFAULT_DENSITY: f64 = 1000.0;

impl Study {
    /// The text of `matrix`, named `name`, exported in `format` for this study's scene;
    /// `density` (kg/m^3; `None`: the scene's `[beam] density`, else [`DEFAULT_DENSITY`])
    /// gives the simulators' masses. The formats that record figures (the model file, the
    /// CSV) judge the model on the truth first, and fail when it cannot follow the scene.
    /// The model file carries the segments' masses in SI when a density is given or the
    /// scene has one (never the default's).
    pub fn export(
        &self,
        name: &str,
        matrix: &PrbMatrix,
        format: Format,
        density: Option<f64>,
    ) -> Result<String, ExportError> {
        let scene = self.scene();
        // The model file's masses: the density given, else the scene's, else none; the
        // simulators' links need one, the default if nothing gives it.
        let masses = density.or(scene.beam.density);
        let density = masses.unwrap_or(DEFAULT_DENSITY);
        if let Err(why) = crate::scene::rules::density(density) {
            return Err(ExportError::Density(why));
        }
        let fidelity = match self.sampling() {
            Sampling::Fidelity(f) => f.to_string(),
            Sampling::Every(r) => format!("tol {:e}", r.tol),
        };
        let judged = || {
            self.judge(matrix)
                .map_err(|e| ExportError::Eval(e.to_string()))
        };
        let own = || -> Result<ModelFile, ExportError> {
            let figures = judged()?.figures;
            let mut file = if masses != scene.beam.density {
                let mut at = scene.clone();
                at.beam.density = masses;
                ModelFile::fitted(matrix, &at, &fidelity, &figures)
            } else {
                ModelFile::fitted(matrix, scene, &fidelity, &figures)
            };
            file.name = name.to_string();
            if scene.mechanism.is_some() {
                file.title = Some(format!(
                    "{name} ({}) judged on the mechanism {}",
                    matrix.topology(),
                    crate::text::sanitize_terminal(&scene.name)
                ));
            } else {
                file.title = Some(format!(
                    "{} for {}",
                    matrix.topology(),
                    crate::text::sanitize_terminal(&scene.name)
                ));
                file.source = Some(format!("prbfit {} export", env!("CARGO_PKG_VERSION")));
            }
            Ok(file)
        };
        match (format, &scene.mechanism, self.baseline()) {
            (Format::Toml, _, _) => Ok(own()?.to_toml()?),
            (Format::Json, _, _) => Ok(own()?.to_json()?),
            (Format::Mjcf, Some(m), _) => mjcf_mech::write(
                m,
                matrix,
                density,
                &scene.body,
                &mechanism_comment(name, matrix, scene, m),
            ),
            (Format::Mjcf | Format::Urdf | Format::Sdf, None, _) => {
                judged()?;
                let chain = Chain::new(matrix, &scene.beam, density, &scene.body);
                let comment = header_comment(matrix, scene);
                match format {
                    Format::Mjcf => mjcf::write(&chain, &comment),
                    Format::Urdf => Ok(urdf::write(&chain, &comment)),
                    _ => Ok(sdf::write(&chain, &comment)),
                }
            }
            (Format::Csv, None, Some(baseline)) => csv::write(
                matrix,
                baseline,
                &format!(
                    "model {name} ({}) on scene \"{}\"",
                    matrix.to_text(),
                    crate::text::sanitize_terminal(&scene.name).replace('"', "'")
                ),
            ),
            _ => Err(ExportError::MechanismFormat {
                format,
                supported: mechanism_formats()
                    .iter()
                    .map(|f| f.name())
                    .collect::<Vec<_>>()
                    .join(", "),
            }),
        }
    }
}
