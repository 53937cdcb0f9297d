//! The scene file writer: a [`Scene`] as TOML in the schema the reader reads (DESIGN §5, §8,
//! §9), so that reading what was written gives the same scene (the UI saves scenes this way).

use super::beam::{BeamSpec, EffectsChoice};
use super::drive::{Coordinate, COORDINATE_KEYS};
use super::mechanism::{Attach, Mechanism};
use super::settings::{Accuracy, Body, FitSettings};
use super::Scene;

impl Scene {
    /// The scene as TOML, in the schema it was read from.
    pub fn to_toml(&self) -> String {
        let mut out = String::new();
        out.push_str(&format!("name = {}\n\n[beam]\n", toml_string(&self.name)));
        let b = &self.beam;
        out.push_str(&format!("length = {:e}\n", b.length));
        out.push_str(&format!("width = {:e}\n", b.width));
        out.push_str(&format!("thickness = {:e}\n", b.thickness));
        out.push_str(&format!("youngs_modulus = {:e}\n", b.youngs_modulus));
        out.push_str(&format!("poisson_ratio = {:?}\n", b.poisson_ratio));
        if let Some(k) = b.shear_coefficient {
            out.push_str(&format!("shear_coefficient = {k:?}\n"));
        }
        if let Some(s) = b.allowable_stress {
            out.push_str(&format!("allowable_stress = {s:e}\n"));
        }
        match b.effects {
            EffectsChoice::Auto => out.push_str("effects = \"auto\"\n"),
            EffectsChoice::Fixed(e) => {
                let names: Vec<String> = e.names().iter().map(|n| format!("\"{n}\"")).collect();
                out.push_str(&format!("effects = [{}]\n", names.join(", ")));
            }
        }
        if let Some(rho) = b.density {
            out.push_str(&format!("density = {rho:?}\n"));
        }
        if let Some(t) = &self.truth {
            out.push_str(&format!("\n[truth]\ndata = {}\n", toml_string(&t.file)));
        }
        for path in self.loads.iter().filter(|_| self.truth.is_none()) {
            out.push_str(&format!(
                "\n[[loads]]\nalpha_x = {:?}\nalpha_y = {:?}\nbeta = {:?}\nsteps = {}\n",
                path.end.alpha_x, path.end.alpha_y, path.end.beta, path.steps
            ));
        }
        if let Some(m) = &self.mechanism {
            // A data scene's drive paths are its file's rows.
            mechanism_tables(m, &self.beam, self.truth.is_none(), &self.body, &mut out);
        } else if !self.body.is_none() {
            out.push_str(&format!(
                "\n[tip]\nmass = {:?}\ninertia = {:?}\n",
                self.body.mass, self.body.inertia
            ));
        }
        out.push_str(&format!(
            "\n[accuracy]\nmax_pos_err = {:?}\nmax_ang_err = {:?}\n",
            self.accuracy.max_pos_err, self.accuracy.max_ang_err
        ));
        if self.mechanism.is_some() {
            out.push_str(&format!(
                "max_force_err = {:?}\n",
                self.accuracy.max_force_err
            ));
        }
        if self.accuracy.max_freq_err != Accuracy::default().max_freq_err {
            out.push_str(&format!(
                "max_freq_err = {:?}\n",
                self.accuracy.max_freq_err
            ));
        }
        out.push_str(&format!(
            "\n[fit]\nangle_weight = {:?}\n",
            self.fit.angle_weight
        ));
        if self.mechanism.is_some() {
            out.push_str(&format!("force_weight = {:?}\n", self.fit.force_weight));
        }
        if self.fit.modes != 0
            || self.fit.frequency_weight != FitSettings::default().frequency_weight
        {
            out.push_str(&format!(
                "modes = {}\nfrequency_weight = {:?}\n",
                self.fit.modes, self.fit.frequency_weight
            ));
        }
        if let Some(m) = &self.prb {
            out.push_str(&format!(
                "\n[prb]\nmatrix = {}\n",
                toml_string(&m.to_text())
            ));
        }
        out
    }
}

fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// Writes `m`'s tables in the scene file's schema: a flexure's beam values only where they
/// differ from the scene's `[beam]`, and the `[[drives]]` only with `drives` (a data scene's
/// drive paths are its file's rows), and the stage's `body`.
fn mechanism_tables(
    m: &Mechanism,
    scene_beam: &BeamSpec,
    drives: bool,
    body: &Body,
    out: &mut String,
) {
    use std::fmt::Write as _;
    for f in &m.flexures {
        let _ = write!(
            out,
            "\n[[flexures]]\nroot = [{:?}, {:?}]\nangle_deg = {:?}\n",
            f.root[0],
            f.root[1],
            f.angle.to_degrees()
        );
        match f.attach {
            Attach::Clamped => out.push_str("attach = \"clamped\"\n"),
            Attach::Pinned => out.push_str("attach = \"pinned\"\n"),
            Attach::Link { to } => {
                let _ = write!(
                    out,
                    "attach = \"link\"\nlink_to = [{:?}, {:?}]\n",
                    to[0], to[1]
                );
            }
        }
        let b = &f.beam;
        for (name, mine, scene) in [
            ("length", b.length, scene_beam.length),
            ("width", b.width, scene_beam.width),
            ("thickness", b.thickness, scene_beam.thickness),
            (
                "youngs_modulus",
                b.youngs_modulus,
                scene_beam.youngs_modulus,
            ),
            ("poisson_ratio", b.poisson_ratio, scene_beam.poisson_ratio),
        ] {
            if mine != scene {
                let _ = writeln!(out, "{name} = {mine:?}");
            }
        }
        if let (Some(s), true) = (
            b.allowable_stress,
            b.allowable_stress != scene_beam.allowable_stress,
        ) {
            let _ = writeln!(out, "allowable_stress = {s:e}");
        }
    }
    let _ = write!(
        out,
        "\n[stage]\npoint = [{:?}, {:?}]\n",
        m.stage_point[0], m.stage_point[1]
    );
    if !body.is_none() {
        let _ = write!(
            out,
            "mass = {:?}\ninertia = {:?}\n",
            body.mass, body.inertia
        );
    }
    for d in m.drives.iter().filter(|_| drives) {
        out.push_str("\n[[drives]]\n");
        for (c, (dk, lk)) in d.coordinates.iter().zip(COORDINATE_KEYS) {
            let _ = match c {
                Coordinate::Prescribed(v) => writeln!(out, "{dk} = {v:?}"),
                Coordinate::Loaded(v) => writeln!(out, "{lk} = {v:?}"),
            };
        }
        let _ = writeln!(out, "steps = {}", d.steps);
    }
}
