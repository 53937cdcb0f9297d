//! The PRB model's own stress estimate beside the truth's (DESIGN §11): per flexure, the
//! largest fibre stress over the cases of each, and the estimate's error.
//!
//! The model's estimate is its largest joint or root moment's fibre stress
//! ([`crate::prb::PrbSolver::max_stress`]: the beam's section, Poisson's shrink as the beam's
//! stress has it); the truth's is the beam's (or beam mechanism's) largest along each
//! flexure. The error of a case is `sigma_PRB - sigma_beam` as a fraction of the beam's
//! largest over the scene (so a case near rest, where both are small, is not blown up);
//! `max_stress_err` is its largest magnitude. Measured data has no stress, so a data scene
//! has no such figures.

use std::fmt;

use serde::Serialize;

use crate::mech::figures::JudgedCase;

use super::super::mpa;

/// One flexure's stress figures of a model over the scene (Pa).
#[derive(Debug, Clone, Serialize)]
pub struct StressFigures {
    /// From 1.
    pub flexure: usize,
    /// The PRB model's largest estimate over the cases, Pa.
    pub prb_max_stress: f64,
    /// Where it is, `s / L` along the unloaded chain.
    pub prb_max_stress_at: f64,
    /// The truth's largest over the cases, Pa.
    pub beam_max_stress: f64,
    /// Where it is, `s / L`.
    pub beam_max_stress_at: f64,
    /// The largest `|sigma_PRB - sigma_beam|` of a case, as a fraction of
    /// `beam_max_stress`.
    pub max_stress_err: f64,
}

/// The figures per flexure over `cases`, each flexure's stress in units of its Young's
/// modulus `youngs[i]`; `None` when the truth has no stress (measured data) or the model
/// gave none.
pub fn figures(cases: &[JudgedCase], youngs: &[f64]) -> Option<Vec<StressFigures>> {
    let mut out = Vec::with_capacity(youngs.len());
    for (i, &e) in youngs.iter().enumerate() {
        let mut pairs = Vec::with_capacity(cases.len());
        for c in cases {
            let truth = c.truth.flexures.get(i)?.stress?;
            let model = c.model.flexures.get(i)?.stress?;
            pairs.push((model, truth));
        }
        let (mut prb, mut beam) = pairs.first().copied()?;
        for &(m, t) in &pairs {
            if m.max > prb.max {
                prb = m;
            }
            if t.max > beam.max {
                beam = t;
            }
        }
        let err = pairs
            .iter()
            .map(|(m, t)| (m.max - t.max).abs())
            .fold(0.0, f64::max);
        out.push(StressFigures {
            flexure: i + 1,
            prb_max_stress: prb.max * e,
            prb_max_stress_at: prb.at,
            beam_max_stress: beam.max * e,
            beam_max_stress_at: beam.at,
            // No stress anywhere (every case at rest): no error to scale.
            max_stress_err: if beam.max > 0.0 { err / beam.max } else { 0.0 },
        });
    }
    Some(out)
}

/// The text lines of a model's stress figures: one per flexure (`flexure` named when the
/// scene has several), or the reason there are none.
pub struct StressLines<'a> {
    /// The model's name.
    pub model: &'a str,
    /// Its figures; `None`: a data scene's, which has no stress.
    pub figures: Option<&'a [StressFigures]>,
    /// Whether the scene is a mechanism (name each flexure).
    pub mechanism: bool,
}

impl fmt::Display for StressLines<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some(figures) = self.figures else {
            return Ok(());
        };
        for s in figures {
            let which = if self.mechanism {
                format!(" flexure {}", s.flexure)
            } else {
                String::new()
            };
            writeln!(
                f,
                "{}{which} stress: PRB {} MPa at s/L {:.3}, beam {} MPa at s/L {:.3} \
                 (largest over the cases); max error {:.2e} of the beam's largest",
                self.model,
                mpa(s.prb_max_stress, 1),
                s.prb_max_stress_at,
                mpa(s.beam_max_stress, 1),
                s.beam_max_stress_at,
                s.max_stress_err
            )?;
        }
        Ok(())
    }
}
