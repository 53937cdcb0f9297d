//! The published PRB models prbfit ships and compares against (DESIGN §3): Howell's 1R, Su's
//! 3R and Chen's 3R, converted to the PRB-matrix convention.
//!
//! The models' files live in `assets/models/` (the matrix, its source and how it was
//! converted) and are compiled in, so `--model su-3r` works from any directory and the fit can
//! start from them without reading a file. This module reads only those compiled-in texts; a
//! model file a user names is read by the IO layer ([`crate::io::model_file`]).

use std::sync::LazyLock;

use serde::Deserialize;

use super::PrbMatrix;

/// The published models' names, in the order the UI cycles through them.
pub const NAMES: [&str; 3] = ["howell-1r", "su-3r", "chen-3r"];

/// The compiled-in model files: name and TOML text.
pub const FILES: [(&str, &str); 3] = [
    (
        "howell-1r",
        include_str!("../../assets/models/howell-1r.toml"),
    ),
    ("su-3r", include_str!("../../assets/models/su-3r.toml")),
    ("chen-3r", include_str!("../../assets/models/chen-3r.toml")),
];

/// A published model: its matrix and where it comes from.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct PublishedModel {
    /// Short name (`su-3r`).
    pub name: String,
    /// Human name (`Su 3R`).
    pub title: String,
    /// Topology name (`L-R-R-R`).
    pub topology: String,
    /// The publication.
    pub source: String,
    /// How the published values were converted to this matrix.
    pub conversion: String,
    /// The matrix.
    pub prb: PrbMatrix,
}

/// The published model called `name`, if there is one.
pub fn by_name(name: &str) -> Option<PublishedModel> {
    let (_, text) = FILES.iter().find(|(n, _)| *n == name)?;
    parse(text)
}

/// The published models' matrices in the PRB-matrix notation, as DESIGN §3 gives them, in the
/// order of [`NAMES`]: the `prb` of each of [`FILES`] (a test checks it). A fit starts from them, and reading three
/// TOML files for that took a tenth of the 20-case 3R fit at draft (in a profile).
pub const MATRICES: [&str; 3] = [
    "0.15,inf,inf; 0.85,2.2525,inf",
    "0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf",
    "0.126,inf,inf; 0.35,3.25,inf; 0.388,2.84,inf; 0.136,2.95,inf",
];

/// The matrices of [`MATRICES`], parsed once.
pub fn matrices() -> &'static [PrbMatrix] {
    static PARSED: LazyLock<Vec<PrbMatrix>> = LazyLock::new(|| {
        MATRICES
            .iter()
            .filter_map(|text| PrbMatrix::parse(text).ok())
            .collect()
    });
    &PARSED
}

/// Every published model, in the order of [`NAMES`].
pub fn all() -> Vec<PublishedModel> {
    FILES.iter().filter_map(|(_, text)| parse(text)).collect()
}

/// Parses a compiled-in file. The files are checked by this module's tests (each parses, its
/// topology matches its matrix), so `None` here would mean a broken build, never bad input.
fn parse(text: &str) -> Option<PublishedModel> {
    toml::from_str(text).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_file_parses_and_matches_design() {
        assert_eq!(all().len(), NAMES.len());
        assert_eq!(matrices().len(), NAMES.len());
        for ((name, text), matrix) in NAMES.iter().zip(MATRICES).zip(matrices()) {
            let m = by_name(name).expect("a compiled-in model parses");
            assert_eq!(m.name, *name);
            assert_eq!(m.prb, PrbMatrix::parse(text).expect("valid"));
            assert_eq!(&m.prb, matrix, "{name}: its file and MATRICES differ");
            assert_eq!(m.topology, m.prb.topology());
            assert!(!m.source.is_empty() && !m.conversion.is_empty());
        }
        assert!(by_name("nosuch-9r").is_none());
    }
}
