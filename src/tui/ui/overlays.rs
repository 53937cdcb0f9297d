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

use super::parts::{centered, Palette, MIN_HEIGHT, MIN_WIDTH};

/// What the overlays draw.
#[derive(Debug, Clone)]
pub struct View {
    /// Show the help.
    pub help: bool,
    /// An open prompt: its question and the text typed so far with the cursor drawn in
    /// (none for a yes/no question).
    pub prompt: Option<(&'static str, Option<String>)>,
    /// Colours.
    pub pal: Palette,
}

impl View {
    /// The overlays of `app`.
    pub fn new(app: &App) -> View {
        View {
            help: app.help,
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
pub fn draw(frame: &mut Frame, area: Rect, view: &View) {
    if view.help {
        draw_help(frame, area, view.pal);
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

fn draw_help(frame: &mut Frame, area: Rect, pal: Palette) {
    let rect = centered(area, 106, KEYMAP.len() as u16 + 2);
    frame.render_widget(Clear, rect);
    let lines: Vec<Line> = KEYMAP
        .iter()
        .map(|e| {
            Line::from(vec![
                Span::styled(format!(" {:<27}", e.keys), pal.fg(Color::Cyan)),
                Span::raw(e.does),
            ])
        })
        .collect();
    let block = Block::default().borders(Borders::ALL).title(" Keys ");
    frame.render_widget(
        Paragraph::new(lines)
            .block(block)
            .wrap(Wrap { trim: false }),
        rect,
    );
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
