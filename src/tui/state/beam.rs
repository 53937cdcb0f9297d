//! The beam panel: the beam's dimensions, material and effects, and the scene's accuracy
//! targets and angle weight, one field per row; a mechanism scene adds its reaction target
//! and force weight (DESIGN §8).

use crate::beam::Effects;
use crate::scene::{EffectsChoice, Scene};

use super::super::units::{format_quantity, parse_over, trim_number, Quantity};
use super::step;

/// The rows of the beam panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BeamField {
    /// Beam length (m).
    Length,
    /// Cross-section width (m).
    Width,
    /// Cross-section thickness (m).
    Thickness,
    /// Young's modulus (Pa).
    YoungsModulus,
    /// Poisson's ratio.
    PoissonRatio,
    /// Timoshenko shear coefficient, or `auto` from the section.
    ShearCoefficient,
    /// Which of shear, extension and Poisson the beam solves, or `auto`.
    Effects,
    /// The scene's tip position target (fraction of L).
    MaxPosErr,
    /// The scene's tip angle target (rad).
    MaxAngErr,
    /// The fit's angle weight.
    AngleWeight,
    /// A mechanism scene's reaction target (fraction of each coordinate's largest).
    MaxForceErr,
    /// A mechanism scene's force weight in the fit.
    ForceWeight,
}

impl BeamField {
    /// Every field, in display order.
    pub const ALL: [BeamField; 10] = [
        BeamField::Length,
        BeamField::Width,
        BeamField::Thickness,
        BeamField::YoungsModulus,
        BeamField::PoissonRatio,
        BeamField::ShearCoefficient,
        BeamField::Effects,
        BeamField::MaxPosErr,
        BeamField::MaxAngErr,
        BeamField::AngleWeight,
    ];

    /// A mechanism scene's fields: the cantilever's and the reaction target and weight.
    pub const MECHANISM: [BeamField; 12] = [
        BeamField::Length,
        BeamField::Width,
        BeamField::Thickness,
        BeamField::YoungsModulus,
        BeamField::PoissonRatio,
        BeamField::ShearCoefficient,
        BeamField::Effects,
        BeamField::MaxPosErr,
        BeamField::MaxAngErr,
        BeamField::MaxForceErr,
        BeamField::AngleWeight,
        BeamField::ForceWeight,
    ];

    /// The fields of a scene (a mechanism scene when `mechanism`), in display order.
    pub fn of(mechanism: bool) -> &'static [BeamField] {
        if mechanism {
            &BeamField::MECHANISM
        } else {
            &BeamField::ALL
        }
    }

    /// The row's label.
    pub fn label(self) -> &'static str {
        match self {
            BeamField::Length => "length",
            BeamField::Width => "width",
            BeamField::Thickness => "thickness",
            BeamField::YoungsModulus => "E",
            BeamField::PoissonRatio => "nu",
            BeamField::ShearCoefficient => "kappa",
            BeamField::Effects => "effects",
            BeamField::MaxPosErr => "pos target",
            BeamField::MaxAngErr => "ang target",
            BeamField::AngleWeight => "ang weight",
            BeamField::MaxForceErr => "force tgt",
            BeamField::ForceWeight => "frc weight",
        }
    }

    fn quantity(self) -> Quantity {
        match self {
            BeamField::Length | BeamField::Width | BeamField::Thickness => Quantity::Length,
            BeamField::YoungsModulus => Quantity::Pressure,
            // As shown: `0.01 L (1%)`, `0.05 (5% of max)`, `0.02 rad (1.146 deg)`.
            BeamField::MaxPosErr | BeamField::MaxForceErr => Quantity::Fraction,
            BeamField::MaxAngErr => Quantity::Angle,
            _ => Quantity::Plain,
        }
    }

    /// The text the field shows. `decided` is what `auto` effects were decided as, once
    /// they were.
    pub fn text(self, scene: &Scene, decided: Option<Effects>) -> String {
        let b = &scene.beam;
        match self {
            BeamField::Length => format_quantity(b.length, Quantity::Length),
            BeamField::Width => format_quantity(b.width, Quantity::Length),
            BeamField::Thickness => format_quantity(b.thickness, Quantity::Length),
            BeamField::YoungsModulus => format_quantity(b.youngs_modulus, Quantity::Pressure),
            BeamField::PoissonRatio => trim_number(b.poisson_ratio, 6),
            BeamField::ShearCoefficient => match b.shear_coefficient {
                Some(k) => trim_number(k, 6),
                None => format!("auto ({})", trim_number(b.kappa(), 4)),
            },
            BeamField::Effects => match b.effects {
                EffectsChoice::Auto => match decided {
                    Some(e) => format!("auto ({e})"),
                    None => "auto (deciding...)".into(),
                },
                EffectsChoice::Fixed(e) => e.to_string(),
            },
            BeamField::MaxPosErr => format!(
                "{} L ({}%)",
                trim_number(scene.accuracy.max_pos_err, 6),
                trim_number(scene.accuracy.max_pos_err * 100.0, 4)
            ),
            BeamField::MaxAngErr => format!(
                "{} rad ({} deg)",
                trim_number(scene.accuracy.max_ang_err, 6),
                trim_number(scene.accuracy.max_ang_err.to_degrees(), 4)
            ),
            BeamField::AngleWeight => trim_number(scene.fit.angle_weight, 6),
            BeamField::MaxForceErr => format!(
                "{} ({}% of max)",
                trim_number(scene.accuracy.max_force_err, 6),
                trim_number(scene.accuracy.max_force_err * 100.0, 4)
            ),
            BeamField::ForceWeight => trim_number(scene.fit.force_weight, 6),
        }
    }

    /// The text its editor starts with (what the file would say, without decorations).
    pub fn edit_text(self, scene: &Scene) -> String {
        match self {
            BeamField::ShearCoefficient if scene.beam.shear_coefficient.is_none() => "auto".into(),
            BeamField::Effects => scene.beam.effects.to_string(),
            BeamField::MaxPosErr => trim_number(scene.accuracy.max_pos_err, 6),
            BeamField::MaxAngErr => trim_number(scene.accuracy.max_ang_err, 6),
            BeamField::MaxForceErr => trim_number(scene.accuracy.max_force_err, 6),
            _ => self.text(scene, None),
        }
    }

    /// `scene` with this field set from `text`, not yet validated as a whole (the app does
    /// that); an error if the text is not a value of the field's kind.
    pub fn edited(self, scene: &Scene, text: &str) -> Result<Scene, String> {
        let mut scene = scene.clone();
        let b = &mut scene.beam;
        match self {
            BeamField::ShearCoefficient if text.trim() == "auto" => b.shear_coefficient = None,
            BeamField::Effects => {
                b.effects = match text.trim() {
                    "auto" => EffectsChoice::Auto,
                    other => {
                        EffectsChoice::Fixed(Effects::parse_list(other).map_err(|e| e.to_string())?)
                    }
                }
            }
            f => {
                let present = match f {
                    BeamField::Length => b.length,
                    BeamField::Width => b.width,
                    BeamField::Thickness => b.thickness,
                    BeamField::YoungsModulus => b.youngs_modulus,
                    _ => 0.0,
                };
                let v = parse_over(text, f.quantity(), present)?;
                match f {
                    BeamField::Length => b.length = v,
                    BeamField::Width => b.width = v,
                    BeamField::Thickness => b.thickness = v,
                    BeamField::YoungsModulus => b.youngs_modulus = v,
                    BeamField::PoissonRatio => b.poisson_ratio = v,
                    BeamField::ShearCoefficient => b.shear_coefficient = Some(v),
                    BeamField::MaxPosErr => scene.accuracy.max_pos_err = v,
                    BeamField::MaxAngErr => scene.accuracy.max_ang_err = v,
                    BeamField::AngleWeight => scene.fit.angle_weight = v,
                    BeamField::MaxForceErr => scene.accuracy.max_force_err = v,
                    BeamField::ForceWeight => scene.fit.force_weight = v,
                    // Parsed as a list above.
                    BeamField::Effects => {}
                }
            }
        }
        Ok(scene)
    }
}

/// The beam panel's cursor.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BeamState {
    /// The selected row, an index into [`BeamField::of`] the scene.
    pub row: usize,
}

impl BeamState {
    /// The selected field (of a mechanism scene's fields when `mechanism`).
    pub fn field(&self, mechanism: bool) -> BeamField {
        let fields = BeamField::of(mechanism);
        fields[self.row.min(fields.len() - 1)]
    }

    /// Moves the cursor `dy` rows (among a mechanism scene's fields when `mechanism`).
    pub fn move_by(&mut self, dy: i32, mechanism: bool) {
        self.row = step(self.row, dy, BeamField::of(mechanism).len());
    }
}

/// The effects after `1`, `2`, `3` or `4` switched shear, extension, Poisson or plane strain,
/// starting from what the beam uses now (`auto` as `decided`, when known). Poisson needs
/// extension, so they move together where they must.
pub fn toggled_effect(scene: &Scene, decided: Option<Effects>, which: char) -> Effects {
    let mut e = match (scene.beam.effects, decided) {
        (EffectsChoice::Auto, Some(e)) => e,
        (choice, _) => choice.resolve(),
    };
    match which {
        '1' => e.shear = !e.shear,
        '2' => {
            e.extension = !e.extension;
            e.poisson &= e.extension;
        }
        '4' => e.plane_strain = !e.plane_strain,
        _ => {
            e.poisson = !e.poisson;
            e.extension |= e.poisson;
        }
    }
    e
}
