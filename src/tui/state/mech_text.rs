//! How the mechanism panel shows and reads its values: points, lengths, angles and drive
//! coordinates in the mechanism's display units ([`MechUnits`]: mm under a metre-long
//! flexure 1, else m; degrees; N; N m), a bare number in those units, a number with a unit
//! (`0.02 m`, `0.5 rad`, `3 mN`) in its own.

use crate::scene::Coordinate;
use crate::si::MechUnits;

use super::super::units::{parse_quantity, trim_number, Quantity};

/// A coordinate's end value in display units, with its unit: `15 mm`, `0 deg`, `2.5 N`.
pub(super) fn value_text(c: usize, k: Coordinate, u: &MechUnits) -> String {
    let unit = match (k.is_prescribed(), c == 2) {
        (true, true) => "deg",
        (true, false) => u.distance,
        (false, true) => "N m",
        (false, false) => "N",
    };
    format!("{} {unit}", trim_number(u.input(c, k), 6))
}

/// A point in display units: `67.68, -17.68 mm`.
pub(super) fn point_text(p: [f64; 2], u: &MechUnits) -> String {
    format!(
        "{}, {} {}",
        trim_number(p[0] * u.per_metre, 5),
        trim_number(p[1] * u.per_metre, 5),
        u.distance
    )
}

pub(super) fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// A length typed in the panel, m: bare numbers are in the display unit.
pub(super) fn parse_length(text: &str, u: &MechUnits) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v / u.per_metre),
        Ok(_) => Err(format!("`{}` is not a finite number", text.trim())),
        Err(_) => parse_quantity(text, Quantity::Length),
    }
}

/// `x, y` with an optional unit after either number (one after `y` applies to a bare `x`).
pub(super) fn parse_point(text: &str, u: &MechUnits) -> Result<[f64; 2], String> {
    let parts: Vec<&str> = text.split(',').collect();
    let [x, y] = parts.as_slice() else {
        return Err(format!(
            "type x, y (e.g. `50, -10` in {} or `0.05, -0.01 m`)",
            u.distance
        ));
    };
    let y_value = parse_length(y, u)?;
    let x_value = match x.trim().parse::<f64>() {
        // A bare x takes y's unit: "50, -10 mm".
        Ok(v) if v.is_finite() => {
            let unit = y.trim().trim_start_matches(|ch: char| {
                ch.is_ascii_digit() || matches!(ch, '.' | '-' | '+' | 'e' | 'E')
            });
            if unit.trim().is_empty() {
                v / u.per_metre
            } else {
                parse_quantity(&format!("{v} {}", unit.trim()), Quantity::Length)?
            }
        }
        _ => parse_length(x, u)?,
    };
    Ok([x_value, y_value])
}

/// An angle typed in degrees (bare or `deg`) or radians (`rad`), returned in radians.
pub(super) fn parse_angle(text: &str) -> Result<f64, String> {
    super::super::units::parse_angle(text, true)
}

/// A coordinate's end value typed in display units (mm, deg, N, N m) or with its own unit,
/// returned in SI (m, rad, N, N m).
pub(super) fn parse_value(
    c: usize,
    k: Coordinate,
    text: &str,
    u: &MechUnits,
) -> Result<f64, String> {
    match (k.is_prescribed(), c == 2) {
        (true, false) => parse_length(text, u),
        (true, true) => parse_angle(text),
        (false, rotation) => {
            let t = text.trim();
            let units: &[(&str, f64)] = if rotation {
                &[
                    ("N mm", 1e-3),
                    ("Nmm", 1e-3),
                    ("N m", 1.0),
                    ("Nm", 1.0),
                    ("N·m", 1.0),
                ]
            } else {
                &[("mN", 1e-3), ("kN", 1e3), ("N", 1.0)]
            };
            let (number, factor) = units
                .iter()
                .find_map(|(unit, f)| t.strip_suffix(unit).map(|n| (n, *f)))
                .unwrap_or((t, 1.0));
            Ok(parse_quantity(number, Quantity::Plain)? * factor)
        }
    }
}
