//! The text box of a field's editor and of the prompts: a line with a cursor and the
//! readline keys people expect (the keymap's text-entry rows). A box opened on a pre-filled
//! value starts "fresh": the first character typed replaces the whole value, while a cursor
//! key keeps it for editing.

use super::super::keymap::Action;

/// Longest text a box takes, in characters.
pub const MAX_CHARS: usize = 256;

/// A line of text being typed, with its cursor.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TextBox {
    /// The text so far.
    pub text: String,
    /// The cursor, a byte index into `text` on a character boundary.
    pub cursor: usize,
    /// Pre-filled and not touched yet: the first character typed replaces the text.
    pub fresh: bool,
}

impl TextBox {
    /// A box pre-filled with `text` (fresh, the cursor at its end).
    pub fn new(text: impl Into<String>) -> TextBox {
        let text = text.into();
        TextBox {
            cursor: text.len(),
            fresh: !text.is_empty(),
            text,
        }
    }

    /// Types `c` at the cursor; over a fresh box it replaces the text.
    pub fn insert(&mut self, c: char) {
        if self.fresh {
            self.text.clear();
            self.cursor = 0;
            self.fresh = false;
        }
        if self.text.chars().count() < MAX_CHARS {
            self.text.insert(self.cursor, c);
            self.cursor += c.len_utf8();
        }
    }

    /// An editing key of the keymap's text scope; false for an action that is not one.
    pub fn apply(&mut self, action: Action) -> bool {
        self.fresh = false;
        let before = self.prev_boundary(self.cursor);
        let after = self.next_boundary(self.cursor);
        match action {
            Action::TextLeft => self.cursor = before,
            Action::TextRight => self.cursor = after,
            Action::TextStart => self.cursor = 0,
            Action::TextEnd => self.cursor = self.text.len(),
            Action::TextBackspace => {
                self.text.replace_range(before..self.cursor, "");
                self.cursor = before;
            }
            Action::TextDelete => self.text.replace_range(self.cursor..after, ""),
            Action::TextClearStart => {
                self.text.replace_range(..self.cursor, "");
                self.cursor = 0;
            }
            Action::TextClearEnd => self.text.truncate(self.cursor),
            Action::TextDeleteWord => {
                let start = self.word_start();
                self.text.replace_range(start..self.cursor, "");
                self.cursor = start;
            }
            _ => return false,
        }
        true
    }

    /// The text before and after the cursor.
    pub fn split(&self) -> (&str, &str) {
        self.text.split_at(self.cursor)
    }

    /// The text with the cursor drawn in: `_` at the end, `|` inside.
    pub fn with_cursor(&self) -> String {
        let (a, b) = self.split();
        if b.is_empty() {
            format!("{a}_")
        } else {
            format!("{a}|{b}")
        }
    }

    fn prev_boundary(&self, i: usize) -> usize {
        self.text[..i].char_indices().last().map_or(0, |(j, _)| j)
    }

    fn next_boundary(&self, i: usize) -> usize {
        self.text[i..]
            .chars()
            .next()
            .map_or(self.text.len(), |c| i + c.len_utf8())
    }

    /// Where Ctrl-W deletes back to: over spaces, then over the word before them (a word
    /// ends at a space or at the `,` `;` `-` of a matrix or topology text).
    fn word_start(&self) -> usize {
        let head = &self.text[..self.cursor];
        let trimmed = head.trim_end_matches(' ');
        let is_sep = |c: char| c == ' ' || c == ',' || c == ';' || c == '-';
        match trimmed.char_indices().rev().find(|&(_, c)| is_sep(c)) {
            // The word is the separator itself when nothing else is left.
            Some((j, c)) if j + c.len_utf8() == trimmed.len() => j,
            Some((j, c)) => j + c.len_utf8(),
            None => 0,
        }
    }
}
