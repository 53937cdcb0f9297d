//! Making text safe for where it is printed or written. Pure functions: no terminal, no
//! files.
//!
//! Names in a scene file (the scene, its load paths, its beam) come from whoever wrote the
//! file, and a scene file can come from anywhere. Printed as they are, they can carry
//! terminal escape sequences (recolour the terminal, retitle the window, move the cursor,
//! on some terminals worse) and, written into an XML export, they can make the file
//! unreadable (a control character, or `--` inside a comment) or inject markup (`<`, `&`).
//! So every such string goes through one of these functions on its way out:
//!
//! - [`sanitize_terminal`] before it reaches a terminal (the CLI, the TUI, error messages),
//! - [`xml_text_safe`] for XML text and attribute values, [`xml_comment_safe`] for XML
//!   comments (MuJoCo, URDF, SDF),
//! - [`bounded`] / [`bounded_prec`] for numbers, so that `1e300` in a scene prints in a few
//!   characters and does not push a table or a status line off the screen.
//!
//! Whatever is replaced is replaced by [`REPLACEMENT`] (`?`): visible, ASCII, and one
//! character for one character, so a user can still tell where something was dropped.

use std::borrow::Cow;

/// What the sanitising functions put in place of a character they may not pass on.
pub const REPLACEMENT: char = '?';

/// Significant digits [`bounded`] prints.
pub const DEFAULT_SIG_DIGITS: usize = 6;

/// Whether `c` may not go to a terminal as it is: the C0 controls (U+0000–U+001F, including
/// ESC, BEL, tab and newline), DEL (U+007F) and the C1 controls (U+0080–U+009F, which some
/// terminals read as escape sequences on their own, e.g. U+009B as CSI) — that is,
/// [`char::is_control`] — and the bidirectional formatting characters (U+061C, U+200E,
/// U+200F, U+202A–U+202E, U+2066–U+2069), which reorder what is displayed around them so a
/// name can look like something it is not.
fn terminal_unsafe(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{061C}' | '\u{200E}' | '\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2066}'..='\u{2069}'
        )
}

/// `s` with every character that could act on a terminal replaced by [`REPLACEMENT`]: all
/// control characters ([`char::is_control`]: C0 including ESC, BEL, tab and newline, DEL and
/// C1) and the bidirectional formatting characters. Meant for single-line text (names,
/// paths); text that should keep its line breaks must be sanitised line by line. Borrows
/// when there is nothing to replace.
pub fn sanitize_terminal(s: &str) -> Cow<'_, str> {
    if !s.chars().any(terminal_unsafe) {
        return Cow::Borrowed(s);
    }
    Cow::Owned(
        s.chars()
            .map(|c| if terminal_unsafe(c) { REPLACEMENT } else { c })
            .collect(),
    )
}

/// Whether `c` may not be written into an XML document: what XML 1.0 (§2.2, production
/// `Char`) forbids — the C0 controls other than tab, newline and carriage return, and
/// U+FFFE and U+FFFF (surrogates cannot occur in a Rust string) — and also DEL and the C1
/// controls, which XML 1.0 allows but discourages and which act on a terminal when the file
/// is printed.
fn xml_unsafe(c: char) -> bool {
    (c.is_control() && !matches!(c, '\t' | '\n' | '\r')) || matches!(c, '\u{FFFE}' | '\u{FFFF}')
}

/// `s` made safe as XML 1.0 character data or as an attribute value (in either quotes):
/// characters XML does not allow (see the module docs) are replaced by [`REPLACEMENT`];
/// `&`, `<`, `>`, `"` and `'` are escaped as entities; tab, newline and carriage return are
/// written as character references (`&#9;`, `&#10;`, `&#13;`), so that they survive the
/// normalisation an XML parser applies to attribute values and line ends and the text
/// reads back exactly as given (apart from the replaced characters).
pub fn xml_text_safe(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' => out.push_str("&#9;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            c if xml_unsafe(c) => out.push(REPLACEMENT),
            c => out.push(c),
        }
    }
    out
}

/// `s` made safe as the content of an XML 1.0 comment (between `<!--` and `-->`):
/// characters XML does not allow are replaced by [`REPLACEMENT`], a space is put between
/// two consecutive `-` (a comment may not contain `--`) and after a final `-` (a comment may
/// not end with `-`). Nothing is escaped: a comment has no entities, and `<` or `&` in it
/// are harmless.
pub fn xml_comment_safe(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        let c = if xml_unsafe(c) { REPLACEMENT } else { c };
        if c == '-' && out.ends_with('-') {
            out.push(' ');
        }
        out.push(c);
    }
    if out.ends_with('-') {
        out.push(' ');
    }
    out
}

/// `x` in at most [`DEFAULT_SIG_DIGITS`] significant digits and a bounded width (at most 13
/// characters): see [`bounded_prec`].
pub fn bounded(x: f64) -> String {
    bounded_prec(x, DEFAULT_SIG_DIGITS)
}

/// `x` rounded to `sig` significant digits (clamped to 1..=17) in a bounded width: plainly
/// (`0.00123`, `-42.5`, `123457`) when the rounded value is at least 1e-4 and below 1e6 in
/// magnitude, in Rust's scientific notation (`1.5e300`, `-2e-7`) otherwise; trailing zeros
/// are dropped. Zero (of either sign) prints `0`, NaN `NaN`, the infinities `inf` and
/// `-inf`. Every output parses back as an `f64` (`str::parse`) equal to `x` to within half a
/// unit of the last printed digit. The width is at most `sig + 7` characters (sign, point,
/// and `e-308`).
pub fn bounded_prec(x: f64, sig: usize) -> String {
    format_prec(x, sig, false)
}

/// `x` rounded to `sig` significant digits as [`bounded_prec`] writes a number outside its
/// plain range, whatever its size: `6e5`, `1.2e6`, `-2.5e-3` (zero, NaN and the infinities as
/// there). For labels that must share one form (a plot axis's ticks).
pub fn scientific_prec(x: f64, sig: usize) -> String {
    format_prec(x, sig, true)
}

/// [`bounded_prec`], or with `scientific` its scientific form for every size.
fn format_prec(x: f64, sig: usize, scientific: bool) -> String {
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let sig = sig.clamp(1, 17);
    // Rounded once, here: the digits and the exponent both come from this one rounding, so a
    // value that rounds up to the next power of ten (999999.7 → 1e6) gets the right form.
    let sci = format!("{:.*e}", sig - 1, x.abs());
    // `{:e}` of a finite number always has an integer exponent; the fallback is unreachable.
    let (mantissa, exp) = sci.split_once('e').unwrap_or((sci.as_str(), "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
    let digits = digits.trim_end_matches('0');
    let digits = if digits.is_empty() { "0" } else { digits };
    let sign = if x < 0.0 { "-" } else { "" };
    if !scientific && (-4..6).contains(&exp) {
        if exp < 0 {
            let zeros = "0".repeat((-exp - 1) as usize);
            format!("{sign}0.{zeros}{digits}")
        } else {
            let int_len = exp as usize + 1;
            if digits.len() <= int_len {
                format!("{sign}{digits}{}", "0".repeat(int_len - digits.len()))
            } else {
                format!("{sign}{}.{}", &digits[..int_len], &digits[int_len..])
            }
        }
    } else {
        let (first, rest) = digits.split_at(1);
        let point = if rest.is_empty() { "" } else { "." };
        format!("{sign}{first}{point}{rest}e{exp}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A scene name meant to recolour the terminal, retitle the window, ring the bell and
    /// break an XML comment.
    const NASTY: &str = "\u{1b}[31mRED\u{1b}]0;pwned\u{7}--x-";

    /// The XML document an export would write, with `s` in a comment, an attribute and text.
    fn xml_with(s: &str) -> String {
        format!(
            "<a><!--{}--><b n=\"{}\" m='{}'>{}</b></a>",
            xml_comment_safe(s),
            xml_text_safe(s),
            xml_text_safe(s),
            xml_text_safe(s)
        )
    }

    /// What a strict parser reads back from [`xml_with`]: (comment, attribute n, attribute m,
    /// text).
    fn parse_back(s: &str) -> (String, String, String, String) {
        let xml = xml_with(s);
        let doc = roxmltree::Document::parse(&xml)
            .unwrap_or_else(|e| panic!("{e} in {xml:?} (from {s:?})"));
        let a = doc.root_element();
        let comment = a
            .children()
            .find(|n| n.is_comment())
            .and_then(|n| n.text())
            .unwrap_or("")
            .to_string();
        let b = a.children().find(|n| n.has_tag_name("b")).unwrap();
        (
            comment,
            b.attribute("n").unwrap().to_string(),
            b.attribute("m").unwrap().to_string(),
            b.text().unwrap_or("").to_string(),
        )
    }

    /// `s` with what XML may not carry replaced, as the text and attributes read back.
    fn xml_expected(s: &str) -> String {
        s.chars()
            .map(|c| if xml_unsafe(c) { REPLACEMENT } else { c })
            .collect()
    }

    #[test]
    fn terminal_controls_are_replaced() {
        assert_eq!(sanitize_terminal(NASTY), "?[31mRED?]0;pwned?--x-");
        // DEL, C1 (CSI), tab, newline, a right-to-left override.
        assert_eq!(
            sanitize_terminal("a\u{7f}b\u{9b}c\td\ne\u{202e}f"),
            "a?b?c?d?e?f"
        );
        // Ordinary text, including non-ASCII, is passed through without a copy.
        assert!(matches!(
            sanitize_terminal("Kragbalken µ=0.3 — 梁"),
            Cow::Borrowed("Kragbalken µ=0.3 — 梁")
        ));
    }

    #[test]
    fn the_nasty_name_survives_xml() {
        let (comment, n, m, text) = parse_back(NASTY);
        assert_eq!(comment, "?[31mRED?]0;pwned?- -x- ");
        assert_eq!(n, "?[31mRED?]0;pwned?--x-");
        assert_eq!(m, n);
        assert_eq!(text, n);
        // Markup is escaped, not interpreted.
        let (comment, n, _, text) = parse_back("</b><c x='1'>&amp;\"--><!--");
        assert_eq!(n, "</b><c x='1'>&amp;\"--><!--");
        assert_eq!(text, n);
        assert_eq!(comment, "</b><c x='1'>&amp;\"- -><!- - ");
        // Whitespace reads back exactly, even in attributes.
        let (_, n, _, text) = parse_back(" a\tb\r\nc ");
        assert_eq!(n, " a\tb\r\nc ");
        assert_eq!(text, n);
    }

    #[test]
    fn comments_never_hold_a_double_dash_or_end_with_one() {
        for s in ["-", "--", "---", "a-", "-a", "- -", "x--y---z----"] {
            let c = xml_comment_safe(s);
            assert!(!c.contains("--") && !c.ends_with('-'), "{s:?} → {c:?}");
            assert_eq!(c.replace(' ', ""), s.replace(' ', ""));
        }
        assert_eq!(xml_comment_safe(""), "");
    }

    #[test]
    fn forbidden_xml_characters_are_replaced() {
        assert_eq!(xml_text_safe("a\u{0}b\u{FFFE}c\u{FFFF}d\u{85}"), "a?b?c?d?");
        assert_eq!(xml_comment_safe("a\u{1b}b\u{FFFF}"), "a?b?");
    }

    #[test]
    fn numbers_print_in_a_bounded_width() {
        let cases: &[(f64, &str)] = &[
            (0.0, "0"),
            (-0.0, "0"),
            (1.0, "1"),
            (-42.5, "-42.5"),
            (0.1, "0.1"),
            (1e-4, "0.0001"),
            (9.99999e-5, "9.99999e-5"),
            (0.000123456789, "0.000123457"),
            (123456.7, "123457"),
            (999999.4, "999999"),
            (999999.7, "1e6"),
            (1e6, "1e6"),
            (1e300, "1e300"),
            (-1.5e-300, "-1.5e-300"),
            (f64::MAX, "1.79769e308"),
            (f64::MIN_POSITIVE, "2.22507e-308"),
            (5e-324, "4.94066e-324"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
            (std::f64::consts::PI, "3.14159"),
            (210e9, "2.1e11"),
        ];
        for &(x, want) in cases {
            assert_eq!(bounded(x), want, "{x:e}");
        }
        assert_eq!(bounded_prec(std::f64::consts::PI, 3), "3.14");
        assert_eq!(bounded_prec(std::f64::consts::PI, 0), "3");
        assert_eq!(bounded_prec(0.1, 17), "0.10000000000000001");
    }

    proptest! {
        #[test]
        fn any_string_makes_well_formed_xml(s in any::<String>()) {
            let (comment, n, m, text) = parse_back(&s);
            let want = xml_expected(&s);
            prop_assert_eq!(&n, &want);
            prop_assert_eq!(&m, &want);
            prop_assert_eq!(&text, &want);
            prop_assert!(!comment.contains("--") && !comment.ends_with('-'));
            // A comment has no escapes: the parser turns its line ends into `\n`.
            let squeeze = |t: &str| t.replace([' ', '\r', '\n'], "");
            prop_assert_eq!(squeeze(&comment), squeeze(&want));
        }

        #[test]
        fn control_heavy_strings_make_well_formed_xml(s in "[\\x00-\\x20\\-<>&'\"\\x7f-\\u{a0}\\u{fffe}\\u{ffff}a]{0,40}") {
            let (_, n, _, text) = parse_back(&s);
            let want = xml_expected(&s);
            prop_assert_eq!(&n, &want);
            prop_assert_eq!(&text, &want);
        }

        #[test]
        fn sanitized_text_holds_no_controls(s in any::<String>()) {
            let t = sanitize_terminal(&s);
            prop_assert!(!t.chars().any(terminal_unsafe));
            prop_assert_eq!(t.chars().count(), s.chars().count());
        }

        #[test]
        fn any_float_prints_short_and_reads_back(bits in any::<u64>(), sig in 1usize..=17) {
            let x = f64::from_bits(bits);
            let shown = bounded_prec(x, sig);
            prop_assert!(shown.len() <= sig + 7, "{:?} is {} long", shown, shown.len());
            if sig == DEFAULT_SIG_DIGITS {
                prop_assert!(bounded(x).len() <= 13);
            }
            let back: f64 = shown.parse().unwrap();
            if x.is_nan() {
                prop_assert!(back.is_nan());
            } else if x.is_infinite() || x == 0.0 {
                prop_assert_eq!(back, x);
            } else {
                // Half a unit in the last printed digit, plus the rounding of the parse (one
                // ulp, or one step between subnormals).
                let tolerance = (0.5 * 10f64.powi(1 - sig as i32) + f64::EPSILON) * x.abs()
                    + 5e-324;
                prop_assert!((back - x).abs() <= tolerance,
                    "{:e} printed {:?}, read back as {:e}", x, shown, back);
            }
        }
    }
}
