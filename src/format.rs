//! The file formats prbfit writes, and which file extension names which (one table, read by
//! the CLI, the UI and the exporters alike).

use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// A format prbfit can write a model in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// prbfit's own model file, TOML.
    Toml,
    /// prbfit's own model file, JSON.
    Json,
    /// MuJoCo MJCF.
    Mjcf,
    /// URDF (springs as Gazebo extension elements).
    Urdf,
    /// SDF 1.10.
    Sdf,
    /// The load cases, both tips and both shapes.
    Csv,
}

/// Each format: its name and the file extensions that select it (the first is the usual one).
const TABLE: [(Format, &str, &[&str]); 6] = [
    (Format::Toml, "toml", &["toml"]),
    (Format::Json, "json", &["json"]),
    (Format::Mjcf, "mjcf", &["mjcf", "xml"]),
    (Format::Urdf, "urdf", &["urdf"]),
    (Format::Sdf, "sdf", &["sdf"]),
    (Format::Csv, "csv", &["csv"]),
];

impl Format {
    /// Every format, in the order the help lists them.
    pub const ALL: [Format; 6] = [
        Format::Toml,
        Format::Json,
        Format::Mjcf,
        Format::Urdf,
        Format::Sdf,
        Format::Csv,
    ];

    /// The format's name, as `--format` takes it.
    pub fn name(self) -> &'static str {
        TABLE
            .iter()
            .find(|(f, _, _)| *f == self)
            .map_or("?", |(_, name, _)| name)
    }

    /// The format a file's extension names (`.xml` and `.mjcf` are MuJoCo).
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        TABLE
            .iter()
            .find(|(_, _, exts)| exts.contains(&ext.as_str()))
            .map(|(f, _, _)| *f)
    }

    /// Whether this is prbfit's own model file (which `eval --model` reads back).
    pub fn is_model_file(self) -> bool {
        matches!(self, Format::Toml | Format::Json)
    }

    /// The extensions, for messages: `.toml .json .mjcf/.xml .urdf .sdf .csv`.
    pub fn extensions_help() -> String {
        TABLE
            .iter()
            .map(|(_, _, exts)| {
                exts.iter()
                    .map(|e| format!(".{e}"))
                    .collect::<Vec<_>>()
                    .join("/")
            })
            .collect::<Vec<_>>()
            .join(" ")
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Format {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        TABLE
            .iter()
            .find(|(_, name, _)| *name == s)
            .map(|(f, _, _)| *f)
            .ok_or_else(|| {
                format!(
                    "unknown format `{s}` (expected {})",
                    Format::ALL.map(Format::name).join(", ")
                )
            })
    }
}

impl serde::Serialize for Format {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_extensions_agree() {
        for f in Format::ALL {
            assert_eq!(f.name().parse::<Format>(), Ok(f));
            let path = format!("model.{}", f.name());
            assert_eq!(Format::from_path(Path::new(&path)), Some(f));
        }
        assert_eq!(Format::from_path(Path::new("a.XML")), Some(Format::Mjcf));
        assert_eq!(Format::from_path(Path::new("a.stl")), None);
        assert_eq!(Format::from_path(Path::new("noext")), None);
        assert!("obj".parse::<Format>().unwrap_err().contains("toml, json"));
        assert_eq!(
            Format::extensions_help(),
            ".toml .json .mjcf/.xml .urdf .sdf .csv"
        );
    }
}
