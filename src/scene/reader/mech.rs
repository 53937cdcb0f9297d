//! The mechanism tables of a scene file (DESIGN §8): `[[flexures]]`, `[stage]` and
//! `[[drives]]` as written, turned into a [`Mechanism`] with the file's defaults filled in.
//!
//! What only the file can get wrong is refused here, at its line: an `attach` that is no
//! attachment, a `link_to` on a flexure that has no coupler, a coordinate given both a
//! displacement and a load, a step count that is not one, `[[drives]]` in a data scene. The
//! mechanism's rules ([`Mechanism::validate`]) are checked with the whole scene's.

use std::ops::Range;

use serde::{de, Deserialize, Deserializer};
use toml::Spanned;

use super::super::beam::BeamSpec;
use super::super::drive::{Coordinate, Drive, COORDINATE_KEYS};
use super::super::error::SceneError;
use super::super::mechanism::{Attach, Flexure, Mechanism};
use super::spans::Spans;

/// A point `[x, y]`: exactly two numbers. (serde reads a fixed-size array as its first
/// elements and drops the rest: `root = [0, 0.015, 5]` was read as `[0, 0.015]`.)
#[derive(Debug, Clone, Copy)]
pub(super) struct Pair([f64; 2]);

impl<'de> Deserialize<'de> for Pair {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let v = Vec::<f64>::deserialize(deserializer)?;
        <[f64; 2]>::try_from(v.as_slice())
            .map(Pair)
            .map_err(|_| de::Error::invalid_length(v.len(), &"an array of length 2, [x, y]"))
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFlexure {
    root: Option<Spanned<Pair>>,
    angle_deg: Option<Spanned<f64>>,
    attach: Option<Spanned<String>>,
    link_to: Option<Spanned<Pair>>,
    length: Option<Spanned<f64>>,
    width: Option<Spanned<f64>>,
    thickness: Option<Spanned<f64>>,
    youngs_modulus: Option<Spanned<f64>>,
    poisson_ratio: Option<Spanned<f64>>,
    allowable_stress: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawStage {
    point: Option<Spanned<Pair>>,
    /// The stage's mass and inertia (DESIGN §10), read with the scene's body.
    pub(super) mass: Option<Spanned<f64>>,
    pub(super) inertia: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDrive {
    dx: Option<Spanned<f64>>,
    dy: Option<Spanned<f64>>,
    dphi: Option<Spanned<f64>>,
    fx: Option<Spanned<f64>>,
    fy: Option<Spanned<f64>>,
    mz: Option<Spanned<f64>>,
    steps: Option<Spanned<i64>>,
}

/// The mechanism of a scene with `[[flexures]]`; `beam` is the scene's `[beam]`, `data`
/// whether the scene's truth is a data file (whose rows are the drive paths).
pub(super) fn mechanism(
    spans: &mut Spans<'_>,
    beam: &BeamSpec,
    flexures: &[Spanned<RawFlexure>],
    stage: Option<&Spanned<RawStage>>,
    drives: &[Spanned<RawDrive>],
    data: bool,
) -> Result<Mechanism, SceneError> {
    let mut out = Vec::with_capacity(flexures.len());
    for (i, raw) in flexures.iter().enumerate() {
        out.push(flexure(spans, beam, raw, i + 1)?);
    }
    let stage_point = match stage.and_then(|s| s.get_ref().point.as_ref()) {
        Some(p) => spans.take("stage.point", p).0,
        None => out.first().map_or([0.0, 0.0], Flexure::tip),
    };
    // A coupler's stage end defaults to the stage point.
    for (f, raw) in out.iter_mut().zip(flexures) {
        if let (Attach::Link { to }, None) = (&mut f.attach, &raw.get_ref().link_to) {
            *to = stage_point;
        }
    }
    if let (true, Some(first)) = (data, drives.first()) {
        return Err(spans.error(
            first.span(),
            "drives",
            "a data scene's drive paths are its data file's rows (DESIGN §9: the [[drives]] \
             names as input columns): remove the [[drives]] tables"
                .into(),
        ));
    }
    if let Some(first) = drives.first() {
        spans.record("drives", first.span());
    }
    let mut paths = Vec::with_capacity(drives.len());
    for (i, d) in drives.iter().enumerate() {
        paths.push(drive(spans, d, i + 1)?);
    }
    Ok(Mechanism {
        flexures: out,
        stage_point,
        drives: paths,
    })
}

/// A flexure's optional override of one beam value: the raw value, its key, where it goes.
type Override<'a> = (&'a Option<Spanned<f64>>, &'static str, &'a mut f64);

fn flexure(
    spans: &mut Spans<'_>,
    beam: &BeamSpec,
    spanned: &Spanned<RawFlexure>,
    index: usize,
) -> Result<Flexure, SceneError> {
    let key = |field: &str| format!("flexures[{index}].{field}");
    spans.record(format!("flexures[{index}]"), spanned.span());
    let raw = spanned.get_ref();
    let root = raw
        .root
        .as_ref()
        .map_or([0.0, 0.0], |p| spans.take(key("root"), p).0);
    let angle = raw
        .angle_deg
        .as_ref()
        .map_or(0.0, |a| spans.take(key("angle_deg"), a).to_radians());
    let mut b = *beam;
    let fields: [Override<'_>; 5] = [
        (&raw.length, "length", &mut b.length),
        (&raw.width, "width", &mut b.width),
        (&raw.thickness, "thickness", &mut b.thickness),
        (&raw.youngs_modulus, "youngs_modulus", &mut b.youngs_modulus),
        (&raw.poisson_ratio, "poisson_ratio", &mut b.poisson_ratio),
    ];
    for (value, field, slot) in fields {
        if let Some(v) = value {
            *slot = spans.take(key(field), v);
        }
    }
    if let Some(s) = &raw.allowable_stress {
        b.allowable_stress = Some(spans.take(key("allowable_stress"), s));
    }
    // The slenderness rule names the thickness: without an override of it, the length's line.
    if let Some(l) = &raw.length {
        spans.record(key("thickness"), l.span());
    }
    let attach = match raw
        .attach
        .as_ref()
        .map(|a| (a.get_ref().as_str(), a.span()))
    {
        None | Some(("clamped", _)) => Attach::Clamped,
        Some(("pinned", _)) => Attach::Pinned,
        // The coupler's stage end defaults to the stage point, filled in by the caller.
        Some(("link", _)) => Attach::Link { to: [0.0, 0.0] },
        Some((other, span)) => {
            return Err(spans.error(
                span,
                &key("attach"),
                format!("expected \"clamped\", \"pinned\" or \"link\", got \"{other}\""),
            ))
        }
    };
    let attach = match (attach, &raw.link_to) {
        (Attach::Link { .. }, Some(to)) => Attach::Link {
            to: spans.take(key("link_to"), to).0,
        },
        (_, Some(to)) => {
            return Err(spans.error(
                to.span(),
                &key("link_to"),
                "a coupler end is only for attach = \"link\"".into(),
            ))
        }
        (attach, None) => attach,
    };
    Ok(Flexure {
        root,
        angle,
        attach,
        beam: b,
    })
}

fn drive(
    spans: &mut Spans<'_>,
    spanned: &Spanned<RawDrive>,
    index: usize,
) -> Result<Drive, SceneError> {
    let key = |field: &str| format!("drives[{index}].{field}");
    spans.record(format!("drives[{index}]"), spanned.span());
    let r = spanned.get_ref();
    let pairs = [(&r.dx, &r.fx), (&r.dy, &r.fy), (&r.dphi, &r.mz)];
    let mut coordinates = [Coordinate::Loaded(0.0); 3];
    for (slot, ((disp, load), (dk, lk))) in coordinates
        .iter_mut()
        .zip(pairs.into_iter().zip(COORDINATE_KEYS))
    {
        *slot = match (disp, load) {
            (Some(d), Some(l)) => {
                let span: Range<usize> =
                    d.span().start.min(l.span().start)..d.span().end.max(l.span().end);
                return Err(spans.error(
                    span,
                    &key(dk),
                    format!(
                        "give either a displacement ({dk}) or a load ({lk}) for this \
                         coordinate, not both"
                    ),
                ));
            }
            (Some(d), None) => Coordinate::Prescribed(spans.take(key(dk), d)),
            (None, Some(l)) => Coordinate::Loaded(spans.take(key(lk), l)),
            (None, None) => Coordinate::Loaded(0.0),
        };
    }
    let steps = spans.steps(&r.steps, &key("steps"))?;
    Ok(Drive::proportional(coordinates, steps))
}
