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
    let (scaled, unit) = match q {
        Quantity::Plain | Quantity::Fraction | Quantity::Angle => return trim_number(value, 6),
        Quantity::Length => {
            let a = value.abs();
            if a >= 1.0 {
                (value, "m")
            } else if a >= 1e-3 {
                (value * 1e3, "mm")
            } else {
                (value * 1e6, "um")
            }
        }
        Quantity::Pressure => {
            let a = value.abs();
            if a >= 1e9 {
                (value * 1e-9, "GPa")
            } else if a >= 1e6 {
                (value * 1e-6, "MPa")
            } else if a >= 1e3 {
                (value * 1e-3, "kPa")
            } else {
                (value, "Pa")
            }
        }
    };
    format!("{} {unit}", trim_number(scaled, 6))
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
