//! The commands whose reports the library builds ([`prbfit::report`]): each parses its flags
//! into the report's arguments, loads the scene, and prints the report as text or JSON. The
//! progress of a long run goes to a progress line on stderr (a terminal only).

use anyhow::Result;

use prbfit::cancel::CancelToken;
use prbfit::report::{self, Control, Progress};
use prbfit::scene::Scene;

use super::args::{
    CalibrateArgs, Common, EvalArgs, ExportArgs, FeaArgs, FitArgs, ModesArgs, SelectArgs, SolveArgs,
};
use super::load_scene;
use super::output::{self, emit};

/// Runs `report` on the scene of `common` with a progress line, and prints what it reports.
fn run<R: serde::Serialize + std::fmt::Display>(
    common: &Common,
    report: impl FnOnce(&Scene, &mut Control<'_>) -> report::Result<R>,
) -> Result<()> {
    run_on(&load_scene(common)?, common, Interrupt::Discard, report)
}

/// What a command does with its result when Ctrl-C stopped it.
#[derive(Clone, Copy, PartialEq)]
enum Interrupt {
    /// The result is cut short (cases missing, a selection half made): say only that the
    /// run was interrupted.
    Discard,
    /// The result is whole as far as it goes and says that it was stopped (a fit's best
    /// matrix so far, its figures its own, `stop: cancelled`): print it, then say so.
    Keep,
}

/// [`run`] on a scene already loaded. Ctrl-C cancels the run (see
/// [`output::cancel_on_interrupt`]); the command then exits with status 130.
fn run_on<R: serde::Serialize + std::fmt::Display>(
    scene: &Scene,
    common: &Common,
    interrupt: Interrupt,
    report: impl FnOnce(&Scene, &mut Control<'_>) -> report::Result<R>,
) -> Result<()> {
    let cancel = CancelToken::new();
    output::cancel_on_interrupt(&cancel);
    let mut line = output::ProgressLine::default();
    let out = {
        let mut progress = |p: &Progress<'_>| line.show(p);
        let mut ctl = Control {
            cancel: cancel.clone(),
            progress: &mut progress,
        };
        report(scene, &mut ctl)
    };
    // The progress line is erased before anything is printed.
    drop(line);
    if cancel.is_cancelled() {
        return Err(match (interrupt, out) {
            (Interrupt::Keep, Ok(out)) => {
                emit(&out, common.json)?;
                output::Interrupted(": the best so far is above")
            }
            _ => output::Interrupted(""),
        }
        .into());
    }
    emit(&out?, common.json)
}

/// Runs `prbfit solve`.
pub fn solve(args: SolveArgs) -> Result<()> {
    let a = report::solve::SolveArgs {
        load: args.load,
        effects: args.effects,
        slenderness: args.slenderness,
        nu: args.nu,
        kappa: args.kappa,
        tol: args.tol,
        shape: args.shape,
    };
    run(&args.common, |scene, ctl| {
        report::solve::solve(scene, &a, ctl)
    })
}

/// Runs `prbfit eval`.
pub fn eval(args: EvalArgs) -> Result<()> {
    let a = report::eval::EvalArgs {
        prb: args.prb,
        model: args.model,
        load: args.load,
        tol: args.tol,
    };
    run(&args.common, |scene, ctl| {
        report::eval::eval(scene, &a, ctl)
    })
}

/// Runs `prbfit modes`.
pub fn modes(args: ModesArgs) -> Result<()> {
    let a = report::modes::ModesArgs {
        prb: args.prb,
        model: args.model,
        count: args.count,
        load: args.load,
        cases: args.cases,
        tol: args.tol,
    };
    run(&args.common, |scene, ctl| {
        report::modes::modes(scene, &a, ctl)
    })
}

/// Runs `prbfit fit`.
pub fn fit(args: FitArgs) -> Result<()> {
    let a = report::fit::FitArgs {
        topology: args.topology,
        prb: args.prb,
        fidelity: args.fidelity,
        seed: args.seed,
        output: args.output,
        force: args.force,
    };
    run_on(
        &load_scene(&args.common)?,
        &args.common,
        Interrupt::Keep,
        |scene, ctl| report::fit::fit(scene, &a, ctl),
    )
}

/// Runs `prbfit select`.
pub fn select(args: SelectArgs) -> Result<()> {
    let a = report::select::SelectArgs {
        fidelity: args.fidelity,
        within_stroke: args.within_stroke,
    };
    run(&args.common, |scene, ctl| {
        report::select::select(scene, &a, ctl)
    })
}

/// Runs `prbfit calibrate`.
pub fn calibrate(args: CalibrateArgs) -> Result<()> {
    let a = report::calibrate::CalibrateArgs { param: args.param };
    // The parameter is checked before the scene is read.
    report::calibrate::param(&a)?;
    run(&args.common, |scene, ctl| {
        report::calibrate::calibrate_scene(scene, &a, ctl)
    })
}

/// Runs `prbfit export`.
pub fn export(args: ExportArgs) -> Result<()> {
    let a = report::export::ExportArgs {
        prb: args.prb,
        model: args.model,
        format: args.format,
        output: args.output,
        force: args.force,
        density: args.density,
        fidelity: args.fidelity,
    };
    // Refused before the scene is read and the baseline solved: no format, an existing file
    // without --force, a device, a dangling link.
    report::export::target(&a)?;
    run(&args.common, |scene, ctl| {
        report::export::export(scene, &a, ctl)
    })
}

/// Runs `prbfit fea`.
pub fn fea(args: FeaArgs) -> Result<()> {
    let a = report::fea::FeaArgs {
        output: args.output,
        mesh: args.mesh,
        section: args.section,
        taper: args.taper,
        deck: args.deck,
        force: args.force,
        timeout: args.timeout,
    };
    let scene = load_scene(&args.common)?;
    if scene.mechanism.is_none() {
        return run_on(&scene, &args.common, Interrupt::Discard, |scene, ctl| {
            report::fea::fea(scene, &a, ctl)
        });
    }
    // A mechanism: the report is printed even when a drive path stopped early (its cases
    // are in the CSV, marked), and the exit status then says it failed.
    let mut incomplete = None;
    run_on(&scene, &args.common, Interrupt::Discard, |scene, ctl| {
        let r = report::fea_mech::fea_mechanism(scene, &a, ctl)?;
        incomplete = r.incomplete();
        Ok(r)
    })?;
    match incomplete {
        Some(m) => Err(anyhow::anyhow!(m)),
        None => Ok(()),
    }
}
