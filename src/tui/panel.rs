//! The panels that take the keyboard ([`Panel`]) and the order Tab visits them in: what the
//! keymap, the panels' states, the app and the drawing all name.

/// The panels that take the keyboard.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Panel {
    /// The beam and the scene's targets.
    Beam,
    /// The load paths.
    Loads,
    /// The PRB matrix.
    Matrix,
    /// A mechanism scene's flexures, stage and drives (in place of the load paths).
    Mechanism,
}

impl Panel {
    /// The panel in the middle of the left column: the load paths, or on a mechanism scene
    /// the mechanism.
    pub fn middle(mechanism: bool) -> Panel {
        if mechanism {
            Panel::Mechanism
        } else {
            Panel::Loads
        }
    }

    /// The panel Tab moves to (on a mechanism scene when `mechanism`).
    pub fn next(self, mechanism: bool) -> Panel {
        match self {
            Panel::Beam => Panel::middle(mechanism),
            Panel::Loads | Panel::Mechanism => Panel::Matrix,
            Panel::Matrix => Panel::Beam,
        }
    }

    /// The panel Shift-Tab moves to (on a mechanism scene when `mechanism`).
    pub fn prev(self, mechanism: bool) -> Panel {
        match self {
            Panel::Beam => Panel::Matrix,
            Panel::Loads | Panel::Mechanism => Panel::Beam,
            Panel::Matrix => Panel::middle(mechanism),
        }
    }

    /// The panel to focus on a scene of the other kind: the middle panel changes with it.
    pub fn on_scene(self, mechanism: bool) -> Panel {
        match self {
            Panel::Loads | Panel::Mechanism => Panel::middle(mechanism),
            p => p,
        }
    }
}
