//! What a mechanism scene's figure draws (DESIGN §8): the **force–stroke chart**. For each
//! drive path, one panel per output the drive produces:
//! - a *prescribed* stage coordinate carrying a reaction: the reaction the drive supplies
//!   (`stage_load`, in N for `dx`/`dy` and N m for `dphi`, through flexure 1's `E I0` and `L`
//!   as `eval` prints it) against the drive's stroke;
//! - a *loaded* stage coordinate that moves: the stage motion (`stage`, mm or m for `dx`/`dy`,
//!   degrees for `dphi`) against the drive's load.
//!
//! The abscissa is the drive's own input, exact because a drive varies proportionally from
//! rest: the case at fraction `f` sits at `f` times the end value. Reaction panels use the
//! prescribed displacement that varies (the stroke), motion panels the load that varies; each
//! falls back on the other, and on the fraction of the drive when nothing varies. Every curve
//! starts at the unloaded state (abscissa and ordinate 0), then has one point per case.
//!
//! The beam is the exact mechanism ([`crate::mech::exact`]); each model replaces every flexure
//! ([`crate::mech::prb`]). A model that cannot follow a drive is drawn as far as it got (the
//! cases before its critical point, re-solved on the truncated drive) or not at all
//! ([`crate::mech::MechError::Immobile`]), and is listed in [`Figure::unfollowed`].

use crate::beam::Resolution;
use crate::cancel::CancelToken;
use crate::mech::prb::{follow, Followed};
use crate::mech::MechCase;
use crate::scene::{Drive, Mechanism, Scene, COORDINATE_KEYS};
use crate::si::MechUnits;

use super::strokes::{ForceStrokeChart, Output, StrokePanel};
use super::{ChartKind, Figure, PlotError, PlotModel, Unfollowed, MODEL_RGB};

/// An output no larger than this part of `1 +` the largest of its kind over the drive's
/// beam cases (reactions and applied loads in `E I0 / L^2` units, the scale Newton's
/// residuals are measured in; motions in units of L and radians) is identically zero and gets
/// no panel: a coupler pinned at the stage point carries no moment there, whatever the drive.
/// Such an output is zero only to the solver's tolerance: Newton stops once each equation's
/// residual is within `tol (1 + |load|)`, which leaves the slider crank's pinned moment
/// reaction at 1.5e-9 at the default tolerance 1e-9 (`prbfit solve --scene
/// assets/scenes/slider-crank.toml`). A hundred times the default tolerance sits above that
/// (ten times at normal fidelity's 1e-8) and still draws a parasitic motion of a micro-radian
/// beside a stroke of 0.3 L.
const TRIVIAL: f64 = 1e-7;

/// A drive's abscissa: the input that varies (or the fraction), in display units.
#[derive(Debug, Clone)]
struct Abscissa {
    /// Display units at the drive's end (1 for the fraction).
    end: f64,
    /// Name and unit.
    label: String,
    /// The coordinate it is, and whether as its prescribed motion (else its load); `None`:
    /// the fraction.
    coordinate: Option<(usize, bool)>,
}

impl Abscissa {
    /// The input of `drive` that varies, of the kind `prescribed` asks for first, then the
    /// other kind, then the fraction. Of several, the largest translation (or force) wins:
    /// they vary in proportion, so any one orders the cases.
    fn of(drive: &Drive, index: usize, prescribed: bool, units: &MechUnits) -> Abscissa {
        let pick = |want: bool| {
            (0..3)
                .filter(|&c| {
                    let k = drive.coordinates[c];
                    k.is_prescribed() == want && k.value() != 0.0
                })
                .max_by(|&a, &b| {
                    // Translations (forces) before rotations (moments), then the larger.
                    let key = |c: usize| (c < 2, drive.coordinates[c].value().abs());
                    let (ka, kb) = (key(a), key(b));
                    ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
                })
        };
        let found = pick(prescribed)
            .map(|c| (c, prescribed))
            .or_else(|| pick(!prescribed).map(|c| (c, !prescribed)));
        match found {
            Some((c, is_prescribed)) => {
                let (disp, load) = COORDINATE_KEYS[c];
                let name = if is_prescribed {
                    format!("stroke {disp}")
                } else {
                    format!("load {}", capitalised(load))
                };
                Abscissa {
                    end: units.input(c, drive.coordinates[c]),
                    label: format!("{name} ({})", units.unit(c, is_prescribed)),
                    coordinate: Some((c, is_prescribed)),
                }
            }
            None => Abscissa {
                end: 1.0,
                label: format!("fraction of drive {index}"),
                coordinate: None,
            },
        }
    }

    /// Where `case` sits along it, in display units: the case's own input (its prescribed
    /// motion or its load, which a measured drive's rows need not space evenly), or its
    /// fraction.
    fn at(&self, case: &MechCase, units: &MechUnits) -> f64 {
        match self.coordinate {
            Some((c, true)) => units.motion(c, case.stage[c]),
            Some((c, false)) => case.stage_load[c] * units.load(c),
            None => case.fraction * self.end,
        }
    }
}

/// What a drive varies, in display units: "dy 15 mm, Fx 10 N" (its nonzero end values).
fn summary(drive: &Drive, units: &MechUnits) -> String {
    let parts: Vec<String> = drive
        .coordinates
        .iter()
        .enumerate()
        .filter(|(_, k)| k.value() != 0.0)
        .map(|(c, &k)| {
            let (disp, load) = COORDINATE_KEYS[c];
            let name = if k.is_prescribed() {
                disp.to_string()
            } else {
                capitalised(load)
            };
            format!(
                "{name} {} {}",
                crate::text::bounded_prec(units.input(c, k), 4),
                units.unit(c, k.is_prescribed())
            )
        })
        .collect();
    if parts.is_empty() {
        "at rest".to_string()
    } else {
        parts.join(", ")
    }
}

/// `fx` as `Fx`, for force names.
fn capitalised(s: &str) -> String {
    let mut chars = s.chars();
    match chars.next() {
        Some(first) => first.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}

/// The force–stroke figure of `models` on the mechanism of `scene`: the exact mechanism at
/// `resolution`, each model's PRB mechanism at `resolution.tol`. `kind` is
/// [`ChartKind::Force`] (reactions only), [`ChartKind::Motion`] (motions only) or
/// [`ChartKind::All`] (both); the others are for cantilever scenes.
pub fn figure(
    scene: &Scene,
    mechanism: &Mechanism,
    models: &[PlotModel],
    resolution: Resolution,
    kind: ChartKind,
) -> Result<Figure, PlotError> {
    // The truth: the exact mechanism, or a data scene's measured cases (DESIGN §9).
    let beam =
        crate::mech::measured::truth(scene, mechanism, resolution).map_err(PlotError::Exact)?;
    figure_from(scene, mechanism, &beam, models, resolution.tol, kind)
}

/// [`figure`] with the exact mechanism already solved (`beam`, one `Vec` per drive).
pub fn figure_from(
    scene: &Scene,
    mechanism: &Mechanism,
    beam: &[Vec<MechCase>],
    models: &[PlotModel],
    tol: f64,
    kind: ChartKind,
) -> Result<Figure, PlotError> {
    if !kind.has_force() && !kind.has_motion() {
        return Err(PlotError::KindNotForScene {
            kind,
            mechanism: true,
        });
    }
    if models.len() > MODEL_RGB.len() {
        return Err(PlotError::TooManyModels {
            max: MODEL_RGB.len(),
            got: models.len(),
        });
    }
    let followed: Vec<Followed> = models
        .iter()
        .map(|m| follow(mechanism, &m.matrix, tol, &CancelToken::new()))
        .collect();

    let mut unfollowed = Vec::new();
    for (m, f) in models.iter().zip(&followed) {
        for (i, (d, failure)) in mechanism.drives.iter().zip(&f.failures).enumerate() {
            if let Some(e) = failure {
                unfollowed.push(Unfollowed {
                    model: m.name.clone(),
                    path: i + 1,
                    reached: f.drives.get(i).map_or(0, Vec::len),
                    steps: d.steps.max(1) as usize,
                    reason: Some(e.to_string()),
                });
            }
        }
    }
    let legend = models
        .iter()
        .map(|m| {
            let stopped: Vec<String> = unfollowed
                .iter()
                .filter(|u| u.model == m.name)
                .map(|u| u.path.to_string())
                .collect();
            let none_reached = unfollowed
                .iter()
                .filter(|u| u.model == m.name)
                .all(|u| u.reached == 0);
            if stopped.is_empty() {
                m.name.clone()
            } else if stopped.len() == mechanism.drives.len() && none_reached {
                format!("{} (cannot follow)", m.name)
            } else {
                format!("{} (stops on drive {})", m.name, stopped.join(", "))
            }
        })
        .collect();

    let reached: Vec<&[Vec<MechCase>]> = followed.iter().map(|f| f.drives.as_slice()).collect();
    let panels = stroke_panels(mechanism, beam, &reached, kind);
    if panels.is_empty() {
        return Err(PlotError::NothingToDraw {
            kind,
            scene: scene.name.clone(),
        });
    }
    Ok(Figure {
        kind,
        title: scene.name.clone(),
        shapes: None,
        errors: None,
        force_stroke: Some(ForceStrokeChart {
            legend,
            panels,
            measured: scene.truth.is_some(),
        }),
        stress: None,
        unfollowed,
    })
}

/// The panels of the force–stroke chart: per drive, its reactions (when `kind` has force),
/// then its motions (when it has motion), each coordinate whose beam output is not
/// identically zero; `beam` is the exact mechanism's cases and `models` each model's, one
/// `Vec` per drive, as far as the model got. The UI draws these too.
pub fn stroke_panels(
    mechanism: &Mechanism,
    beam: &[Vec<MechCase>],
    models: &[&[Vec<MechCase>]],
    kind: ChartKind,
) -> Vec<StrokePanel> {
    let units = MechUnits::new(mechanism);
    let drive_count = mechanism.drives.len();
    let mut panels = Vec::new();
    for (i, d) in mechanism.drives.iter().enumerate() {
        let beam_cases = beam.get(i).map_or(&[][..], Vec::as_slice);
        for output in [Output::Reaction, Output::Motion] {
            let wanted = match output {
                Output::Reaction => kind.has_force(),
                Output::Motion => kind.has_motion(),
            };
            if !wanted {
                continue;
            }
            let prescribed = output == Output::Reaction;
            let x = Abscissa::of(d, i + 1, prescribed, &units);
            // The largest output of this kind over the drive's beam cases.
            let scale = beam_cases.iter().fold(0.0_f64, |m, case| {
                let values = match output {
                    Output::Reaction => case.stage_load,
                    Output::Motion => case.stage,
                };
                values.iter().fold(m, |m, v| m.max(v.abs()))
            });
            for (c, coordinate) in d.coordinates.iter().enumerate() {
                if coordinate.is_prescribed() != prescribed {
                    continue;
                }
                let value = |case: &MechCase| match output {
                    Output::Reaction => case.stage_load[c],
                    Output::Motion => case.stage[c],
                };
                if beam_cases
                    .iter()
                    .all(|case| value(case).abs() <= TRIVIAL * (1.0 + scale))
                {
                    continue;
                }
                let curve = |cases: &[MechCase]| -> Vec<[f64; 2]> {
                    if cases.is_empty() {
                        return Vec::new();
                    }
                    std::iter::once([0.0, 0.0])
                        .chain(cases.iter().map(|case| {
                            let y = match output {
                                Output::Reaction => value(case) * units.load(c),
                                Output::Motion => units.motion(c, value(case)),
                            };
                            [x.at(case, &units), y]
                        }))
                        .collect()
                };
                let (disp, load) = COORDINATE_KEYS[c];
                let (y_label, what) = match output {
                    Output::Reaction => (
                        format!("reaction {} ({})", capitalised(load), units.unit(c, false)),
                        format!("reaction {}", capitalised(load)),
                    ),
                    Output::Motion => (
                        format!("stage {disp} ({})", units.unit(c, true)),
                        format!("stage {disp}"),
                    ),
                };
                let against = x.label.split(" (").next().unwrap_or_default().to_string();
                panels.push(StrokePanel {
                    drive: i + 1,
                    coordinate: c,
                    output,
                    title: format!(
                        "drive {} of {drive_count} ({}): {what} against {against}",
                        i + 1,
                        summary(d, &units)
                    ),
                    x_label: x.label.clone(),
                    y_label,
                    beam: curve(beam_cases),
                    models: models
                        .iter()
                        .map(|m| curve(m.get(i).map_or(&[][..], Vec::as_slice)))
                        .collect(),
                });
            }
        }
    }
    panels
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mech::exact;

    /// A measured drive's rows need not be evenly spaced: each case is drawn at its own
    /// stroke (1, 4 and 5 mm here), not at its fraction of the end stroke.
    #[test]
    #[allow(clippy::unwrap_used)]
    fn cases_sit_at_their_own_stroke() {
        use crate::scene::{Coordinate::Prescribed, Drive};
        let scene = Scene::from_toml_str(
            include_str!("../../assets/scenes/slider-crank.toml"),
            "slider-crank.toml",
        )
        .unwrap();
        let mut m = scene.mechanism.unwrap();
        m.drives = vec![Drive {
            coordinates: [Prescribed(0.0), Prescribed(0.005), Prescribed(0.0)],
            steps: 3,
            rows: vec![[0.0, 0.001, 0.0], [0.0, 0.004, 0.0], [0.0, 0.005, 0.0]],
        }];
        let beam = exact::solve(&m, Resolution::default()).unwrap();
        let panels = stroke_panels(&m, &beam, &[], ChartKind::Force);
        assert!(!panels.is_empty());
        for p in &panels {
            let x: Vec<f64> = p.beam.iter().map(|q| q[0]).collect();
            for (got, want) in x.iter().zip([0.0, 1.0, 4.0, 5.0]) {
                assert!((got - want).abs() < 1e-9, "{x:?}");
            }
            assert_eq!(x.len(), 4);
        }
    }

    #[test]
    fn force_names_are_capitalised() {
        assert_eq!(capitalised("fx"), "Fx");
        assert_eq!(capitalised("mz"), "Mz");
        assert_eq!(capitalised(""), "");
    }
}
