//! `prbfit tradeoff`: time against error along each knob, measured.

use std::fmt;

use anyhow::Result;
use serde::Serialize;

use prbfit::fit::CancelToken;
use prbfit::prb::PrbMatrix;
use prbfit::study::tradeoff::{measure, Knob};
use prbfit::study::EffectsDecision;

use super::args::TradeoffArgs;
use prbfit::report::{safe, DecisionLine};

use super::output::emit;
use super::{bad, resolved_scene};

/// The measured tables.
#[derive(Debug, Serialize)]
pub struct TradeoffOutput {
    scene: String,
    topology: String,
    effects_decision: Option<EffectsDecision>,
    knobs: Vec<Knob>,
}

impl fmt::Display for TradeoffOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "scene: {}; fitted topology for the fit knobs: {}",
            safe(&self.scene),
            self.topology
        )?;
        write!(f, "{}", DecisionLine(&self.effects_decision))?;
        for k in &self.knobs {
            writeln!(
                f,
                "\n{}: time = {}; error = {}",
                k.knob, k.time_of, k.error_of
            )?;
            for r in &k.rows {
                let time = if r.seconds < 1e-3 {
                    format!("{:.2} us", r.seconds * 1e6)
                } else {
                    format!("{:.1} ms", r.seconds * 1e3)
                };
                writeln!(f, "  {:<28} {:>12} {:>12.3e}", r.setting, time, r.error)?;
            }
        }
        Ok(())
    }
}

/// Runs `prbfit tradeoff`.
pub fn run(args: TradeoffArgs) -> Result<()> {
    let (scene, decision) = resolved_scene(&args.common, "tradeoff")?;
    super::refuse_data(
        &scene,
        "tradeoff",
        "measures the beam solver's resolution and the load sampling, which measured data \
         does not have (time the fit's presets with fit --fidelity draft|normal|precise)",
    )?;
    let start = PrbMatrix::from_topology(&args.topology)
        .map_err(|e| bad(format!("--topology {}: {e}", args.topology)))?;
    let knobs = measure(&scene, &start, &CancelToken::new())?;
    let out = TradeoffOutput {
        scene: scene.name,
        topology: args.topology,
        effects_decision: decision,
        knobs,
    };
    emit(&out, args.common.json)
}
