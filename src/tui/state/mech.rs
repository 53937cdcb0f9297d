//! The mechanism panel (DESIGN §8): one row per editable value of a mechanism scene — each
//! flexure's root, angle, attachment and coupler end, the stage point, each drive's three
//! stage coordinates (prescribed or loaded) and its steps — and what the charts show of it
//! (the drive, the case, the force–stroke panel).
//!
//! Values are shown and typed in the mechanism's display units ([`MechUnits`]: mm under a
//! metre-long flexure 1, else m; degrees; N; N m); a bare number is in those units, a number
//! with a unit (`0.02 m`, `0.5 rad`, `3 mN`) in its own. A coordinate shows its file key:
//! `dx`, `dy`, `dphi` when prescribed, `Fx`, `Fy`, `Mz` when loaded.
//!
//! Edits never leave an invalid mechanism: each returns a new [`Mechanism`], which the app
//! checks by the scene's rules ([`checked`](super::checked): the rules the scene file's
//! reader applies) before taking it. Two edits carry what a designer would expect along, by the
//! scene's own edits: a coupler whose stage end sat on the stage point stays on it when the
//! stage point moves ([`Mechanism::with_stage_point`]), and a beam edit reaches every flexure
//! that does not override that value ([`Mechanism::rebased`]).

use crate::mech::MechCase;
use crate::scene::{rules, Attach, Coordinate, Mechanism, COORDINATE_KEYS};
use crate::si::MechUnits;

use super::super::units::trim_number;
use super::mech_text::{dist, parse_angle, parse_point, parse_value, point_text, value_text};
use super::step;

/// One editable value of a mechanism.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MechField {
    /// Flexure `i`'s clamp (m).
    Root(usize),
    /// Flexure `i`'s unloaded direction.
    Angle(usize),
    /// How flexure `i`'s tip meets the stage.
    Attach(usize),
    /// Flexure `i`'s coupler end on the stage (only for `link`).
    Coupler(usize),
    /// The stage point `P`.
    StagePoint,
    /// Drive `drive`'s stage coordinate `c` (0 x, 1 y, 2 phi).
    Coordinate {
        /// The drive (from 0).
        drive: usize,
        /// The coordinate.
        c: usize,
    },
    /// Drive `i`'s steps.
    Steps(usize),
}

/// The rows of the panel for `m`, in order.
pub fn fields(m: &Mechanism) -> Vec<MechField> {
    let mut out = Vec::new();
    for (i, f) in m.flexures.iter().enumerate() {
        out.extend([
            MechField::Root(i),
            MechField::Angle(i),
            MechField::Attach(i),
        ]);
        if matches!(f.attach, Attach::Link { .. }) {
            out.push(MechField::Coupler(i));
        }
    }
    out.push(MechField::StagePoint);
    for d in 0..m.drives.len() {
        out.extend((0..3).map(|c| MechField::Coordinate { drive: d, c }));
        out.push(MechField::Steps(d));
    }
    out
}

/// Names of the stage coordinates in the panel.
const AXES: [&str; 3] = ["x", "y", "phi"];

impl MechField {
    /// The group the row belongs to, as its first row names it: `flexure 1`, `stage`,
    /// `drive 2`.
    pub fn group(self) -> String {
        match self {
            MechField::Root(i) | MechField::Angle(i) | MechField::Attach(i) => {
                format!("flexure {}", i + 1)
            }
            MechField::Coupler(i) => format!("flexure {}", i + 1),
            MechField::StagePoint => "stage".into(),
            MechField::Coordinate { drive, .. } | MechField::Steps(drive) => {
                format!("drive {}", drive + 1)
            }
        }
    }

    /// The row's label.
    pub fn label(self) -> &'static str {
        match self {
            MechField::Root(_) => "root",
            MechField::Angle(_) => "angle",
            MechField::Attach(_) => "attach",
            MechField::Coupler(_) => "coupler",
            MechField::StagePoint => "point",
            MechField::Coordinate { c, .. } => AXES[c.min(2)],
            MechField::Steps(_) => "steps",
        }
    }

    /// The drive the row belongs to, if any.
    pub fn drive(self) -> Option<usize> {
        match self {
            MechField::Coordinate { drive, .. } | MechField::Steps(drive) => Some(drive),
            _ => None,
        }
    }

    /// The text the row shows.
    pub fn text(self, m: &Mechanism) -> String {
        let u = MechUnits::new(m);
        let flexure = |i: usize| m.flexures.get(i);
        match self {
            MechField::Root(i) => flexure(i).map_or_else(String::new, |f| point_text(f.root, &u)),
            MechField::Angle(i) => flexure(i).map_or_else(String::new, |f| {
                format!("{} deg", trim_number(f.angle.to_degrees(), 6))
            }),
            MechField::Attach(i) => flexure(i).map_or_else(String::new, |f| match f.attach {
                Attach::Link { to } => format!(
                    "link, coupler {} {}",
                    trim_number(dist(f.tip(), to) * u.per_metre, 4),
                    u.distance
                ),
                a => attach_name(&a).to_string(),
            }),
            MechField::Coupler(i) => match flexure(i).map(|f| f.attach) {
                Some(Attach::Link { to }) => point_text(to, &u),
                _ => String::new(),
            },
            MechField::StagePoint => point_text(m.stage_point, &u),
            MechField::Coordinate { drive, c } => match m.drives.get(drive) {
                Some(d) => {
                    let k = d.coordinates[c.min(2)];
                    format!("{} = {}", key_name(c, k), value_text(c, k, &u))
                }
                None => String::new(),
            },
            MechField::Steps(drive) => m
                .drives
                .get(drive)
                .map_or_else(String::new, |d| d.steps.to_string()),
        }
    }

    /// The text its editor starts with.
    pub fn edit_text(self, m: &Mechanism) -> String {
        let u = MechUnits::new(m);
        match self {
            MechField::Attach(i) => m
                .flexures
                .get(i)
                .map(|f| attach_name(&f.attach).to_string())
                .unwrap_or_default(),
            MechField::Coordinate { drive, c } => m
                .drives
                .get(drive)
                .map(|d| value_text(c, d.coordinates[c.min(2)], &u))
                .unwrap_or_default(),
            f => f.text(m),
        }
    }

    /// `m` with this row set from `text`; an error (and nothing changed) if the text is not
    /// a value of the row's kind. The whole scene is checked by the caller
    /// ([`checked`](super::checked)).
    pub fn edited(self, m: &Mechanism, text: &str) -> Result<Mechanism, String> {
        let u = MechUnits::new(m);
        let mut out = m.clone();
        let no_flexure = || "no such flexure".to_string();
        match self {
            MechField::Root(i) => {
                out.flexures.get_mut(i).ok_or_else(no_flexure)?.root =
                    parse_point(text, &u).map_err(|e| format!("root: {e}"))?;
            }
            MechField::Angle(i) => {
                out.flexures.get_mut(i).ok_or_else(no_flexure)?.angle =
                    parse_angle(text).map_err(|e| format!("angle: {e}"))?;
            }
            MechField::Attach(i) => {
                let attach = match text.trim() {
                    "clamped" => Attach::Clamped,
                    "pinned" => Attach::Pinned,
                    "link" => Attach::Link {
                        to: match m.flexures.get(i).map(|f| f.attach) {
                            Some(Attach::Link { to }) => to,
                            _ => m.stage_point,
                        },
                    },
                    other => {
                        return Err(format!(
                            "attach: expected clamped, pinned or link, got `{other}`"
                        ))
                    }
                };
                out.flexures.get_mut(i).ok_or_else(no_flexure)?.attach = attach;
            }
            MechField::Coupler(i) => {
                let f = out.flexures.get_mut(i).ok_or_else(no_flexure)?;
                if !matches!(f.attach, Attach::Link { .. }) {
                    return Err("only a flexure attached by a link has a coupler".into());
                }
                f.attach = Attach::Link {
                    to: parse_point(text, &u).map_err(|e| format!("coupler: {e}"))?,
                };
            }
            MechField::StagePoint => {
                let p = parse_point(text, &u).map_err(|e| format!("stage point: {e}"))?;
                out = m.with_stage_point(p);
            }
            MechField::Coordinate { drive, c } => {
                let d = out.drives.get_mut(drive).ok_or("no such drive")?;
                let c = c.min(2);
                let name = key_name(c, d.coordinates[c]);
                let v = parse_value(c, d.coordinates[c], text, &u)
                    .map_err(|e| format!("{name}: {e}"))?;
                d.coordinates[c] = match d.coordinates[c] {
                    Coordinate::Prescribed(_) => Coordinate::Prescribed(v),
                    Coordinate::Loaded(_) => Coordinate::Loaded(v),
                };
            }
            MechField::Steps(drive) => {
                let d = out.drives.get_mut(drive).ok_or("no such drive")?;
                let steps: i64 = text
                    .trim()
                    .parse()
                    .map_err(|_| format!("steps: `{}` is not a whole number", text.trim()))?;
                d.steps = rules::steps(steps).map_err(|m| format!("steps: {m}"))?;
            }
        }
        Ok(out)
    }
}

/// The choices `p` offers on a row, in the order it tries them: the other attachments
/// (clamped, pinned, link, round again), or the coordinate of the other kind. A prescribed
/// coordinate becomes the load that holds the exact mechanism where the drive took it (its
/// reaction at the drive's end), a loaded one the motion that load caused, so the drive's
/// end state `end` (the exact mechanism's last case of the drive) stays where it was; with no
/// exact solution yet, zero.
pub fn toggled(m: &Mechanism, field: MechField, end: Option<&MechCase>) -> Vec<Mechanism> {
    match field {
        MechField::Attach(i) => {
            let Some(f) = m.flexures.get(i) else {
                return Vec::new();
            };
            let order = ["clamped", "pinned", "link"];
            let now = order
                .iter()
                .position(|n| *n == attach_name(&f.attach))
                .unwrap_or(0);
            (1..order.len())
                .filter_map(|k| {
                    MechField::Attach(i)
                        .edited(m, order[(now + k) % order.len()])
                        .ok()
                })
                .collect()
        }
        MechField::Coordinate { drive, c } => {
            let c = c.min(2);
            let Some(d) = m.drives.get(drive) else {
                return Vec::new();
            };
            let (l, _) = m.scale();
            let u = MechUnits::new(m);
            let mut out = m.clone();
            out.drives[drive].coordinates[c] = match d.coordinates[c] {
                Coordinate::Prescribed(_) => {
                    Coordinate::Loaded(end.map_or(0.0, |e| e.stage_load[c] * u.load(c)))
                }
                Coordinate::Loaded(_) => Coordinate::Prescribed(end.map_or(0.0, |e| {
                    if c == 2 {
                        e.stage[c]
                    } else {
                        e.stage[c] * l
                    }
                })),
            };
            vec![out]
        }
        _ => Vec::new(),
    }
}

/// The mechanism panel's cursor and what the mechanism charts show.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MechState {
    /// The selected row, an index into [`fields`].
    pub row: usize,
    /// The drive the charts show (from 0).
    pub drive: usize,
    /// The case of that drive the shape chart shows (from 0); `None`: the last, the drive's
    /// end.
    pub case: Option<usize>,
    /// The force–stroke panel shown when the chart has room for only one.
    pub chart: usize,
}

impl MechState {
    /// Moves the cursor `dy` rows among `rows`.
    pub fn move_by(&mut self, dy: i32, rows: usize) {
        self.row = step(self.row, dy, rows);
    }

    /// The selected row of `m`.
    pub fn field(&self, m: &Mechanism) -> Option<MechField> {
        let f = fields(m);
        f.get(self.row.min(f.len().saturating_sub(1))).copied()
    }

    /// The shown drive, within `drives`.
    pub fn shown_drive(&self, drives: usize) -> usize {
        self.drive.min(drives.saturating_sub(1))
    }

    /// `[` and `]`: the previous or next drive, wrapping; the shape chart goes to its end.
    pub fn cycle_drive(&mut self, delta: i32, drives: usize) {
        let n = drives.max(1) as i64;
        self.drive = (self.shown_drive(drives) as i64 + delta as i64).rem_euclid(n) as usize;
        self.case = None;
        self.chart = 0;
    }

    /// The shown case of a drive with `cases` cases (none when it has none).
    pub fn shown_case(&self, cases: usize) -> Option<usize> {
        let last = cases.checked_sub(1)?;
        Some(self.case.map_or(last, |c| c.min(last)))
    }

    /// `<` and `>`: the previous or next case of the shown drive, wrapping.
    pub fn cycle_case(&mut self, delta: i32, cases: usize) {
        if let Some(now) = self.shown_case(cases) {
            let n = cases as i64;
            self.case = Some((now as i64 + delta as i64).rem_euclid(n) as usize);
        }
    }
}

/// `flexure.attach` as the scene file names it.
pub fn attach_name(a: &Attach) -> &'static str {
    match a {
        Attach::Clamped => "clamped",
        Attach::Pinned => "pinned",
        Attach::Link { .. } => "link",
    }
}

/// The file key of coordinate `c` of kind `k`, capitalised for loads: `dy`, `Fy`.
pub fn key_name(c: usize, k: Coordinate) -> String {
    let (disp, load) = COORDINATE_KEYS[c.min(2)];
    if k.is_prescribed() {
        disp.to_string()
    } else {
        let mut s = load.to_string();
        s.replace_range(..1, &load[..1].to_uppercase());
        s
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::scene::Scene;

    fn slider_crank() -> Scene {
        Scene::from_toml_str(
            include_str!("../../../assets/scenes/slider-crank.toml"),
            "slider-crank",
        )
        .unwrap()
    }

    #[test]
    fn rows_and_texts_of_the_slider_crank() {
        let s = slider_crank();
        let m = s.mechanism.as_ref().unwrap();
        let rows = fields(m);
        assert_eq!(rows.len(), 4 + 1 + 4, "{rows:?}");
        assert_eq!(MechField::Root(0).text(m), "0, 0 mm");
        assert_eq!(MechField::Attach(0).text(m), "link, coupler 25 mm");
        assert_eq!(MechField::Attach(0).edit_text(m), "link");
        assert_eq!(MechField::Coupler(0).text(m), "67.678, -17.678 mm");
        assert_eq!(
            MechField::Coordinate { drive: 0, c: 1 }.text(m),
            "dy = 15 mm"
        );
        assert_eq!(
            MechField::Coordinate { drive: 0, c: 2 }.text(m),
            "dphi = 0 deg"
        );
        assert_eq!(MechField::Steps(0).text(m), "10");
    }

    #[test]
    fn typed_values_take_the_display_units_unless_given_their_own() {
        let s = slider_crank();
        let m = s.mechanism.as_ref().unwrap();
        let dy = MechField::Coordinate { drive: 0, c: 1 };
        let e = dy.edited(m, "20").unwrap();
        assert_eq!(e.drives[0].coordinates[1], Coordinate::Prescribed(0.02));
        let e = dy.edited(m, "0.01 m").unwrap();
        assert_eq!(e.drives[0].coordinates[1], Coordinate::Prescribed(0.01));
        let e = MechField::Root(0).edited(m, "1, 2 cm").unwrap();
        assert!((e.flexures[0].root[0] - 0.01).abs() < 1e-15);
        assert!((e.flexures[0].root[1] - 0.02).abs() < 1e-15);
        let e = MechField::Angle(0).edited(m, "90").unwrap();
        assert!((e.flexures[0].angle - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        for (field, bad) in [
            (dy, "fast"),
            (MechField::Root(0), "3"),
            (MechField::Root(0), "1, 2, 3"),
            (MechField::Angle(0), "nan"),
            (MechField::Attach(0), "glued"),
            (MechField::Steps(0), "0"),
            (MechField::Steps(0), "2.5"),
        ] {
            assert!(field.edited(m, bad).is_err(), "{field:?} took {bad:?}");
        }
    }

    #[test]
    fn a_coupler_on_the_stage_point_follows_it() {
        let s = slider_crank();
        let m = s.mechanism.as_ref().unwrap();
        let e = MechField::StagePoint.edited(m, "70, -20").unwrap();
        assert_eq!(e.flexures[0].attach, Attach::Link { to: e.stage_point });
        assert!((e.stage_point[0] - 0.07).abs() < 1e-15);
    }

    #[test]
    fn toggling_a_coordinate_keeps_the_end_state_and_validation_catches_bad_ones() {
        let mut s = slider_crank();
        let m = s.mechanism.clone().unwrap();
        let dy = MechField::Coordinate { drive: 0, c: 1 };
        let toggled = toggled(&m, dy, None);
        assert_eq!(toggled[0].drives[0].coordinates[1], Coordinate::Loaded(0.0));
        // With every coordinate zero the drive goes nowhere: the file's rule refuses it.
        s.mechanism = Some(toggled[0].clone());
        let e = crate::tui::state::checked(&s).unwrap_err();
        assert!(e.contains("goes nowhere"), "{e}");
        // A coupler ending on the flexure's own tip has zero length.
        let mut bad = m.clone();
        bad.flexures[0].attach = Attach::Link {
            to: bad.flexures[0].tip(),
        };
        s.mechanism = Some(bad);
        assert!(crate::tui::state::checked(&s)
            .unwrap_err()
            .contains("zero length"));
    }

    /// A stage-point edit meets the scene file's rule: onto the flexure's tip (where the
    /// coupler, which ends on the stage point, would have no length) it is refused with the
    /// key and message the reader gives for that mechanism, without the line.
    #[test]
    fn a_stage_point_edit_meets_the_file_rule() {
        let mut s = slider_crank();
        let m = s.mechanism.clone().unwrap();
        s.mechanism = Some(MechField::StagePoint.edited(&m, "50, 0").unwrap());
        let ui = crate::tui::state::checked(&s).unwrap_err();
        let file = Scene::from_toml_str(&s.to_toml(), "s.toml").unwrap_err();
        assert!(file.line.is_some(), "{file}");
        assert_eq!(ui, format!("{}: {}", file.key.unwrap(), file.message));
        assert!(
            ui.starts_with("flexures[1].link_to: the coupler would have zero length"),
            "{ui}"
        );
    }

    #[test]
    fn a_beam_edit_reaches_the_flexures_that_do_not_override_it() {
        let s = slider_crank();
        let m = s.mechanism.as_ref().unwrap();
        let mut new = s.beam;
        new.length = 0.06;
        new.thickness = 0.0006;
        let r = m.rebased(&s.beam, &new);
        assert_eq!(r.flexures[0].beam.length, 0.06);
        assert_eq!(r.flexures[0].beam.thickness, 0.0006);
        // The slider is not flexure 1's tip: it stays.
        assert_eq!(r.stage_point, m.stage_point);
    }

    #[test]
    fn cases_and_drives_wrap() {
        let mut st = MechState::default();
        assert_eq!(st.shown_case(10), Some(9));
        st.cycle_case(1, 10);
        assert_eq!(st.shown_case(10), Some(0));
        st.cycle_case(-1, 10);
        assert_eq!(st.shown_case(10), Some(9));
        assert_eq!(st.shown_case(0), None);
        st.cycle_drive(1, 2);
        assert_eq!((st.drive, st.case), (1, None));
        st.cycle_drive(1, 2);
        assert_eq!(st.drive, 0);
    }
}
