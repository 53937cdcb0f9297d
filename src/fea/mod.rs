//! FEA in the loop (DESIGN §9): the scene's beam as a CalculiX (`ccx`) model, solved along
//! the scene's load paths, as an independent check of the beam theory of §2 and as measured
//! data to fit to.
//!
//! # The model
//! - **Elements**: 20-node bricks with reduced integration (`C3D20R`), one layer across the
//!   width for the plane models. Quadratic elements bend without shear locking, and reduced
//!   integration keeps nearly incompressible materials (urethane, `nu = 0.49`) from locking.
//! - **Plane stress** ([`Section::PlaneStress`], the default, what the beam of §2 is): every
//!   node is held in its plane and the material is the plane-strain equivalent of plane
//!   stress, `E* = E (1 + 2 nu) / (1 + nu)^2`, `nu* = nu / (1 + nu)` ([`deck::material`]).
//!   CalculiX's own plane-stress elements (`CPS8`) were tried first and measured unfit in
//!   ccx 2.20: (a) ccx expands them into one brick across the given thickness with its
//!   in-plane motion tied across it, which suppresses the anticlastic bending of a section
//!   wider than it is thick, so with the real width they are not plane stress at all (a
//!   steel strip of `w0 / t0 = 26.7` bent 0.913 times as far as plane stress, i.e. nearly
//!   plane strain's `1 - nu^2 = 0.916`; with `w0 = t0 / 10`, 0.998); (b) a `*RIGID BODY` on
//!   expanded plane elements does not converge under `NLGEOM` (ccx: "linear MPCs and
//!   nonlinear MPCs depend on each other"; no increment converged under a tip moment).
//! - **Plane strain** ([`Section::PlaneStrain`]): the same slab with the true `E, nu`: the
//!   limit of a section much wider than the beam is long or curved (the beam's
//!   [`crate::beam::Effects::plane_strain`] at plate fraction 1).
//! - **Solid** ([`Section::Solid`]): the true 3D strip, half its width modelled with a
//!   symmetry plane at the middle, several bricks across: where the real plate effect of a
//!   wide section lies between the two plane limits.
//! - **Taper** ([`Taper`], `prbfit fea --taper R`): the thickness may vary linearly from the
//!   scene's `t0` at the clamp to `R t0` at the tip, the width constant (a tapered flexure,
//!   which no uniform beam of §2 matches). Every node's through-thickness coordinate scales
//!   with the local thickness, so the mesh keeps its bricks and the rigid tip is the tip's
//!   own section. `R = 1` (the default) writes the uniform beam's deck, byte for byte.
//! - **Clamp**: every node of the root face is fixed.
//! - **Tip**: the tip face is a `*RIGID BODY` with its reference node at the section's centre
//!   `(L, 0)`, so the tip pose is that of a rigid body bolted to the tip (DESIGN §2's `phi`).
//!   The forces act at the reference node and the moment on the rigid body's rotation node
//!   (its third degree of freedom is the rotation about z). Both are `*CLOAD`s, which keep
//!   their global direction under `NLGEOM`: dead loads, as in §2 (a planar moment is the same
//!   dead or following). The tip's rotation is read from the rotation node, whose
//!   displacement is the rotation vector: not wrapped at pi (a full loop reads 2 pi).
//! - **Steps**: one `*STEP` (`NLGEOM`, automatic increments, tight convergence controls) per
//!   load case, each taking the load from the previous case's to its own: continuation along
//!   the path. Each path is a separate analysis starting unloaded.
//!
//! # Accuracy
//! The error is the mesh's: measure it by refining ([`Mesh::for_beam`] scales all three
//! directions with one density). Along a slender beam with one brick through the thickness
//! the tip converges at about first order in the element length (measured ratio 2.0-2.2 per
//! halving; the clamp's corner singularity), which a three-mesh Richardson estimate captures:
//! `tests/fea.rs` prints the tables. The solver's own tolerance (residual 1e-7 of the mean
//! force) and the `.dat`'s seven digits are far below it.

pub mod ccx;
pub mod dat;
pub mod deck;
pub mod mech;

use std::fmt;
use std::str::FromStr;
use std::time::Duration;

use serde::Serialize;

use crate::beam::Load;
use crate::scene::{BeamSpec, Scene};
use crate::si::load_si;

pub use ccx::{Ccx, CcxError, CcxFailure, INSTALL_HINT};
pub use dat::{DatError, StepEnd};

/// How the section is modelled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Section {
    /// Plane stress: the beam of DESIGN §2 (a narrow section).
    PlaneStress,
    /// Plane strain: a section so wide it cannot curl across (`E / (1 - nu^2)`).
    PlaneStrain,
    /// The 3D strip (half its width, by symmetry).
    Solid,
}

impl Section {
    /// Its name on the command line and in reports.
    pub fn name(&self) -> &'static str {
        match self {
            Section::PlaneStress => "plane-stress",
            Section::PlaneStrain => "plane-strain",
            Section::Solid => "solid",
        }
    }
}

impl fmt::Display for Section {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Section {
    type Err = String;
    fn from_str(s: &str) -> Result<Section, String> {
        match s {
            "plane-stress" => Ok(Section::PlaneStress),
            "plane-strain" => Ok(Section::PlaneStrain),
            "solid" => Ok(Section::Solid),
            other => Err(format!(
                "unknown section `{other}` (expected plane-stress, plane-strain or solid)"
            )),
        }
    }
}

/// A linear taper of the thickness: `t(s) = t0 (1 - (1 - R) s / L)`, from the scene's `t0`
/// at the clamp to `R t0` at the tip, the width constant. `R = 1` is the uniform beam.
///
/// `R` is kept within [`Taper::MIN`]..=[`Taper::MAX`]. Towards `R = 0` the tip section
/// vanishes: under a tip force the tip angle grows as `1 / R` (`∫ (L - s) / t(s)^3 ds`) and
/// the elements at the tip, one brick through a thickness `R t0` and as long as `t0`, grow
/// too slender for quadratic bricks; at `R = 0.05` they are 20 times as long as thick, about
/// the limit where C3D20R elements still bend accurately. The upper bound is the same ratio
/// the other way (a tip 20 times the root: the brick count through the thick end follows the
/// thickest section, so it is the root's bricks that are 20 times as long as thick).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Taper(f64);

/// A taper ratio that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct TaperError(String);

impl Taper {
    /// The uniform beam.
    pub const UNIFORM: Taper = Taper(1.0);
    /// The thinnest tip allowed, as a fraction of the root thickness.
    pub const MIN: f64 = 0.05;
    /// The thickest tip allowed, as a multiple of the root thickness.
    pub const MAX: f64 = 20.0;

    /// The taper with tip thickness `ratio` times the root's.
    pub fn new(ratio: f64) -> Result<Taper, TaperError> {
        if !ratio.is_finite() || !(Taper::MIN..=Taper::MAX).contains(&ratio) {
            return Err(TaperError(format!(
                "the taper (tip thickness over root thickness) must be a number from {} to {}, \
                 got {}",
                Taper::MIN,
                Taper::MAX,
                crate::text::bounded(ratio)
            )));
        }
        Ok(Taper(ratio))
    }

    /// `R`, the tip thickness over the root thickness.
    pub fn ratio(self) -> f64 {
        self.0
    }

    /// Whether this is the uniform beam (`R = 1`).
    pub fn is_uniform(self) -> bool {
        self.0 == 1.0
    }

    /// `t(s) / t0` at `s = fraction L`: exactly 1 everywhere for the uniform beam.
    pub fn thickness_factor(self, fraction: f64) -> f64 {
        1.0 - (1.0 - self.0) * fraction
    }

    /// The thickest section over `t0`: `max(1, R)`.
    pub fn thickest(self) -> f64 {
        self.0.max(1.0)
    }
}

impl Default for Taper {
    fn default() -> Taper {
        Taper::UNIFORM
    }
}

impl fmt::Display for Taper {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

impl FromStr for Taper {
    type Err = String;
    fn from_str(s: &str) -> Result<Taper, String> {
        let ratio: f64 = s
            .trim()
            .parse()
            .map_err(|_| format!("`{s}` is not a number (the tip thickness over the root's)"))?;
        Taper::new(ratio).map_err(|e| e.to_string())
    }
}

/// Bricks along the length, through the thickness and across the modelled width.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Mesh {
    /// Along the length `L`.
    pub along: u32,
    /// Through the thickness `t0`.
    pub through: u32,
    /// Across the modelled width (1 in the plane models).
    pub across: u32,
}

/// The most bricks a mesh may have: far beyond any beam's needs (a 3D strip of 200 x 4 x 20
/// is 16 000), small enough that a typo does not start an hour of solving.
pub const MAX_BRICKS: u64 = 200_000;

/// A mesh density that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct MeshError(String);

impl Mesh {
    /// The mesh of density `n` for `beam`: `n` bricks along the length, and through the
    /// thickness and across the width as many as keep the bricks about as long as they are
    /// thick and wide (`round(n t0 / L)`, at least 1; across the half-width of the solid,
    /// `round(n w0 / (2 L))`, at least 2). Refining `n` refines every direction alike.
    pub fn for_beam(n: u32, beam: &BeamSpec, section: Section) -> Result<Mesh, MeshError> {
        Mesh::for_tapered_beam(n, beam, section, Taper::UNIFORM)
    }

    /// [`Mesh::for_beam`] for the beam tapered by `taper`: the bricks through the thickness
    /// follow the thickest section (`max(1, R) t0`), so no brick is thicker than it is long;
    /// with `R <= 1` this is the uniform beam's mesh.
    pub fn for_tapered_beam(
        n: u32,
        beam: &BeamSpec,
        section: Section,
        taper: Taper,
    ) -> Result<Mesh, MeshError> {
        if n < 2 {
            return Err(MeshError(format!(
                "the mesh density must be at least 2 elements along the beam, got {n}"
            )));
        }
        let share = |size: f64| (n as f64 * size / beam.length).round().max(1.0) as u32;
        let mesh = Mesh {
            along: n,
            through: share(beam.thickness * taper.thickest()),
            across: match section {
                Section::Solid => share(beam.width / 2.0).max(2),
                Section::PlaneStress | Section::PlaneStrain => 1,
            },
        };
        let bricks = mesh.bricks();
        if bricks > u128::from(MAX_BRICKS) {
            return Err(MeshError(format!(
                "density {n} makes {} x {} x {} = {bricks} elements, more than the {MAX_BRICKS} \
                 allowed: choose a smaller density",
                mesh.along, mesh.through, mesh.across
            )));
        }
        Ok(mesh)
    }
}

impl Mesh {
    /// Its number of bricks, counted where no density can overflow it (three `u32` factors).
    pub fn bricks(&self) -> u128 {
        u128::from(self.along) * u128::from(self.through) * u128::from(self.across)
    }
}

impl fmt::Display for Mesh {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} x {} x {}", self.along, self.through, self.across)
    }
}

/// One load case as CalculiX solved it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FeaCase {
    /// The load path, 1-based.
    pub path: usize,
    /// The load, nondimensional (the scene's case).
    pub load: Load,
    /// The same load in SI: `[Fx, Fy, Mz]`, N, N, N m.
    pub load_si: [f64; 3],
    /// The tip from the clamp, m (unloaded tip at `(L, 0)`).
    pub x: f64,
    /// m
    pub y: f64,
    /// The tip section's angle, rad.
    pub theta: f64,
}

/// Why an FEA of a scene failed.
#[derive(Debug, thiserror::Error)]
pub enum FeaError {
    /// A mechanism scene given to the cantilever's model ([`mech`] models mechanisms).
    #[error("a mechanism scene: its FEA is the mechanism's (fea::mech), not a cantilever's")]
    Mechanism,
    /// Running CalculiX failed on a path.
    #[error("load path {path}: {source}")]
    Ccx {
        /// 1-based.
        path: usize,
        /// Why.
        source: CcxError,
    },
    /// CalculiX's output could not be read, or stopped early, on a path.
    #[error("load path {path}: {source}{}", detail.as_deref().map(|d| format!(" (ccx: {d})")).unwrap_or_default())]
    Output {
        /// 1-based.
        path: usize,
        /// Why.
        source: DatError,
        /// CalculiX's last words, when they help.
        detail: Option<String>,
    },
}

/// The SI loads of each path's cases, path by path.
pub fn path_loads(scene: &Scene) -> Vec<Vec<(Load, [f64; 3])>> {
    scene
        .loads
        .iter()
        .map(|p| p.cases().map(|l| (l, load_si(&scene.beam, &l))).collect())
        .collect()
}

/// The deck of each load path of a cantilever scene, its thickness tapered by `taper`.
pub fn scene_decks(
    scene: &Scene,
    mesh: &Mesh,
    section: Section,
    taper: Taper,
) -> Result<Vec<String>, FeaError> {
    if scene.mechanism.is_some() {
        return Err(FeaError::Mechanism);
    }
    Ok(path_loads(scene)
        .iter()
        .map(|cases| {
            let loads: Vec<[f64; 3]> = cases.iter().map(|c| c.1).collect();
            deck::deck(&scene.beam, mesh, section, taper, &loads)
        })
        .collect())
}

/// Solves every load path of `scene` (its thickness tapered by `taper`) with `ccx` (one run
/// per path, each under `timeout`); `on_path(k, seconds)` hears when path `k` (1-based) is
/// done.
pub fn solve_scene(
    scene: &Scene,
    mesh: &Mesh,
    section: Section,
    taper: Taper,
    ccx: &Ccx,
    timeout: Duration,
    on_path: &mut dyn FnMut(usize, f64),
) -> Result<Vec<FeaCase>, FeaError> {
    let decks = scene_decks(scene, mesh, section, taper)?;
    let mut out = Vec::new();
    for (k, (deck, cases)) in decks.iter().zip(path_loads(scene)).enumerate() {
        let path = k + 1;
        let run = ccx
            .run(deck, timeout)
            .map_err(|source| FeaError::Ccx { path, source })?;
        let ends = dat::step_ends(&run.dat, cases.len()).map_err(|source| FeaError::Output {
            path,
            source,
            detail: last_words(&run.log),
        })?;
        out.extend(
            cases
                .iter()
                .zip(ends)
                .map(|(&(load, load_si), end)| FeaCase {
                    path,
                    load,
                    load_si,
                    x: scene.beam.length + end.ux,
                    y: end.uy,
                    theta: end.theta,
                }),
        );
        on_path(path, run.seconds);
    }
    Ok(out)
}

/// The last non-empty line of a log, shortened.
fn last_words(log: &str) -> Option<String> {
    log.lines()
        .rev()
        .map(str::trim)
        .find(|l| !l.is_empty())
        .map(|l| l.chars().take(120).collect())
}

/// The cases as DESIGN §9's CSV in SI columns: `path,fx,fy,mz,x,y,theta`, one row per case
/// in path order (each path from near unloaded outward). A tapered beam's file opens with a
/// `#` comment that says so (readers skip `#` lines): its data are not the scene's uniform
/// beam's. The uniform beam's file has no comment.
pub fn csv(cases: &[FeaCase], taper: Taper) -> String {
    let mut out = String::new();
    if !taper.is_uniform() {
        out.push_str(&format!(
            "# prbfit fea --taper {taper}: thickness tapered linearly from the scene's [beam] \
             thickness at the clamp to {taper} times it at the tip, width constant\n"
        ));
    }
    out.push_str("path,fx,fy,mz,x,y,theta\n");
    for c in cases {
        let [fx, fy, mz] = c.load_si;
        out.push_str(&format!(
            "{},{fx:e},{fy:e},{mz:e},{:e},{:e},{:e}\n",
            c.path, c.x, c.y, c.theta
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesh_density_scales_every_direction() {
        let scene = Scene::builtin(); // L = 50 mm, t0 = 0.5 mm, w0 = 10 mm
        let m = Mesh::for_beam(40, &scene.beam, Section::PlaneStress).unwrap();
        assert_eq!((m.along, m.through, m.across), (40, 1, 1));
        let m = Mesh::for_beam(40, &scene.beam, Section::Solid).unwrap();
        assert_eq!((m.along, m.through, m.across), (40, 1, 4));
        let mut stubby = scene.beam;
        stubby.thickness = 0.0125; // L / t0 = 4
        let m = Mesh::for_beam(16, &stubby, Section::PlaneStrain).unwrap();
        assert_eq!((m.along, m.through, m.across), (16, 4, 1));
        assert!(Mesh::for_beam(1, &scene.beam, Section::PlaneStress).is_err());
        assert!(Mesh::for_beam(100_000, &stubby, Section::Solid).is_err());
    }

    #[test]
    fn a_density_whose_brick_count_would_wrap_is_refused_with_the_true_count() {
        // 209715200 x 2097152 x 20971520 is 125 x 2^66: in u64 it wrapped to exactly 0 bricks,
        // which passed the limit and aborted on a 1.6e17-byte allocation.
        let beam = Scene::builtin().beam; // L / t0 = 100, w0 / L = 0.2
        let err = Mesh::for_beam(209_715_200, &beam, Section::Solid).unwrap_err();
        let m = Mesh {
            along: 209_715_200,
            through: 2_097_152,
            across: 20_971_520,
        };
        assert!(
            err.to_string()
                .contains(&format!("= {} elements", m.bricks())),
            "{err}"
        );
        assert!(m.bricks() > u128::from(u64::MAX));
    }

    #[test]
    fn csv_rows_follow_the_paths_in_si() {
        let scene = Scene::builtin();
        let loads = path_loads(&scene);
        let cases: Vec<FeaCase> = loads
            .iter()
            .enumerate()
            .flat_map(|(k, p)| {
                p.iter().map(move |&(load, load_si)| FeaCase {
                    path: k + 1,
                    load,
                    load_si,
                    x: 0.05,
                    y: 0.0,
                    theta: 0.0,
                })
            })
            .collect();
        let text = csv(&cases, Taper::UNIFORM);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "path,fx,fy,mz,x,y,theta");
        assert_eq!(lines.len(), 1 + scene.cases().len());
        assert!(lines[1].starts_with("1,"));
        assert!(lines
            .last()
            .unwrap()
            .starts_with(&format!("{},", scene.loads.len())));
        // The first case of path 1 (alpha_y = 1 of 5) in newtons: E I0 / L^2.
        let b = &scene.beam;
        let fy = b.youngs_modulus * b.second_moment() / b.length.powi(2);
        let row: Vec<f64> = lines[1].split(',').map(|v| v.parse().unwrap()).collect();
        assert!((row[2] - fy).abs() < 1e-12 * fy, "{} vs {fy}", row[2]);
    }

    #[test]
    fn tapers_are_finite_and_bounded() {
        for bad in [0.0, 0.049, 20.5, -1.0, f64::NAN, f64::INFINITY] {
            assert!(Taper::new(bad).is_err(), "{bad}");
        }
        for good in [Taper::MIN, 0.5, 1.0, 3.0, Taper::MAX] {
            assert_eq!(Taper::new(good).unwrap().ratio(), good);
        }
        assert_eq!("0.5".parse::<Taper>().unwrap(), Taper::new(0.5).unwrap());
        assert!("half"
            .parse::<Taper>()
            .unwrap_err()
            .contains("not a number"));
        let t = Taper::new(0.5).unwrap();
        assert_eq!(t.thickness_factor(0.0), 1.0);
        assert_eq!(t.thickness_factor(1.0), 0.5);
        assert_eq!(Taper::UNIFORM.thickness_factor(0.37), 1.0);
        // The bricks through the thickness follow the thickest section.
        let scene = Scene::builtin(); // L / t0 = 100
        let mesh = |r| {
            Mesh::for_tapered_beam(
                100,
                &scene.beam,
                Section::PlaneStress,
                Taper::new(r).unwrap(),
            )
            .unwrap()
            .through
        };
        assert_eq!((mesh(0.5), mesh(1.0), mesh(3.0)), (1, 1, 3));
    }

    #[test]
    fn a_tapered_csv_says_so_in_a_comment() {
        let case = FeaCase {
            path: 1,
            load: Load::new(0.0, 1.0, 0.0),
            load_si: [0.0, 1.0, 0.0],
            x: 0.05,
            y: 0.01,
            theta: 0.2,
        };
        let uniform = csv(&[case], Taper::UNIFORM);
        assert!(uniform.starts_with("path,"));
        let tapered = csv(&[case], Taper::new(0.5).unwrap());
        assert!(tapered.starts_with("# prbfit fea --taper 0.5: "));
        assert!(tapered.ends_with(&uniform));
        // Readers skip the comment: the rows are the uniform file's.
        let beam = Scene::builtin().beam;
        let read = |text: &str| {
            crate::scene::data::parse_csv(text, "d.csv", &beam)
                .unwrap()
                .0
        };
        assert_eq!(read(&tapered)[0].rows[0].tip, read(&uniform)[0].rows[0].tip);
    }

    #[test]
    fn mechanisms_are_refused() {
        let text = include_str!("../../assets/scenes/fixed-guided.toml");
        let scene = Scene::from_toml_str(text, "fixed-guided.toml").unwrap();
        let mesh = Mesh::for_beam(4, &scene.beam, Section::PlaneStress).unwrap();
        assert!(matches!(
            scene_decks(&scene, &mesh, Section::PlaneStress, Taper::UNIFORM),
            Err(FeaError::Mechanism)
        ));
    }
}
