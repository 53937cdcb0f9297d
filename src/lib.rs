//! prbfit: finds the best pseudo-rigid-body (PRB) model of a compliant beam, alone (a
//! cantilever) or inside the mechanism it serves, against the large-deflection beam or
//! against measured data.
//!
//! The library is the numerical core and its files; the binary's command line (`cli`), the
//! terminal UI ([`tui`]) and the Python module (`python/`) are front ends over one problem, [`study`]. Bottom up (a
//! module uses only those before it; `tests/layering.rs` checks it):
//! - [`cancel`], [`text`], [`linalg`]: a cancel token, safe text, small dense solvers (and,
//!   private, `trig`'s inline sine and cosine and `cpu`'s choice of instructions);
//! - [`continuation`]: the one path-following driver of the beam, PRB and mechanism
//!   solvers;
//! - [`beam`]: the large-deflection baseline beam (DESIGN §2);
//! - [`prb`]: the PRB matrix, topology names, kinematics and statics (DESIGN §3);
//! - [`scene`]: scene files — beam, load paths, mechanisms, measured data, targets (§5, §8,
//!   §9);
//! - [`mech`]: flexure mechanisms solved with the beam or a PRB model, and the error
//!   [`mech::figures`] of every kind of scene (§4, §8);
//! - [`si`], [`fidelity`], [`format`](mod@format): SI conversions, the fit presets, file formats;
//! - [`eval`]: a cantilever's beam solutions along its load paths (the fast path of the
//!   one-flexure mechanism) and its tip errors;
//! - [`fit`]: the search for optimal PRB parameters on any target (§4);
//! - [`io`], [`fea`], [`export`]: model files, CalculiX in the loop (§9), simulator formats;
//! - [`study`]: ONE problem (§7): a scene's truth — the beam, the beam mechanism or measured
//!   data — and what every front end asks of it: judge, fit, select, calibrate, effects,
//!   export, trade-off;
//! - [`report`]: the commands' reports (§6, §12): a scene and a command's arguments in, the
//!   `--json` object and the text out, for the CLI and the Python module alike;
//! - [`plot`]: charts for reports as SVG or PNG;
//! - [`tui`]: the terminal UI (the only module that touches the terminal).

pub mod beam;
pub mod cancel;
pub mod continuation;
mod cpu;
pub mod eval;
pub mod export;
pub mod fea;
pub mod fidelity;
pub mod fit;
pub mod format;
pub mod io;
pub mod linalg;
pub mod mech;
pub mod plot;
pub mod prb;
pub mod report;
pub mod scene;
pub mod si;
pub mod study;
pub mod text;
mod trig;
#[cfg(feature = "tui")]
pub mod tui;
