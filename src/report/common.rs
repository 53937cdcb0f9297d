//! The lines and parts the reports share: numbers in bounded width, safe text, the effects
//! decision's line, a data scene's truth.

use std::fmt::{self, Display};

use serde::Serialize;

use crate::mech::figures::Figures;
use crate::study::{CaseForm, EffectsDecision, Study};

/// A number in bounded width: plain in `[1e-4, 1e6)`, else scientific; at most `sig`
/// significant digits. `1e300` prints as `1e300`, never as 301 digits.
pub fn num(x: f64) -> String {
    crate::text::bounded(x)
}

/// A stress in Pa as MPa with `decimals` decimals, in bounded width: plainly below 1e6 MPa,
/// else scientific to as many significant digits (an absurd modulus's stresses print as
/// `8.47547e21`, never as 22 digits and a point).
pub fn mpa(pa: f64, decimals: usize) -> String {
    fixed(pa / 1e6, decimals)
}

/// `v` with `decimals` decimals, in bounded width: plainly below 1e6 in magnitude, else
/// scientific to as many significant digits.
pub fn fixed(v: f64, decimals: usize) -> String {
    if v.abs() < 1e6 {
        format!("{v:.decimals$}")
    } else {
        crate::text::bounded_prec(v, decimals + 6)
    }
}

/// Text that came from a file (a scene's name), safe to print on a terminal.
pub fn safe(s: &str) -> std::borrow::Cow<'_, str> {
    crate::text::sanitize_terminal(s)
}

/// One line saying what `effects = "auto"` decided, when it was decided.
pub struct DecisionLine<'a>(pub &'a Option<EffectsDecision>);

impl Display for DecisionLine<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some(d) = self.0 else { return Ok(()) };
        let part = |kept: bool| {
            d.impacts
                .iter()
                .filter(|i| i.kept == kept)
                .map(|i| {
                    format!(
                        "{} ({:.1}% of target)",
                        i.effect,
                        i.fraction_of_target * 100.0
                    )
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        write!(
            f,
            "effects auto: kept [{}]; dropped [{}] (together {:.1}% of target; threshold {:.0}%)",
            part(true),
            part(false),
            d.dropped_together_fraction * 100.0,
            d.threshold * 100.0
        )?;
        match &d.plate {
            Some(p) => writeln!(
                f,
                "; section {} (mean plate fraction {:.2}, w0/t0 = {}, w0/L = {}, largest Searle w0^2/(R t0) = {})",
                if p.wide { "wide" } else { "narrow" },
                p.plate_fraction,
                num(p.width_over_thickness),
                num(p.width_over_length),
                num(p.largest_searle)
            ),
            None => writeln!(f),
        }
    }
}

/// The frequency target's lines (DESIGN §10) when the scene judges its first `modes`
/// natural frequencies (`[fit] modes`; nothing when 0): the target, then each model's largest
/// error over them about the unloaded equilibrium, or that it has fewer, and whether it meets
/// the target (the models' `targets` verdicts include it).
pub fn frequency_lines<'a>(
    f: &mut fmt::Formatter<'_>,
    modes: u32,
    target: f64,
    rows: impl IntoIterator<Item = (&'a str, &'a Figures)>,
) -> fmt::Result {
    if modes == 0 {
        return Ok(());
    }
    writeln!(
        f,
        "frequency target: max error {}% on the first {modes} natural frequencies (unloaded)",
        num(target * 100.0)
    )?;
    for (name, figures) in rows {
        let Some(e) = figures.max_freq_err else {
            continue;
        };
        let what = if e.is_finite() {
            format!("largest error {:.3}%", e * 100.0)
        } else {
            format!("fewer than {modes} frequencies")
        };
        writeln!(f, "  {}: {what}: {}", safe(name), met(e <= target))?;
    }
    Ok(())
}

/// "met" or "NOT met".
pub fn met(ok: bool) -> &'static str {
    if ok {
        "met"
    } else {
        "NOT met"
    }
}

/// A data scene's truth as the reports show it (DESIGN §9): the file, its hash, its size, and
/// the scene's own beam judged against it.
#[derive(Debug, Serialize)]
pub struct TruthInfo {
    /// The data file as the scene names it.
    data: String,
    /// SHA-256 of its bytes.
    sha256: String,
    /// Rows (load cases) and paths.
    rows: usize,
    paths: usize,
    /// The beam theory's own error against the data (the scene's nominal `[beam]`; a
    /// mechanism's exact beam mechanism along the measured drives).
    #[serde(skip_serializing_if = "Option::is_none")]
    beam_vs_data: Option<Figures>,
    /// Why the beam could not be judged, when it could not.
    #[serde(skip_serializing_if = "Option::is_none")]
    beam_failure: Option<String>,
    /// How the scene's cases read (the beam's line or the beam mechanism's).
    #[serde(skip)]
    form: CaseForm,
}

impl TruthInfo {
    /// The truth of `study`, if it is measured data, with the scene's own beam (beam
    /// mechanism) judged against it.
    pub fn of(study: &Study) -> Option<TruthInfo> {
        let scene = study.scene();
        let truth = scene.truth.as_ref()?;
        let (beam_vs_data, beam_failure) = match study.beam_against_data() {
            Some(Ok(f)) => (Some(f), None),
            Some(Err(e)) => (None, Some(e)),
            None => (None, None),
        };
        Some(TruthInfo {
            form: study.case_form(),
            data: truth.file.clone(),
            sha256: truth.sha256.clone(),
            rows: truth.row_count(),
            paths: truth
                .stage
                .as_ref()
                .map_or(truth.paths.len(), |s| s.paths.len()),
            beam_vs_data,
            beam_failure,
        })
    }
}

/// The line a report gives a data scene's truth (nothing for a beam scene).
pub struct TruthLine<'a>(pub &'a Option<TruthInfo>);

impl Display for TruthLine<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Some(t) = self.0 else { return Ok(()) };
        writeln!(
            f,
            "truth: measured data {} ({} rows in {} path(s), sha256 {}...)",
            safe(&t.data),
            t.rows,
            t.paths,
            t.sha256.get(..12).unwrap_or(&t.sha256)
        )?;
        match (&t.beam_vs_data, &t.beam_failure) {
            (Some(b), _) if t.form == CaseForm::Tip => writeln!(
                f,
                "the scene's beam against the data: rms pos {:.3e}, max pos {:.3e} L; rms ang \
                 {:.3e}, max ang {:.3e} rad; J {:.4e}",
                b.rms_pos_err, b.max_pos_err, b.rms_ang_err, b.max_ang_err, b.objective
            ),
            (Some(b), _) => writeln!(
                f,
                "the scene's beam mechanism against the data: max pos {:.3e} L, max ang {:.3e} \
                 rad, reaction rms {:.3e} max {:.3e}; J {:.4e}",
                b.max_pos_err,
                b.max_ang_err,
                b.rms_force_err.unwrap_or(0.0),
                b.max_force(),
                b.objective
            ),
            (None, Some(why)) => writeln!(f, "the scene's beam against the data: {}", safe(why)),
            (None, None) => Ok(()),
        }
    }
}
