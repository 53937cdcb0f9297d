//! The CalculiX input deck of a scene's beam: a pure function of the beam, the mesh, the
//! section model, the taper and the SI tip loads of one load path.
//!
//! The beam is a slab of 20-node bricks with reduced integration (C3D20R), `along` elements
//! over the length `L`, `through` over the thickness and `across` over the modelled width.
//! The thickness is `t0` or, tapered, `t(x) = t0 (1 - (1 - R) x / L)`: each node's
//! through-thickness coordinate is its place in the uniform slab scaled by `t(x) / t0`.
//! Nodes are numbered contiguously, length fastest, then thickness, then width; the tip's
//! reference node and rotation node come last. See the module docs of [`crate::fea`] for why
//! the bricks and not CalculiX's own plane elements.

use std::fmt::Write as _;

use super::{Mesh, Section, Taper};
use crate::scene::BeamSpec;

/// The name of the node set whose displacement is the tip position.
pub const REF_SET: &str = "NREF";
/// The name of the node set whose first three "displacements" are the tip's rotation vector.
pub const ROT_SET: &str = "NROT";

/// The brick's 20 nodes in CalculiX's order, as offsets in half-element steps
/// (x along the length, y through the thickness, z across the width): the eight corners,
/// the four mid-edge nodes of the face z = 0, those of z = 1, then the four edges along z.
const BRICK: [(usize, usize, usize); 20] = [
    (0, 0, 0),
    (2, 0, 0),
    (2, 2, 0),
    (0, 2, 0),
    (0, 0, 2),
    (2, 0, 2),
    (2, 2, 2),
    (0, 2, 2),
    (1, 0, 0),
    (2, 1, 0),
    (1, 2, 0),
    (0, 1, 0),
    (1, 0, 2),
    (2, 1, 2),
    (1, 2, 2),
    (0, 1, 2),
    (0, 0, 1),
    (2, 0, 1),
    (2, 2, 1),
    (0, 2, 1),
];

/// The grid of a mesh: node positions in half-element steps and their numbers.
struct Grid {
    nx: usize,
    ny: usize,
    nz: usize,
    /// Node number of each grid point (0 where no brick uses it: a face or body centre).
    ids: Vec<usize>,
    count: usize,
}

impl Grid {
    fn new(mesh: &Mesh) -> Grid {
        let (nx, ny, nz) = (
            2 * mesh.along as usize + 1,
            2 * mesh.through as usize + 1,
            2 * mesh.across as usize + 1,
        );
        let mut ids = vec![0; nx * ny * nz];
        let mut count = 0;
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    // A 20-node brick has no node with two or three odd coordinates.
                    let odd = (i % 2) + (j % 2) + (k % 2);
                    if odd <= 1 {
                        count += 1;
                        ids[(k * ny + j) * nx + i] = count;
                    }
                }
            }
        }
        Grid {
            nx,
            ny,
            nz,
            ids,
            count,
        }
    }

    fn id(&self, i: usize, j: usize, k: usize) -> usize {
        self.ids[(k * self.ny + j) * self.nx + i]
    }

    /// Every node as `(id, i, j, k)`, in number order.
    fn nodes(&self) -> impl Iterator<Item = (usize, usize, usize, usize)> + '_ {
        (0..self.nz).flat_map(move |k| {
            (0..self.ny).flat_map(move |j| {
                (0..self.nx).filter_map(move |i| {
                    let id = self.id(i, j, k);
                    (id > 0).then_some((id, i, j, k))
                })
            })
        })
    }
}

/// The opening of every load case's step: geometrically nonlinear, automatic increments from
/// the whole step down to 1e-5 of it, and tight convergence controls (residual 1e-7 of the
/// mean force).
pub(super) const STEP_HEAD: &str = "*STEP, NLGEOM, INC=1000\n\
     *STATIC\n1.0, 1.0, 1e-5, 1.0\n\
     *CONTROLS, PARAMETERS=TIME INCREMENTATION\n8, 16, 9, 200, 10, 4, 0, 5\n\
     *CONTROLS, PARAMETERS=FIELD\n1e-7, 1e-6\n";

/// The material constants CalculiX is given: `(E, nu)` of the bricks. Plane stress is
/// modelled as plane strain with `E* = E (1 + 2 nu) / (1 + nu)^2`, `nu* = nu / (1 + nu)`,
/// whose in-plane law is exactly plane stress's with `E, nu` (the same condensed matrix
/// `E / (1 - nu^2) [1, nu; nu, 1]` and shear modulus `E / (2 (1 + nu))`; the identity holds
/// for the Green strain / second Piola-Kirchhoff law of a geometrically nonlinear run too).
pub fn material(beam: &BeamSpec, section: Section) -> (f64, f64) {
    let (e, nu) = (beam.youngs_modulus, beam.poisson_ratio);
    match section {
        Section::PlaneStress => (e * (1.0 + 2.0 * nu) / (1.0 + nu).powi(2), nu / (1.0 + nu)),
        Section::PlaneStrain | Section::Solid => (e, nu),
    }
}

/// The width the slab models (m) and the fraction of the beam's loads it carries: the whole
/// width in the plane models, half of it (a symmetry plane at the middle) in the solid one.
pub fn modelled_width(beam: &BeamSpec, section: Section) -> (f64, f64) {
    match section {
        Section::PlaneStress | Section::PlaneStrain => (beam.width, 1.0),
        Section::Solid => (beam.width / 2.0, 0.5),
    }
}

/// The deck for one load path: one `*STEP` per case, each taking the tip load from the
/// previous case's to `loads[k]` (SI: `[Fx, Fy, Mz]` in N, N, N m), starting unloaded. The
/// beam's thickness is `beam.thickness` at the clamp and tapers linearly to `taper` times it
/// at the tip; the uniform taper writes the uniform beam's deck exactly.
pub fn deck(
    beam: &BeamSpec,
    mesh: &Mesh,
    section: Section,
    taper: Taper,
    loads: &[[f64; 3]],
) -> String {
    let grid = Grid::new(mesh);
    let (width, share) = modelled_width(beam, section);
    let (l, t) = (beam.length, beam.thickness);
    let reference = grid.count + 1;
    let rotation = grid.count + 2;
    let mut out = String::new();
    // `write!` to a String cannot fail; the results are ignored throughout.
    let _ = writeln!(
        out,
        "** prbfit: {} model of a cantilever, L = {l:e} m, t0 = {t:e} m, w0 = {:e} m\n\
         ** {} x {} x {} C3D20R bricks (length x thickness x modelled width {width:e} m)",
        section.name(),
        beam.width,
        mesh.along,
        mesh.through,
        mesh.across
    );
    if !taper.is_uniform() {
        let _ = writeln!(
            out,
            "** tapered: thickness t0 at the clamp to {} t0 = {:e} m at the tip, linearly",
            taper,
            t * taper.ratio()
        );
    }
    let _ = writeln!(out, "*HEADING\nprbfit beam\n*NODE");
    let slab = Slab {
        beam,
        mesh,
        section,
        taper,
        nodes: 0,
        elements: 0,
    };
    slab.write_nodes(&mut out, &|p| p);
    let _ = writeln!(
        out,
        "{reference}, {l:.12e}, 0, 0\n{rotation}, {l:.12e}, 0, 0"
    );
    slab.write_elements(&mut out, "EBEAM");
    let sets = slab.sets();
    node_set(&mut out, "NROOT", &sets.root);
    node_set(&mut out, "NTIP", &sets.tip);
    node_set(&mut out, "NPLANE", &sets.plane);
    node_set(&mut out, REF_SET, &[reference]);
    node_set(&mut out, ROT_SET, &[rotation]);
    let (e, nu) = material(beam, section);
    // CalculiX reads at most 20 characters a field: 13 digits in scientific notation.
    let _ = writeln!(
        out,
        "*MATERIAL, NAME=MBEAM\n*ELASTIC\n{e:.12e}, {nu:.12e}\n\
         *SOLID SECTION, ELSET=EBEAM, MATERIAL=MBEAM\n\
         *BOUNDARY\nNROOT, 1, 3\nNPLANE, 3, 3\n{REF_SET}, 3, 3\n{ROT_SET}, 1, 2\n\
         *RIGID BODY, NSET=NTIP, REF NODE={reference}, ROT NODE={rotation}"
    );
    for load in loads {
        let [fx, fy, mz] = load.map(|v| v * share);
        let _ = writeln!(
            out,
            "{STEP_HEAD}*CLOAD\n{reference}, 1, {fx:.12e}\n{reference}, 2, {fy:.12e}\n{rotation}, 3, {mz:.12e}\n\
             *NODE PRINT, NSET={REF_SET}\nU\n*NODE PRINT, NSET={ROT_SET}\nU\n*END STEP"
        );
    }
    out
}

/// Writes a node set, at most 16 numbers a line.
pub(super) fn node_set(out: &mut String, name: &str, ids: &[usize]) {
    let _ = writeln!(out, "*NSET, NSET={name}");
    for chunk in ids.chunks(16) {
        let line: Vec<String> = chunk.iter().map(ToString::to_string).collect();
        let _ = writeln!(out, "{},", line.join(", "));
    }
}

/// The node sets of one slab: its root face (the clamp), its tip face, and the nodes held
/// out of the plane (every node but the root's and tip's in the plane models, the symmetry
/// plane's in the solid).
pub(super) struct SlabSets {
    /// The clamped face.
    pub root: Vec<usize>,
    /// The tip face.
    pub tip: Vec<usize>,
    /// Held out of the plane (z).
    pub plane: Vec<usize>,
}

/// One beam's slab of bricks, its nodes numbered after `nodes` and its elements after
/// `elements` (so several slabs share one deck), in its own frame: x along the length from
/// the root, y through the thickness (centred), z across the modelled width.
pub(super) struct Slab<'a> {
    /// The beam.
    pub beam: &'a BeamSpec,
    /// Its mesh.
    pub mesh: &'a Mesh,
    /// The section model.
    pub section: Section,
    /// Its taper.
    pub taper: Taper,
    /// Node numbers already used.
    pub nodes: usize,
    /// Element numbers already used.
    pub elements: usize,
}

impl Slab<'_> {
    /// How many nodes the slab has.
    pub fn node_count(&self) -> usize {
        Grid::new(self.mesh).count
    }

    /// How many elements the slab has.
    pub fn element_count(&self) -> usize {
        (self.mesh.along * self.mesh.through * self.mesh.across) as usize
    }

    /// The `*NODE` lines (no header), each node's frame position put in place by `place`.
    pub fn write_nodes(&self, out: &mut String, place: &dyn Fn([f64; 3]) -> [f64; 3]) {
        let grid = Grid::new(self.mesh);
        let (width, _) = modelled_width(self.beam, self.section);
        let (l, t0) = (self.beam.length, self.beam.thickness);
        let (ex, ey, ez) = (grid.nx - 1, grid.ny - 1, grid.nz - 1);
        for (id, i, j, k) in grid.nodes() {
            let x = l * i as f64 / ex as f64;
            // The local thickness; exactly `t0` on a uniform beam (a factor of exactly 1),
            // so its deck is the one written before tapers existed.
            let t = t0 * self.taper.thickness_factor(i as f64 / ex as f64);
            let y = -t / 2.0 + t * j as f64 / ey as f64;
            let z = width * k as f64 / ez as f64;
            let [x, y, z] = place([x, y, z]);
            let _ = writeln!(out, "{}, {x:.12e}, {y:.12e}, {z:.12e}", id + self.nodes);
        }
    }

    /// The `*ELEMENT` block of C3D20R bricks in the element set `elset`.
    pub fn write_elements(&self, out: &mut String, elset: &str) {
        let grid = Grid::new(self.mesh);
        let _ = writeln!(out, "*ELEMENT, TYPE=C3D20R, ELSET={elset}");
        let mut element = self.elements;
        for ez_ in 0..self.mesh.across as usize {
            for ey_ in 0..self.mesh.through as usize {
                for ex_ in 0..self.mesh.along as usize {
                    element += 1;
                    let ids: Vec<String> = BRICK
                        .iter()
                        .map(|&(a, b, c)| {
                            (grid.id(2 * ex_ + a, 2 * ey_ + b, 2 * ez_ + c) + self.nodes)
                                .to_string()
                        })
                        .collect();
                    // At most 16 entries on a line: the first 15 nodes, then the other 5.
                    let _ = writeln!(
                        out,
                        "{element}, {},\n{}",
                        ids[..15].join(", "),
                        ids[15..].join(", ")
                    );
                }
            }
        }
    }

    /// The slab's root, tip and out-of-plane node sets.
    pub fn sets(&self) -> SlabSets {
        let grid = Grid::new(self.mesh);
        let ex = grid.nx - 1;
        let nodes: Vec<(usize, usize, usize, usize)> = grid.nodes().collect();
        let pick = |f: &dyn Fn(usize, usize) -> bool| -> Vec<usize> {
            nodes
                .iter()
                .filter(|&&(_, i, _, k)| f(i, k))
                .map(|&(id, ..)| id + self.nodes)
                .collect()
        };
        // Out of the plane: the plane models hold every node in its plane (plane strain, and
        // plane stress through its equivalent material); the solid holds its symmetry plane.
        // Root and tip nodes are held by the clamp and the rigid tip instead.
        let inner = |i: usize| i > 0 && i < ex;
        SlabSets {
            root: pick(&|i, _| i == 0),
            tip: pick(&|i, _| i == ex),
            plane: match self.section {
                Section::PlaneStress | Section::PlaneStrain => pick(&|i, _| inner(i)),
                Section::Solid => pick(&|i, k| inner(i) && k == 0),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn mesh(along: u32, through: u32, across: u32) -> Mesh {
        Mesh {
            along,
            through,
            across,
        }
    }

    #[test]
    fn a_brick_has_twenty_nodes_and_the_grid_counts_them() {
        // One brick: 8 corners + 12 edges.
        assert_eq!(Grid::new(&mesh(1, 1, 1)).count, 20);
        // n bricks in a row share faces of 8 nodes: 20 n - 8 (n - 1).
        assert_eq!(Grid::new(&mesh(5, 1, 1)).count, 20 * 5 - 8 * 4);
    }

    #[test]
    fn the_deck_holds_the_beam_the_loads_and_the_rigid_tip() {
        let scene = Scene::builtin();
        let text = deck(
            &scene.beam,
            &mesh(4, 1, 1),
            Section::PlaneStress,
            Taper::UNIFORM,
            &[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0]],
        );
        assert_eq!(text.matches("*STEP, NLGEOM").count(), 2);
        assert_eq!(text.matches("*END STEP").count(), 2);
        assert!(text.contains("*ELEMENT, TYPE=C3D20R"));
        // 4 bricks; 4 x 20 - 3 x 8 = 56 nodes; the reference and rotation nodes follow.
        assert!(text.contains("REF NODE=57, ROT NODE=58"), "{text}");
        assert!(text.contains("57, 2, 4.000000000000e0"), "{text}");
        assert!(text.contains("58, 3, 6.000000000000e0"), "{text}");
        // Plane stress through its plane-strain equivalent.
        let nu = scene.beam.poisson_ratio;
        assert!(
            text.contains(&format!("{:.12e}", nu / (1.0 + nu))),
            "{text}"
        );
        let root = text.split("*NSET, NSET=NROOT\n").nth(1).unwrap();
        let root_ids: Vec<&str> = root
            .split('*')
            .next()
            .unwrap()
            .split([',', '\n', ' '])
            .filter(|s| !s.is_empty())
            .collect();
        // The clamped face of one brick column: 8 nodes (corners and mid-edges, no centre).
        assert_eq!(root_ids.len(), 8, "{root_ids:?}");
    }

    #[test]
    fn the_solid_models_half_the_width_and_carries_half_the_load() {
        let scene = Scene::builtin();
        let text = deck(
            &scene.beam,
            &mesh(2, 1, 2),
            Section::Solid,
            Taper::UNIFORM,
            &[[0.0, 2.0, 0.0]],
        );
        let (_, share) = modelled_width(&scene.beam, Section::Solid);
        assert_eq!(share, 0.5);
        assert!(text.contains(", 2, 1.000000000000e0"), "{text}");
        // The widest node sits at half the width.
        let half = format!("{:.12e}", scene.beam.width / 2.0);
        assert!(text.contains(&half), "{text}");
    }

    /// The `*NODE` block as `(x, y, z)`, the tip's reference and rotation nodes left out.
    fn node_coordinates(text: &str, count: usize) -> Vec<[f64; 3]> {
        let block = text
            .split("*NODE\n")
            .nth(1)
            .unwrap()
            .split('*')
            .next()
            .unwrap();
        block
            .lines()
            .take(count)
            .map(|l| {
                let v: Vec<f64> = l.split(", ").map(|f| f.parse().unwrap()).collect();
                [v[1], v[2], v[3]]
            })
            .collect()
    }

    #[test]
    fn a_tapered_deck_scales_each_section_to_its_thickness() {
        let scene = Scene::builtin();
        let (l, t0) = (scene.beam.length, scene.beam.thickness);
        for section in [Section::PlaneStress, Section::PlaneStrain, Section::Solid] {
            for ratio in [0.5, 2.0] {
                let m = mesh(4, 2, 2);
                let taper = Taper::new(ratio).unwrap();
                let text = deck(&scene.beam, &m, section, taper, &[[0.0, 1.0, 0.0]]);
                assert!(text.contains("** tapered"), "{text}");
                let nodes = node_coordinates(&text, Grid::new(&m).count);
                let (width, _) = modelled_width(&scene.beam, section);
                for x_node in [0.0, 0.25, 0.5, 0.75, 1.0].map(|f| f * l) {
                    let column: Vec<&[f64; 3]> = nodes
                        .iter()
                        .filter(|p| (p[0] - x_node).abs() < 1e-12)
                        .collect();
                    assert!(!column.is_empty());
                    let half = t0 * (1.0 - (1.0 - ratio) * x_node / l) / 2.0;
                    let (lo, hi) = column.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                        (lo.min(p[1]), hi.max(p[1]))
                    });
                    // Each section spans its own thickness, centred on the axis (to the
                    // deck's 13 significant digits) ...
                    let tol = 1e-11 * t0;
                    assert!(
                        (hi - half).abs() < tol && (lo + half).abs() < tol,
                        "{lo} {hi} {half}"
                    );
                    // ... and the width is untouched.
                    let widest = column.iter().map(|p| p[2]).fold(0.0, f64::max);
                    assert!(
                        (widest - width).abs() < 1e-11 * width,
                        "{widest} vs {width}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_uniform_taper_leaves_the_deck_unmarked() {
        let scene = Scene::builtin();
        let text = deck(
            &scene.beam,
            &mesh(3, 1, 1),
            Section::PlaneStress,
            Taper::UNIFORM,
            &[[0.0, 1.0, 0.0]],
        );
        assert!(!text.contains("tapered"));
        assert!(text.starts_with("** prbfit: plane-stress model"));
        assert!(text.contains("C3D20R bricks (length x thickness x modelled width 1e-2 m)\n*HEADING\nprbfit beam\n*NODE\n"), "{text}");
    }
}
