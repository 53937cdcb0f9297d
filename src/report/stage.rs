//! The stage form of the reports (DESIGN §8): how a mechanism's cases read in text, with
//! flexure 1's units in SI, each drive's prescribed and loaded coordinates named, reactions
//! starred.

use serde::Serialize;

use crate::scene::{Drive, Mechanism, Scene, COORDINATE_KEYS};
use crate::si::MechUnits;

use super::{num, safe, ReportError};

/// Names of the stage coordinates' loads in the text tables, with their SI unit.
pub(super) const LOAD_NAMES: [&str; 3] = ["Fx N", "Fy N", "Mz N m"];

/// Flexure 1's scale, for the text form: lengths and loads in SI.
/// The line that says which units flexure 1 sets.
pub(super) fn units_line(units: &MechUnits) -> String {
    format!(
        "flexure 1 sets the units: L = {} {}; alpha = 1 is E I0/L^2 = {} N, beta = 1 is \
         E I0/L = {} N m\n",
        num(units.length * units.per_metre),
        units.distance,
        num(units.force),
        num(units.moment)
    )
}

/// `n` things, plural when not one.
pub(super) fn count(n: usize, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

/// `x` for a column printed with `decimals` digits: a value that rounds to zero there (a
/// reaction zero in exact arithmetic, met to the solver's tolerance) prints as `0`, not
/// `-0.0000`.
pub(super) fn tidy(x: f64, decimals: i32) -> f64 {
    if x.abs() < 0.5 * 10f64.powi(-decimals) {
        0.0
    } else {
        x
    }
}

/// A drive path as the reports describe it.
#[derive(Debug, Clone, Serialize)]
pub struct DriveInfo {
    /// From 1.
    pub(super) drive: usize,
    /// Per stage coordinate `[x, y, phi]`: prescribed (the output is the reaction) or loaded.
    pub(super) prescribed: [bool; 3],
    /// Cases along the path.
    steps: u32,
}

impl DriveInfo {
    pub(super) fn all(mechanism: &Mechanism) -> Vec<DriveInfo> {
        mechanism
            .drives
            .iter()
            .enumerate()
            .map(|(i, d)| DriveInfo {
                drive: i + 1,
                prescribed: d.coordinates.map(|c| c.is_prescribed()),
                steps: d.steps,
            })
            .collect()
    }
}

/// One line naming what a drive prescribes and what it loads, in SI.
pub(super) fn drive_line(drive: usize, d: &Drive, units: &MechUnits) -> String {
    let (dist, factor) = (units.distance, units.per_metre);
    let mut prescribed = Vec::new();
    let mut loaded = Vec::new();
    for (c, (coordinate, (disp, load))) in d.coordinates.iter().zip(COORDINATE_KEYS).enumerate() {
        let v = coordinate.value();
        if coordinate.is_prescribed() {
            prescribed.push(if c == 2 {
                format!("{disp} -> {} deg", num(v.to_degrees()))
            } else {
                format!("{disp} -> {} {dist}", num(v * factor))
            });
        } else {
            let unit = if c == 2 { "N m" } else { "N" };
            loaded.push(format!("{load} -> {} {unit}", num(v)));
        }
    }
    let list = |v: Vec<String>| {
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    };
    let steps = if d.rows.is_empty() {
        format!("{} steps", d.steps)
    } else {
        format!("{} measured rows to", d.rows.len())
    };
    format!(
        "drive {drive}, {steps}: prescribed {}; loaded {} (* = a reaction the drive supplies)",
        list(prescribed),
        list(loaded)
    )
}

/// A flag of the single beam given with a mechanism scene: bad input naming the flag.
pub(super) fn refuse_flag(flag: &str, scene: &Scene, why: &str) -> ReportError {
    ReportError::input(format!(
        "{flag}: \"{}\" is a mechanism scene, and {why}",
        safe(&scene.name)
    ))
}

/// The loads of a mechanism are its drives.
pub(super) const LOADS_ARE_DRIVES: &str =
    "a mechanism's loads are its [[drives]] (edit them in the scene)";
