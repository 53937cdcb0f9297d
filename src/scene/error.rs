//! What a scene that cannot be used says: a [`RuleError`] names the key a rule is about and
//! why (the validators of [`super::rules`] and of each scene type return it), a
//! [`SceneError`] is that or a reader's error placed in a file (`file:line: key: message`).
//!
//! A rule error's key is a path from where the checked value sits: `thickness` from a
//! [`BeamSpec`](super::BeamSpec)'s own check, `beam.thickness` or `flexures[2].thickness`
//! once the scene places it ([`RuleError::under`]). The TOML reader maps that key to the line
//! that wrote it; an editor shows the error as it is (`beam.thickness: must be ...`).

use std::fmt;

/// A broken scene rule: the key it is about and what is wrong and what is allowed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct RuleError {
    /// Dotted key path, such as `thickness`, `loads[2].steps` or `flexures[1].link_to`;
    /// empty when the error is about the checked item as a whole.
    pub key: String,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl RuleError {
    /// An error about `key`.
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> RuleError {
        RuleError {
            key: key.into(),
            message: message.into(),
        }
    }

    /// An error about the checked item as a whole (an empty key).
    pub fn whole(message: impl Into<String>) -> RuleError {
        RuleError::new("", message)
    }

    /// The same error for the item placed at `prefix`: `thickness` under `beam` is
    /// `beam.thickness`, a whole-item error under `loads[2]` is `loads[2]`.
    pub fn under(self, prefix: &str) -> RuleError {
        let key = match (prefix.is_empty(), self.key.is_empty()) {
            (true, _) => self.key,
            (false, true) => prefix.to_string(),
            (false, false) => format!("{prefix}.{}", self.key),
        };
        RuleError { key, ..self }
    }

    /// The error as a scene error of `origin` (a scene's name or file) with no line.
    pub fn in_scene(self, origin: &str) -> SceneError {
        SceneError {
            origin: origin.to_string(),
            line: None,
            key: (!self.key.is_empty()).then_some(self.key),
            message: self.message,
        }
    }
}

impl fmt::Display for RuleError {
    /// `key: message`, or the message alone for a whole-item error: what an editor shows.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.key.is_empty() {
            write!(f, "{}: ", self.key)?;
        }
        write!(f, "{}", self.message)
    }
}

/// A scene that cannot be used, with where and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct SceneError {
    /// The file (or `<built-in scene>`).
    pub origin: String,
    /// 1-based line in the file, when the error has one.
    pub line: Option<usize>,
    /// Dotted key, such as `beam.thickness` or `loads[2].steps`.
    pub key: Option<String>,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.origin)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": ")?;
        if let Some(key) = &self.key {
            write!(f, "{key}: ")?;
        }
        write!(f, "{}", self.message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_compose_and_print() {
        let e = RuleError::new("thickness", "must be > 0").under("flexures[2]");
        assert_eq!(e.key, "flexures[2].thickness");
        assert_eq!(e.to_string(), "flexures[2].thickness: must be > 0");
        let whole = RuleError::whole("all zero").under("loads[1]");
        assert_eq!(whole.to_string(), "loads[1]: all zero");
        assert_eq!(RuleError::whole("x").to_string(), "x");
        let s = RuleError::new("beam.width", "bad").in_scene("s");
        assert_eq!(s.to_string(), "s: beam.width: bad");
        assert_eq!(RuleError::whole("bad").in_scene("s").key, None);
    }
}
