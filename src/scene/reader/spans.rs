//! Where each key of a scene file sits: the reader records the byte span of every value and
//! table it takes, so an error about a key, the reader's own or a rule's
//! ([`RuleError`]), names the line that wrote it.

use std::collections::HashMap;
use std::ops::Range;

use toml::Spanned;

use super::super::error::{RuleError, SceneError};
use super::super::rules;

/// The file being read and the spans of the keys read so far.
pub(super) struct Spans<'a> {
    text: &'a str,
    origin: &'a str,
    /// By key: a file of 100000 load paths records half a million keys, so a list searched
    /// on every record took minutes (the square of the keys).
    at: HashMap<String, Range<usize>>,
}

impl<'a> Spans<'a> {
    pub(super) fn new(text: &'a str, origin: &'a str) -> Spans<'a> {
        Spans {
            text,
            origin,
            at: HashMap::new(),
        }
    }

    /// Records that `key` was written at `span` (the first record of a key stays).
    pub(super) fn record(&mut self, key: impl Into<String>, span: Range<usize>) {
        self.at.entry(key.into()).or_insert(span);
    }

    /// The value of `v`, its span recorded for `key`.
    pub(super) fn take<T: Clone>(&mut self, key: impl Into<String>, v: &Spanned<T>) -> T {
        self.record(key, v.span());
        v.get_ref().clone()
    }

    /// An error at `span` about `key`.
    pub(super) fn error(&self, span: Range<usize>, key: &str, message: String) -> SceneError {
        SceneError {
            origin: self.origin.to_string(),
            line: Some(line_of(self.text, span.start)),
            key: Some(key.to_string()),
            message,
        }
    }

    /// A path's `steps` (1 when absent), by the step rule ([`rules::steps`]), its span
    /// recorded for `key`: a file may write any whole number, a path holds a `u32`.
    pub(super) fn steps(
        &mut self,
        raw: &Option<Spanned<i64>>,
        key: &str,
    ) -> Result<u32, SceneError> {
        match raw {
            None => Ok(1),
            Some(s) => {
                let v = self.take(key, s);
                rules::steps(v).map_err(|m| self.error(s.span(), key, m))
            }
        }
    }

    /// A rule error placed in the file: at the line of its key or, for a key the file does
    /// not write (a default), of the nearest table that holds it (`flexures[1].link_to` falls
    /// back to `flexures[1]`); with no line when the file writes none of them (a scene with
    /// no `[[drives]]`).
    pub(super) fn locate(&self, e: RuleError) -> SceneError {
        let mut key = e.key.as_str();
        let span = loop {
            if let Some(span) = self.at.get(key) {
                break Some(span.clone());
            }
            match key.rfind(['.', '[']) {
                Some(cut) if cut > 0 => key = &key[..cut],
                _ => break None,
            }
        };
        let mut out = e.in_scene(self.origin);
        out.line = span.map(|s| line_of(self.text, s.start));
        out
    }
}

/// 1-based line of a byte offset.
pub(super) fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}
