//! CSV of the load cases: per case the beam tip and the PRB tip, then the beam's shape and the
//! PRB linkage (units of L, radians), from one PRB solve of each load path.

use std::fmt::Write as _;
use std::ops::ControlFlow;

use crate::eval::Baseline;
use crate::prb::{PrbMatrix, PrbSolver};

use super::ExportError;

/// The CSV of `matrix` followed along `baseline`'s paths; `title` goes into the comment line.
pub fn write(matrix: &PrbMatrix, baseline: &Baseline, title: &str) -> Result<String, ExportError> {
    let solver = PrbSolver::new(matrix, baseline.model.axial_compliance());
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# prbfit {} export: {title}; positions in units of L, angles in radians",
        env!("CARGO_PKG_VERSION"),
    );
    let _ = writeln!(out, "case,alpha_x,alpha_y,beta,curve,index,x,y,angle");
    let mut case = 0usize;
    baseline
        .follow(
            &solver,
            |beam, sol| {
                case += 1;
                let l = sol.load;
                let head = format!("{case},{},{},{}", l.alpha_x, l.alpha_y, l.beta);
                let _ = writeln!(
                    out,
                    "{head},beam_tip,0,{},{},{}",
                    beam.tip.a, beam.tip.b, beam.tip.phi
                );
                let _ = writeln!(
                    out,
                    "{head},prb_tip,0,{},{},{}",
                    sol.tip.a, sol.tip.b, sol.tip.phi
                );
                for (i, p) in beam.shape.iter().enumerate() {
                    let _ = writeln!(out, "{head},beam_shape,{i},{},{},{}", p.x, p.y, p.psi);
                }
                for (i, p) in solver.joint_positions(sol.q).iter().enumerate() {
                    let _ = writeln!(out, "{head},prb_linkage,{i},{},{},", p[0], p[1]);
                }
            },
            |_, _| ControlFlow::Break(()),
        )
        .map_err(|e| ExportError::Eval(e.to_string()))?;
    Ok(out)
}
