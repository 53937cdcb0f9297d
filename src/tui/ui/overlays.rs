//! What is drawn over the panels: the help (every key, from the keymap), a prompt (with its
//! text and cursor, or a yes/no question), and the note when the terminal is too small.

use ratatui::layout::Rect;
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Wrap};
use ratatui::Frame;

use super::super::app::App;
use super::super::keymap::KEYMAP;
use crate::text::sanitize_terminal;

use super::parts::{centered, wrap_words, Palette, MIN_HEIGHT, MIN_WIDTH};

/// What the overlays draw.
#[derive(Debug, Clone)]
pub struct View<'a> {
    /// Show the help.
    pub help: bool,
    /// The help's first line shown (clamped to its length when drawn).
    pub help_scroll: u16,
    /// Where the drawn help tells the app how far it can scroll.
    pub help_scroll_max: &'a std::cell::Cell<u16>,
    /// An open prompt: its question and the text typed so far with the cursor drawn in
    /// (none for a yes/no question).
    pub prompt: Option<(&'static str, Option<String>)>,
    /// Colours.
    pub pal: Palette,
}

impl<'a> View<'a> {
    /// The overlays of `app`.
    pub fn new(app: &'a App) -> View<'a> {
        View {
            help: app.help,
            help_scroll: app.help_scroll,
            help_scroll_max: &app.help_scroll_max,
            prompt: app.prompt.as_ref().map(|(kind, tb)| {
                (
                    kind.question(),
                    (!kind.is_question()).then(|| tb.with_cursor()),
                )
            }),
            pal: Palette { mono: app.mono },
        }
    }
}

/// Draws the help, then the prompt, over whatever is in `area`.
pub fn draw(frame: &mut Frame, area: Rect, view: &View<'_>) {
    if view.help {
        draw_help(
            frame,
            area,
            view.help_scroll,
            view.help_scroll_max,
            view.pal,
        );
    }
    if let Some((question, text)) = &view.prompt {
        draw_prompt(frame, area, question, text.as_deref(), view.pal);
    }
}

/// The note drawn instead of the UI below the minimum size, with the question asked, if
/// any (keys act on nothing else there).
pub fn draw_too_small(frame: &mut Frame, area: Rect, question: Option<&str>) {
    let mut text = format!(
        "Terminal too small: {}x{}. prbfit needs at least {MIN_WIDTH}x{MIN_HEIGHT}. \
         Enlarge the window, or press q to quit.",
        area.width, area.height
    );
    if let Some(q) = question {
        text = format!("{q}\n{text}");
    }
    let note = Paragraph::new(text).wrap(Wrap { trim: true });
    frame.render_widget(note, area);
}

fn draw_help(
    frame: &mut Frame,
    area: Rect,
    scroll: u16,
    scroll_max: &std::cell::Cell<u16>,
    pal: Palette,
) {
    // The keys' column, then each description wrapped under itself (a wrapped line used to
    // start at the border, under the keys).
    const KEYS: usize = 28;
    let width = area.width.min(106);
    let room = usize::from(width.saturating_sub(2))
        .saturating_sub(KEYS)
        .max(10);
    let mut lines: Vec<Line> = Vec::new();
    for e in KEYMAP {
        for (i, part) in wrap_words(e.does, room).into_iter().enumerate() {
            let keys = if i == 0 { e.keys } else { "" };
            lines.push(Line::from(vec![
                Span::styled(format!(" {keys:<w$}", w = KEYS - 1), pal.fg(Color::Cyan)),
                Span::raw(part),
            ]));
        }
    }
    let total = lines.len() as u16;
    let rect = centered(area, width, total + 2);
    let shown = rect.height.saturating_sub(2);
    let last_first = total.saturating_sub(shown);
    scroll_max.set(last_first);
    let scroll = scroll.min(last_first);
    let title = if shown < total {
        format!(
            " Keys {}-{} of {} lines · up/down, PgUp/PgDn scroll · any other key closes ",
            scroll + 1,
            (scroll + shown).min(total),
            total
        )
    } else {
        " Keys ".to_string()
    };
    frame.render_widget(Clear, rect);
    let block = Block::default().borders(Borders::ALL).title(title);
    frame.render_widget(Paragraph::new(lines).block(block).scroll((scroll, 0)), rect);
}

fn draw_prompt(frame: &mut Frame, area: Rect, question: &str, text: Option<&str>, pal: Palette) {
    let rect = centered(area, 70, 3);
    frame.render_widget(Clear, rect);
    let block = Block::default()
        .borders(Borders::ALL)
        .border_style(pal.fg(Color::Cyan))
        .title(format!(" {question} "));
    frame.render_widget(
        Paragraph::new(text.map(sanitize_terminal).unwrap_or_default().into_owned()).block(block),
        rect,
    );
}
