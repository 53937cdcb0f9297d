//! prbfit: finds the best pseudo-rigid-body (PRB) model of a compliant cantilever beam.
//!
//! The library is the numerical core (no terminal, no files except through [`scene`]):
//! - [`beam`]: the large-deflection baseline beam (DESIGN §2),
//! - [`scene`]: scene files — beam, load paths, accuracy targets (DESIGN §5).

pub mod beam;
pub mod scene;
