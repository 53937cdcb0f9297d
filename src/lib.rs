//! prbfit: finds the best pseudo-rigid-body (PRB) model of a compliant cantilever beam.
//!
//! The library is the numerical core (no terminal, no files except through [`scene`]):
//! - [`beam`]: the large-deflection baseline beam (DESIGN §2),
//! - [`continuation`]: the one path-following driver of the beam, PRB and mechanism solvers,
//! - [`eval`]: a PRB model judged against the beam over a scene (DESIGN §4),
//! - [`export`]: model files, MuJoCo, URDF, SDF and CSV,
//! - [`fea`]: the beam as a CalculiX model along the scene's loads (DESIGN §9),
//! - [`fit`]: optimal PRB parameters for any topology (DESIGN §4),
//! - [`plot`]: charts for reports (deformed shapes, tip errors) as SVG or PNG,
//! - [`prb`]: the PRB matrix, topology names, kinematics and statics (DESIGN §3),
//! - [`select`]: automatic beam effects and the topology ladder (the simplest model that
//!   meets the scene's targets),
//! - [`tradeoff`]: the speed/accuracy trade measured along each knob,
//! - [`scene`]: scene files — beam, load paths, accuracy targets (DESIGN §5),
//! - [`tui`]: the terminal UI (the only module that touches the terminal).

pub mod beam;
pub mod cancel;
pub mod continuation;
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
pub mod scene;
pub mod select;
pub mod si;
pub mod text;
pub mod tradeoff;
#[cfg(feature = "tui")]
pub mod tui;
