//! TEMPORARY (replaced by the files-safety branch at merge).
use std::borrow::Cow;
/// Placeholder.
pub fn bounded(x: f64) -> String {
    if x == 0.0 || (1e-4..1e6).contains(&x.abs()) {
        format!("{}", (x * 1e6).round() / 1e6)
    } else {
        format!("{x:.5e}")
    }
}
/// Placeholder.
pub fn sanitize_terminal(s: &str) -> Cow<'_, str> {
    if s.chars().any(char::is_control) {
        Cow::Owned(
            s.chars()
                .map(|c| if c.is_control() { '?' } else { c })
                .collect(),
        )
    } else {
        Cow::Borrowed(s)
    }
}
