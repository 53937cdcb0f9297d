//! The value rules a scene is built from: a number that must be positive, finite, a ratio in
//! `[0, 0.5)`, a step count, a slenderness, and the limits on steps and cases.
//!
//! Each rule returns what is wrong in words (`must be a finite number > 0, got -1`); the
//! `validate` method of each scene type ([`BeamSpec`](super::BeamSpec),
//! [`LoadPath`](super::LoadPath), [`Flexure`](super::Flexure), [`Drive`](super::Drive),
//! [`Mechanism`](super::Mechanism), [`Scene`](super::Scene), ...) applies them to its fields
//! and names the key. The TOML reader and every editor (the UI) apply those methods, so
//! this file and those methods are the one place that says what a valid scene is.

use crate::beam::{Load, MAX_SLENDERNESS};
use crate::text::bounded;

/// The most load steps one path may ask for.
pub const MAX_STEPS: i64 = 10_000;

/// The most load cases a scene may have over all its paths. A solve costs tens of
/// microseconds per case and a fit evaluates every case hundreds of times, so this is already
/// minutes of fitting; a scene with more is a mistake (a generated file run wild), refused
/// before any work.
pub const MAX_CASES: u64 = 100_000;

/// A finite number `> 0`.
pub fn positive(v: f64) -> Result<(), String> {
    (v.is_finite() && v > 0.0)
        .then_some(())
        .ok_or_else(|| format!("must be a finite number > 0, got {}", bounded(v)))
}

/// The stiffest Young's modulus a scene may give, Pa: ten times diamond's (about 1.2e12 Pa),
/// the stiffest solid. A larger one is a unit slip (GPa written as Pa twice over), and one
/// near `f64::MAX` overflows every stress it scales to infinity.
pub const MAX_MODULUS: f64 = 1e13;

/// A Young's modulus: finite, `> 0` and at most [`MAX_MODULUS`] Pa.
pub fn modulus(v: f64) -> Result<(), String> {
    positive(v)?;
    if v > MAX_MODULUS {
        return Err(format!(
            "must be at most {MAX_MODULUS:e} Pa (ten times diamond's, the stiffest solid; \
             the scene is in SI units), got {}",
            bounded(v)
        ));
    }
    Ok(())
}

/// The smallest and largest SI size (a beam's length, width or thickness), m: a nanometre,
/// below which no beam is a continuum, and a kilometre. Beyond them a size is a unit slip,
/// and near `f64::MAX` or its least normal one the section's `E I0 = E w t0^3 / 12` and
/// every force scaled by it overflow (a kilometre of steel a kilometre square is 1e25 N m^2).
pub const MIN_SIZE: f64 = 1e-9;
/// See [`MIN_SIZE`].
pub const MAX_SIZE: f64 = 1e3;

/// A size: finite and from [`MIN_SIZE`] to [`MAX_SIZE`] m.
pub fn size(v: f64) -> Result<(), String> {
    positive(v)?;
    within(
        v,
        MIN_SIZE,
        MAX_SIZE,
        "m (a nanometre to a kilometre; the scene is in SI units)",
    )
}

/// A shear coefficient: finite, `> 0` and at most [`crate::beam::MAX_KAPPA`].
pub fn shear_coefficient(v: f64) -> Result<(), String> {
    positive(v)?;
    within(
        v,
        0.0,
        crate::beam::MAX_KAPPA,
        "(real sections' lie between about 0.5 and 1)",
    )
}

/// The lightest and densest material, kg/m^3: below aerogels (about 1) and above osmium
/// (22590) by a margin. Beyond them the links' masses (the MJCF exporter's, the modes')
/// fall below what a simulator takes or overflow what is derived from them.
pub const MIN_DENSITY: f64 = 1e-3;
/// See [`MIN_DENSITY`].
pub const MAX_DENSITY: f64 = 1e5;

/// A density: finite and from [`MIN_DENSITY`] to [`MAX_DENSITY`] kg/m^3.
pub fn density(v: f64) -> Result<(), String> {
    positive(v)?;
    within(
        v,
        MIN_DENSITY,
        MAX_DENSITY,
        "kg/m^3 (the scene is in SI units)",
    )
}

/// An allowable stress, Pa: finite, `> 0` and at most [`MAX_MODULUS`] (no material carries a
/// stress above the stiffest modulus).
pub fn allowable_stress(v: f64) -> Result<(), String> {
    positive(v)?;
    within(
        v,
        0.0,
        MAX_MODULUS,
        "Pa (the stiffest modulus; the scene is in SI units)",
    )
}

/// The largest weight a fit may give one error over another: a billion. `J` sums weighted
/// squares, and a weight near `f64::MAX` made it infinite (a result the CLI refused as an
/// internal error and the Python module handed out as `None`).
pub const MAX_WEIGHT: f64 = 1e9;

/// A fit weight: finite, `>= 0` and at most [`MAX_WEIGHT`].
pub fn weight(v: f64) -> Result<(), String> {
    non_negative(v)?;
    within(
        v,
        0.0,
        MAX_WEIGHT,
        "(a billion times the position error's weight of 1)",
    )
}

/// `v` from `lo` to `hi` (the bounds allowed), else an error naming them in `unit`.
fn within(v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), String> {
    if v < lo {
        return Err(format!(
            "must be at least {} {unit}, got {}",
            bounded(lo),
            bounded(v)
        ));
    }
    if v > hi {
        return Err(format!(
            "must be at most {} {unit}, got {}",
            bounded(hi),
            bounded(v)
        ));
    }
    Ok(())
}

/// The largest magnitude a load (nondimensional `alpha`, `beta`), a drive's end
/// (nondimensional: units of flexure 1's `L`, radians, `E I0/L^2`, `E I0/L`) or a data file's
/// value may have: the solvers follow loads past 1e8 (slowly: a third of a second a case),
/// and a number near `f64::MAX` overflows what is derived from it, or runs the continuation
/// for seconds to give up at 1e-303 of the path.
pub const MAX_NONDIMENSIONAL: f64 = 1e9;

/// A finite load, drive component or measured value within [`MAX_NONDIMENSIONAL`] once
/// nondimensional: `v` as given, `scaled` as the solvers see it.
pub fn reachable(v: f64, scaled: f64) -> Result<(), String> {
    finite(v)?;
    if scaled.abs() > MAX_NONDIMENSIONAL {
        let shown = if v == scaled {
            String::new()
        } else {
            format!(" ({} nondimensional)", bounded(scaled))
        };
        return Err(format!(
            "{}{shown} is beyond the {MAX_NONDIMENSIONAL:e} prbfit follows (in units of L, \
             radians, E I0/L^2 or E I0/L): check the units",
            bounded(v)
        ));
    }
    Ok(())
}

/// A single tip load given outside a scene (`--load`, Python's `load=`): each component
/// [`reachable`], as a scene's `[[loads]]` must be; the message names the component.
pub fn single_load(load: &Load) -> Result<(), String> {
    for (name, v) in [
        ("alpha_x", load.alpha_x),
        ("alpha_y", load.alpha_y),
        ("beta", load.beta),
    ] {
        reachable(v, v).map_err(|m| format!("{name} {m}"))?;
    }
    Ok(())
}

/// A direction in radians, given in degrees: within a turn either way.
pub fn direction(radians: f64) -> Result<(), String> {
    let deg = radians.to_degrees();
    (deg.is_finite() && deg.abs() <= 360.0)
        .then_some(())
        .ok_or_else(|| format!("must be from -360 to 360 degrees, got {}", bounded(deg)))
}

/// Poisson's ratio: in `[0, 0.5)`.
pub fn poisson_ratio(v: f64) -> Result<(), String> {
    (v.is_finite() && (0.0..0.5).contains(&v))
        .then_some(())
        .ok_or_else(|| format!("must be in [0, 0.5), got {}", bounded(v)))
}

/// A finite number `>= 0`.
pub fn non_negative(v: f64) -> Result<(), String> {
    (v.is_finite() && v >= 0.0)
        .then_some(())
        .ok_or_else(|| format!("must be a finite number >= 0, got {}", bounded(v)))
}

/// A finite number.
pub fn finite(v: f64) -> Result<(), String> {
    v.is_finite()
        .then_some(())
        .ok_or_else(|| format!("must be a finite number, got {}", bounded(v)))
}

/// A point with finite coordinates.
pub fn point(p: [f64; 2]) -> Result<(), String> {
    p.into_iter().try_for_each(finite)
}

/// `L / t0`, the upper limit itself for a quotient within rounding above it: 0.05 m over
/// 5e-8 m is 1e6 and one unit in the last place, and a beam of exactly the limit is allowed.
pub fn slenderness_of(length: f64, thickness: f64) -> f64 {
    let s = length / thickness;
    if s > MAX_SLENDERNESS && s <= MAX_SLENDERNESS * (1.0 + 4.0 * f64::EPSILON) {
        MAX_SLENDERNESS
    } else {
        s
    }
}

/// The thickness against the length: `1 <= L/t0 <= MAX_SLENDERNESS`.
pub fn slenderness(thickness: f64, length: f64) -> Result<(), String> {
    if thickness > length {
        return Err(format!(
            "a beam must be at least as long as it is thick (slenderness L/t0 >= 1), \
             got thickness {} > length {}",
            bounded(thickness),
            bounded(length)
        ));
    }
    let s = slenderness_of(length, thickness);
    if s > MAX_SLENDERNESS {
        return Err(format!(
            "slenderness L/t0 = {s:e} is beyond the {MAX_SLENDERNESS:e} prbfit models"
        ));
    }
    Ok(())
}

/// A path's step count, `1..=MAX_STEPS`, as the `u32` a path holds: the checked conversion
/// from what a file or an editor gives (any whole number).
pub fn steps(v: i64) -> Result<u32, String> {
    (1..=MAX_STEPS)
        .contains(&v)
        .then_some(v as u32)
        .ok_or_else(|| format!("must be a whole number from 1 to {MAX_STEPS}, got {v}"))
}

/// The cases over all of a scene's paths (each path's steps; `paths` names them: `paths`,
/// `drive paths`) against [`MAX_CASES`].
pub fn case_count(steps: impl Iterator<Item = u32>, paths: &str) -> Result<(), String> {
    let (mut n, mut count) = (0_u64, 0_usize);
    for s in steps {
        n += u64::from(s);
        count += 1;
    }
    (n <= MAX_CASES).then_some(()).ok_or_else(|| {
        format!("{n} load cases over {count} {paths} is more than the {MAX_CASES} a scene may have")
    })
}

/// The most natural frequencies a scene's fit may match (`[fit] modes`) or a command may ask
/// for (`--count`).
pub const MAX_MODES: i64 = 12;

/// `[fit] modes`: a whole number from 0 to [`MAX_MODES`], as the `u32` the settings hold.
pub fn modes(v: i64) -> Result<u32, String> {
    (0..=MAX_MODES)
        .contains(&v)
        .then_some(v as u32)
        .ok_or_else(|| format!("must be a whole number from 0 to {MAX_MODES}, got {v}"))
}

/// A load path's end load is not zero.
pub fn nonzero(end: &Load) -> Result<(), String> {
    (end.magnitude() != 0.0)
        .then_some(())
        .ok_or_else(|| "the load path is all zero: give alpha_x, alpha_y or beta".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_beam_of_exactly_the_slenderness_limit_is_allowed() {
        // 0.05 / 5e-8 rounds to one unit in the last place above 1e6.
        let (length, thickness) = (std::hint::black_box(0.05), 5e-8);
        assert!(length / thickness > MAX_SLENDERNESS);
        assert!(slenderness(thickness, length).is_ok());
        assert_eq!(slenderness_of(0.05, 5e-8), MAX_SLENDERNESS);
        assert!(slenderness(4.99e-8, 0.05).is_err());
    }

    #[test]
    fn rules_say_what_is_allowed() {
        assert!(positive(1e-9).is_ok() && positive(0.0).is_err());
        assert!(positive(f64::INFINITY).unwrap_err().contains("got inf"));
        assert!(poisson_ratio(0.0).is_ok() && poisson_ratio(0.5).is_err());
        assert!(non_negative(0.0).is_ok() && non_negative(-1.0).is_err());
        assert!(point([0.0, 1.0]).is_ok() && point([f64::NAN, 0.0]).is_err());
        assert_eq!(steps(10), Ok(10));
        assert_eq!(modes(0), Ok(0));
        assert!(modes(-1).unwrap_err().contains("from 0 to 12, got -1"));
        assert!(steps(0).unwrap_err().contains("from 1 to 10000, got 0"));
        assert!(steps(-3).unwrap_err().contains("got -3"));
        assert!(steps(i64::MAX).is_err());
        assert!(slenderness(2.0, 1.0)
            .unwrap_err()
            .contains("at least as long"));
        let e = case_count([10_000_u32; 11].into_iter(), "drive paths").unwrap_err();
        assert_eq!(
            e,
            "110000 load cases over 11 drive paths is more than the 100000 a scene may have"
        );
    }
}
