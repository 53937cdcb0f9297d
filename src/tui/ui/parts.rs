//! The pieces every panel draws with: the palette (colours, or none under NO_COLOR), the
//! colours of paths and of measured data, a panel's bordered block, a field's text or its
//! editor, and the geometry helpers (a centred box, equal-aspect canvas bounds).

use std::borrow::Cow;

use ratatui::layout::Rect;
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::Span;
use ratatui::widgets::{Block, Borders};

use super::super::app::{App, EditTarget};

/// Narrower than this, only the "too small" note is drawn.
pub const MIN_WIDTH: u16 = 60;
/// Lower than this, only the "too small" note is drawn.
pub const MIN_HEIGHT: u16 = 20;

/// Colours, or none at all under NO_COLOR.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Palette {
    /// No colour at all.
    pub mono: bool,
}

impl Palette {
    /// A style with foreground `c` (none under NO_COLOR).
    pub fn fg(&self, c: Color) -> Style {
        if self.mono {
            Style::default()
        } else {
            Style::default().fg(c)
        }
    }
    /// The colour `c` (the terminal's own under NO_COLOR).
    pub fn color(&self, c: Color) -> Color {
        if self.mono {
            Color::Reset
        } else {
            c
        }
    }
    /// A panel's border and title: bold cyan when `focused`.
    pub fn focus(&self, focused: bool) -> Style {
        if focused {
            self.fg(Color::Cyan).add_modifier(Modifier::BOLD)
        } else {
            Style::default()
        }
    }
    /// The selected row: reversed.
    pub fn selected(&self) -> Style {
        Style::default().add_modifier(Modifier::REVERSED)
    }
    /// A verdict: bold green when `ok`, else bold red.
    pub fn pass(&self, ok: bool) -> Style {
        self.fg(if ok { Color::Green } else { Color::Red })
            .add_modifier(Modifier::BOLD)
    }
}

/// The colour of measured data (DESIGN §9): the markers, the data line.
pub const MEASURED_COLOR: Color = Color::Magenta;

/// Path colours for the error charts.
pub const PATH_COLORS: [Color; 6] = [
    Color::Yellow,
    Color::Cyan,
    Color::Magenta,
    Color::Green,
    Color::Blue,
    Color::Red,
];

/// The mark of a measured point (a tip, a stage point, a row of a force–stroke chart).
pub const MEASURED_MARKER: &str = "×";

/// A panel's bordered block, highlighted when it has the focus.
pub fn panel_block<'a>(title: impl Into<Cow<'a, str>>, focused: bool, pal: Palette) -> Block<'a> {
    let title: Cow<'a, str> = title.into();
    Block::default()
        .borders(Borders::ALL)
        .border_style(pal.focus(focused))
        .title(Span::styled(title, pal.focus(focused)))
}

/// The text of a field, or its editor (with a cursor) when being edited.
pub fn field_text(app: &App, target: &EditTarget, text: String) -> (String, bool) {
    match &app.edit.editing {
        Some((t, tb)) if t == target => (tb.with_cursor(), true),
        _ => (text, false),
    }
}

/// A rectangle of at most `width` x `height` in the middle of `area`.
pub fn centered(area: Rect, width: u16, height: u16) -> Rect {
    let w = width.min(area.width);
    let h = height.min(area.height);
    Rect::new(
        area.x + (area.width - w) / 2,
        area.y + (area.height - h) / 2,
        w,
        h,
    )
}

/// Equal-aspect bounds for a braille canvas of `area` (2 x 4 dots per cell) holding `pts`.
pub fn equal_aspect_bounds(pts: &[(f64, f64)], area: Rect) -> ([f64; 2], [f64; 2]) {
    let (mut x0, mut x1, mut y0, mut y1) = (0.0_f64, 1.0_f64, -0.1_f64, 0.1_f64);
    for &(x, y) in pts.iter().filter(|p| p.0.is_finite() && p.1.is_finite()) {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let pad = 0.05 * (x1 - x0).max(y1 - y0);
    let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
    // World units per dot, made equal along both axes.
    let dots_x = (area.width.saturating_sub(2).max(1) as f64) * 2.0;
    let dots_y = (area.height.saturating_sub(2).max(1) as f64) * 4.0;
    let per_dot = ((x1 - x0) / dots_x).max((y1 - y0) / dots_y);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let (hx, hy) = (per_dot * dots_x / 2.0, per_dot * dots_y / 2.0);
    ([cx - hx, cx + hx], [cy - hy, cy + hy])
}

/// `text` in lines of at most `width` characters, broken between words; a word longer than a
/// line is broken at the width. The help and the message line wrap with it, and the message
/// line is as high as the lines it gives.
pub fn wrap_words(text: &str, width: usize) -> Vec<String> {
    let width = width.max(1);
    let mut out = Vec::new();
    let mut line = String::new();
    for word in text.split(' ').filter(|w| !w.is_empty()) {
        let (len, w) = (line.chars().count(), word.chars().count());
        if len > 0 && len + 1 + w > width {
            out.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        let mut rest: Vec<char> = word.chars().collect();
        while line.chars().count() + rest.len() > width {
            let room = width - line.chars().count();
            if room == 0 {
                out.push(std::mem::take(&mut line));
                continue;
            }
            line.extend(rest.drain(..room));
            out.push(std::mem::take(&mut line));
        }
        line.extend(rest);
    }
    out.push(line);
    out
}

#[cfg(test)]
mod wrap_tests {
    use crate::tui::ui::parts::wrap_words;

    #[test]
    fn words_wrap_to_the_width_and_long_words_break() {
        assert_eq!(wrap_words("short", 20), vec!["short"]);
        assert_eq!(wrap_words("aaaa bbbb", 5), vec!["aaaa", "bbbb"]);
        assert_eq!(wrap_words("aaaa bbbb", 10), vec!["aaaa bbbb"]);
        assert_eq!(
            wrap_words("x abcdefghijkl", 5),
            vec!["x", "abcde", "fghij", "kl"]
        );
        assert!(wrap_words("a b c d e f g h", 3)
            .iter()
            .all(|l| l.chars().count() <= 3));
    }
}
