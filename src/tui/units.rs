//! Numbers as engineers type them: `0.5e-3`, `200e9`, `200 GPa`, `0.5 mm`, `12.5um`.

/// What a field measures, which decides the units it accepts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// Metres: m, cm, mm, um (or µm), nm.
    Length,
    /// Pascals: Pa, kPa, MPa, GPa.
    Pressure,
    /// A plain number.
    Plain,
    /// A fraction, as shown beside it: plain, or in % (a position target in units of L, a
    /// force target as a fraction of the largest force).
    Fraction,
    /// An angle: rad (plain) or deg.
    Angle,
}

impl Quantity {
    /// The SI unit written after values of this kind.
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::Length => "m",
            Quantity::Pressure => "Pa",
            Quantity::Plain | Quantity::Fraction | Quantity::Angle => "",
        }
    }
}

/// Parses `text` as a finite number of kind `q`, returning SI units.
pub fn parse_quantity(text: &str, q: Quantity) -> Result<f64, String> {
    let t = text.trim();
    if t.is_empty() {
        return Err("empty: type a number".into());
    }
    // The longest prefix that parses as a number; the rest is the unit.
    let (split, value) = (1..=t.len())
        .rev()
        .filter(|&i| t.is_char_boundary(i))
        .find_map(|i| t[..i].trim().parse::<f64>().ok().map(|v| (i, v)))
        .ok_or_else(|| format!("`{t}` does not start with a number"))?;
    if !value.is_finite() {
        return Err(format!("`{t}` is not a finite number"));
    }
    let unit = t[split..].trim();
    let factor = match (q, unit) {
        (_, "") => 1.0,
        (Quantity::Length, "m") => 1.0,
        (Quantity::Length, "cm") => 1e-2,
        (Quantity::Length, "mm") => 1e-3,
        (Quantity::Length, "um" | "µm" | "μm") => 1e-6,
        (Quantity::Length, "nm") => 1e-9,
        (Quantity::Pressure, "Pa") => 1.0,
        (Quantity::Pressure, "kPa") => 1e3,
        (Quantity::Pressure, "MPa") => 1e6,
        (Quantity::Pressure, "GPa") => 1e9,
        (Quantity::Fraction, "%" | "%L") => 1e-2,
        (Quantity::Fraction, "L") => 1.0,
        (Quantity::Fraction, u) => {
            return Err(format!("unknown unit `{u}` (a plain fraction, or %)"))
        }
        // Its own rule, shared with the mechanism panel's angles.
        (Quantity::Angle, _) => return parse_angle(text, false),
        (Quantity::Length, u) => {
            return Err(format!(
                "unknown length unit `{u}` (use m, cm, mm, um or nm)"
            ))
        }
        (Quantity::Pressure, u) => {
            return Err(format!(
                "unknown pressure unit `{u}` (use Pa, kPa, MPa or GPa)"
            ))
        }
        (Quantity::Plain, u) => return Err(format!("`{u}`: this value takes no unit")),
    };
    Ok(value * factor)
}

/// An angle typed in radians (`rad`) or degrees (`deg`, `°`), returned in radians; a bare
/// number is in degrees when `bare_degrees` (the mechanism panel's angles), else in radians
/// (an accuracy target, shown as `0.02 rad (1.146 deg)`).
pub fn parse_angle(text: &str, bare_degrees: bool) -> Result<f64, String> {
    let t = text.trim();
    let (number, degrees) = if let Some(n) = t.strip_suffix("rad") {
        (n, false)
    } else if let Some(n) = t.strip_suffix("deg").or_else(|| t.strip_suffix('°')) {
        (n, true)
    } else {
        (t, bare_degrees)
    };
    let v = parse_quantity(number, Quantity::Plain)?;
    Ok(if degrees { v.to_radians() } else { v })
}

/// A compact engineering form for display: `50 mm`, `200 GPa`, `0.3`.
pub fn format_quantity(value: f64, q: Quantity) -> String {
    match shown_unit(value, q) {
        Some((unit, size)) => format!("{} {unit}", trim_number(value / size, 6)),
        None => trim_number(value, 6),
    }
}

/// The unit [`format_quantity`] shows `value` in, and its size in SI (`None` for a kind
/// without units).
fn shown_unit(value: f64, q: Quantity) -> Option<(&'static str, f64)> {
    let a = value.abs();
    Some(match q {
        Quantity::Plain | Quantity::Fraction | Quantity::Angle => return None,
        Quantity::Length if a >= 1.0 => ("m", 1.0),
        Quantity::Length if a >= 1e-3 => ("mm", 1e-3),
        Quantity::Length => ("um", 1e-6),
        Quantity::Pressure if a >= 1e9 => ("GPa", 1e9),
        Quantity::Pressure if a >= 1e6 => ("MPa", 1e6),
        Quantity::Pressure if a >= 1e3 => ("kPa", 1e3),
        Quantity::Pressure => ("Pa", 1.0),
    })
}

/// [`parse_quantity`] of a value typed over `shown` (SI), which the field shows in its unit
/// (`40 mm`). A bare number is SI, as everywhere; but a bare number that is a plausible
/// value only in the shown unit (within 100 times `shown` that way, and not in SI) is
/// refused with both readings, not taken as SI: `45` over `40 mm` would be a 45 m beam.
pub fn parse_over(text: &str, q: Quantity, shown: f64) -> Result<f64, String> {
    let v = parse_quantity(text, q)?;
    let t = text.trim();
    let bare = t.parse::<f64>().is_ok();
    let Some((unit, size)) = shown_unit(shown, q) else {
        return Ok(v);
    };
    let near = |x: f64| shown != 0.0 && (0.01..=100.0).contains(&(x / shown).abs());
    if bare && size != 1.0 && near(v * size) && !near(v) {
        return Err(format!(
            "`{t}` has no unit, so it is SI: {}, {} times the present {}; type `{t} {unit}` for \
             {unit}, or `{t} {}` to mean it",
            format_quantity(v, q),
            trim_number(v / shown, 3),
            format_quantity(shown, q),
            q.unit()
        ));
    }
    Ok(v)
}

/// `value` with up to `digits` significant digits, trailing zeros removed.
pub fn trim_number(value: f64, digits: usize) -> String {
    if value == 0.0 {
        return "0".into();
    }
    let a = value.abs();
    if !(1e-4..1e6).contains(&a) {
        let s = format!("{value:.prec$e}", prec = digits.saturating_sub(1));
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = if mantissa.contains('.') {
            mantissa.trim_end_matches('0').trim_end_matches('.')
        } else {
            mantissa
        };
        return format!("{mantissa}e{exponent}");
    }
    let decimals = (digits as i32 - 1 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{value:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bare_number_that_fits_only_the_shown_unit_asks_for_the_unit() {
        // 45 over 40 mm: 45 m is 1125 times the present length, 45 mm is near it.
        let e = parse_over("45", Quantity::Length, 0.04).unwrap_err();
        assert!(e.contains("`45` has no unit") && e.contains("45 m") && e.contains("1125"));
        assert!(e.contains("`45 mm`") && e.contains("`45 m`"), "{e}");
        // Typed with a unit, either way, it is what it says.
        assert_eq!(parse_over("45 mm", Quantity::Length, 0.04).unwrap(), 0.045);
        assert_eq!(parse_over("45 m", Quantity::Length, 0.04).unwrap(), 45.0);
        // A bare SI number near the present value is SI, as documented.
        assert_eq!(parse_over("0.045", Quantity::Length, 0.04).unwrap(), 0.045);
        assert_eq!(parse_over("70e9", Quantity::Pressure, 200e9).unwrap(), 70e9);
        // 70 over 200 GPa reads as 70 Pa: refused; a value shown in the SI unit is never.
        assert!(parse_over("70", Quantity::Pressure, 200e9).is_err());
        assert_eq!(parse_over("2", Quantity::Length, 1.5).unwrap(), 2.0);
        // Far from the present value both ways: SI, as typed (the scene's rules judge it).
        assert_eq!(parse_over("5e-9", Quantity::Length, 0.04).unwrap(), 5e-9);
        // No unit to confuse: plain numbers pass through.
        assert_eq!(parse_over("0.3", Quantity::Plain, 0.29).unwrap(), 0.3);
    }

    #[test]
    fn engineering_input() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs();
        assert!(close(
            parse_quantity("0.5e-3", Quantity::Length).unwrap(),
            0.5e-3
        ));
        assert!(close(
            parse_quantity("0.5 mm", Quantity::Length).unwrap(),
            0.5e-3
        ));
        assert!(close(
            parse_quantity("12.5um", Quantity::Length).unwrap(),
            12.5e-6
        ));
        assert!(close(
            parse_quantity("200 GPa", Quantity::Pressure).unwrap(),
            200e9
        ));
        assert!(close(
            parse_quantity("200e9", Quantity::Pressure).unwrap(),
            200e9
        ));
        assert!(close(
            parse_quantity(" 20MPa ", Quantity::Pressure).unwrap(),
            20e6
        ));
        assert_eq!(parse_quantity("0.3", Quantity::Plain).unwrap(), 0.3);
        assert!(parse_quantity("0.3 mm", Quantity::Plain).is_err());
        assert!(parse_quantity("5 furlongs", Quantity::Length)
            .unwrap_err()
            .contains("furlongs"));
        assert!(parse_quantity("abc", Quantity::Length).is_err());
        assert!(parse_quantity("nan", Quantity::Length).is_err());
        assert!(parse_quantity("inf", Quantity::Plain).is_err());
        assert!(parse_quantity("", Quantity::Plain).is_err());
        // Targets as they are shown: `0.01 L (1%)`, `0.02 rad (1.146 deg)`.
        assert!(close(
            parse_quantity("1%", Quantity::Fraction).unwrap(),
            0.01
        ));
        assert!(close(
            parse_quantity("0.01 L", Quantity::Fraction).unwrap(),
            0.01
        ));
        assert!(close(
            parse_quantity("1.146 deg", Quantity::Angle).unwrap(),
            1.146_f64.to_radians()
        ));
        assert_eq!(parse_quantity("0.02 rad", Quantity::Angle).unwrap(), 0.02);
        assert!(parse_quantity("1 mm", Quantity::Fraction).is_err());
    }

    #[test]
    fn display_round_trips_through_input() {
        for (v, q) in [
            (0.05, Quantity::Length),
            (0.0005, Quantity::Length),
            (200e9, Quantity::Pressure),
            (20e6, Quantity::Pressure),
            (0.3, Quantity::Plain),
        ] {
            let s = format_quantity(v, q);
            let back = parse_quantity(&s, q).unwrap();
            assert!((back - v).abs() <= 1e-9 * v, "{v} -> {s} -> {back}");
        }
        assert_eq!(format_quantity(0.05, Quantity::Length), "50 mm");
        assert_eq!(trim_number(1e9, 6), "1e9");
        assert_eq!(trim_number(-2.5e-7, 6), "-2.5e-7");
        assert_eq!(trim_number(123456789.0, 6), "1.23457e8");
        assert_eq!(format_quantity(200e9, Quantity::Pressure), "200 GPa");
    }
}
