//! The one description of a PRB chain that every simulator format writes: links with their
//! lengths, masses and inertias, and the joints between them, in SI units, laid along +x from
//! the clamp at the origin with revolute joints about +z.
//!
//! A segment `n` (1-based) is the link `segment{n}`. Its root end carries the revolute joint
//! `theta{n}` (a torsion spring), or the fixed joint `fixed{n}` when it has none; an extension
//! spring adds the prismatic joint `delta{n}` along the segment, which needs a tiny
//! intermediate link `segment{n}_hinge` in formats whose joints connect exactly two links
//! (URDF, SDF); MJCF puts both joints in one body. The free end carries the `tip` frame.
//!
//! Masses are the matrix's (DESIGN §10): segment i carries `mu_i rho A0 L` at its middle (a
//! three-column matrix: `mu_i = gamma_i`), its inertia about the bending axis (z) a uniform
//! rod's `m (gamma_i L)^2 / 12`, exactly the PRB model whose frequencies prbfit computes; about
//! x and y `m (l^2 + w^2) / 12` (they do not enter planar motion). A cantilever's tip body ([`Body`],
//! `[tip]`) is added to the last segment's (its centre of mass at the tip, parallel axis
//! theorem), so every format carries it without an extra link.
//!
//! # The mass floor
//! Simulators refuse a massless moving link (MuJoCo: `mass and inertia of moving bodies must
//! be larger than mjMINVAL`), and a fit may let a mu fall to `e^-20` of the beam's mass. Every
//! link's mass is at least [`MASS_FLOOR`] of the model's total mass `M` (the beam's `rho A0 L`
//! and the tip body's), and its inertia about each axis at least [`MASS_FLOOR`] of
//! `M L^2 / 12` (the whole beam's as a rod). Why `1e-6`: it moves the model's frequencies by
//! about 1e-6 relative at most (a mass added where the mode moves at most as much as the
//! tip), four orders below the 0.5 % the MuJoCo test asks and the fits' frequency errors, yet
//! keeps the fastest local mode of a floored link between two springs within about
//! `sqrt(k 12 / 1e-6) ~ 3e3 sqrt(k)` of the beam's unit frequency, so the time step
//! ([`time_step`]) stays practical; a plain `1e-9` of the mass made its inertia `1e-17 kg
//! m^2` for a steel blade, which MuJoCo refuses, and its frequency `3e4` times higher.

use crate::prb::PrbMatrix;
use crate::scene::{BeamSpec, Body};
use crate::si::si_model;

/// Length of the intermediate link of a segment with an extension spring, as a fraction of L
/// (massless in effect; it only gives the prismatic joint a parent).
pub const HINGE_LINK_FRACTION: f64 = 1e-6;

/// Mass, centre of mass and principal inertias (about the centre of mass, along x, y, z) of a
/// link.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// kg
    pub mass: f64,
    /// The centre of mass along the link from its root end, m.
    pub com: f64,
    /// kg m^2 about x, y, z.
    pub inertia: [f64; 3],
}

/// One segment of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainSegment {
    /// 1-based, root first.
    pub index: usize,
    /// Distance of the segment's root end from the clamp along x, m (unloaded).
    pub start_x: f64,
    /// m
    pub length: f64,
    /// Stiffness of the revolute joint at the root end, N m/rad; `None`: fixed.
    pub hinge: Option<f64>,
    /// Stiffness of the prismatic joint along the segment, N/m; `None`: rigid.
    pub slide: Option<f64>,
    /// The segment's mass (its mu's share of the beam's, with the tip body on the last).
    pub mass: MassProperties,
}

impl ChainSegment {
    /// The link's name.
    pub fn link(&self) -> String {
        format!("segment{}", self.index)
    }

    /// The intermediate link between the revolute and the prismatic joint.
    pub fn hinge_link(&self) -> String {
        format!("segment{}_hinge", self.index)
    }

    /// The link the root-end joint moves: the intermediate one when there is a slide.
    pub fn first_child(&self) -> String {
        if self.slide.is_some() {
            self.hinge_link()
        } else {
            self.link()
        }
    }

    /// The revolute joint's name (`theta{n}`), or the fixed joint's (`fixed{n}`).
    pub fn root_joint(&self) -> String {
        match self.hinge {
            Some(_) => format!("theta{}", self.index),
            None => format!("fixed{}", self.index),
        }
    }

    /// The prismatic joint's name.
    pub fn slide_joint(&self) -> String {
        format!("delta{}", self.index)
    }
}

/// A PRB chain ready to be written.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// The model's name in the file (`prbfit_l_r_r_r`).
    pub name: String,
    /// Beam length L, m (sets the scale of small links and limits).
    pub beam_length: f64,
    /// Section width, m.
    pub width: f64,
    /// Section thickness, m.
    pub thickness: f64,
    /// Root first.
    pub segments: Vec<ChainSegment>,
    /// The intermediate links' mass properties.
    pub hinge_link_mass: MassProperties,
}

impl Chain {
    /// The chain of `matrix` for `beam` of `density` (kg/m^3), `tip` bolted to its free end.
    pub fn new(matrix: &PrbMatrix, beam: &BeamSpec, density: f64, tip: &Body) -> Chain {
        let si = si_model(matrix, beam);
        let beam_mass = density * beam.area() * beam.length;
        let total = beam_mass + tip.mass;
        let floor = Floor {
            mass: MASS_FLOOR * total,
            inertia: MASS_FLOOR * total * beam.length * beam.length / 12.0,
        };
        let mut start_x = 0.0;
        let n = si.segments.len();
        let segments = si
            .segments
            .iter()
            .zip(matrix.rows())
            .enumerate()
            .map(|(i, (s, row))| {
                let mut props = rod_mass(beam, row.mass() * beam_mass, s.length);
                if i + 1 == n && !tip.is_none() {
                    props = with_tip(props, s.length, tip);
                }
                let props = floor.apply(props);
                let seg = ChainSegment {
                    index: i + 1,
                    start_x,
                    length: s.length,
                    hinge: s.k_theta,
                    slide: s.k_ex,
                    mass: props,
                };
                start_x += s.length;
                seg
            })
            .collect();
        let boxed = |length: f64| rod_mass(beam, density * length * beam.area(), length);
        Chain {
            name: format!("prbfit_{}", ident(&matrix.topology())),
            beam_length: beam.length,
            width: beam.width,
            thickness: beam.thickness,
            segments,
            hinge_link_mass: floor.apply(boxed(HINGE_LINK_FRACTION * beam.length)),
        }
    }

    /// The length of the intermediate links, m.
    pub fn hinge_link_length(&self) -> f64 {
        HINGE_LINK_FRACTION * self.beam_length
    }
}

/// The least mass and inertia of a moving link (module docs, [`MASS_FLOOR`]).
pub const MASS_FLOOR: f64 = 1e-6;

/// The least mass (kg) and inertia (kg m^2, about each axis) a link is given.
struct Floor {
    mass: f64,
    inertia: f64,
}

impl Floor {
    /// `link` with its mass and each inertia raised to the floor (the centre kept).
    fn apply(&self, link: MassProperties) -> MassProperties {
        MassProperties {
            mass: link.mass.max(self.mass),
            com: link.com,
            inertia: link.inertia.map(|i| i.max(self.inertia)),
        }
    }
}

/// A link of `mass` spread along `length` (a zero length is taken as 1e-9 L so that no
/// simulator sees a massless body): its centre in the middle, about z a uniform rod's
/// `m l^2 / 12` (DESIGN §10's PRB segment), about x and y `m (l^2 + w^2) / 12`
/// (out of the plane: only the simulators' inertia checks see them).
fn rod_mass(beam: &BeamSpec, mass: f64, length: f64) -> MassProperties {
    let length = length.max(1e-9 * beam.length);
    let w = beam.width;
    MassProperties {
        mass,
        com: length / 2.0,
        // About x and y `m (l^2 + w^2) / 12`: with z's `m l^2 / 12` the triangle inequality a
        // simulator checks (MuJoCo: A + B >= C, each way) holds with a margin of `m l^2 / 12`
        // for every length, the tiny hinge links' too (a box's would not beside the rod's z).
        inertia: [
            mass * (length * length + w * w) / 12.0,
            mass * (length * length + w * w) / 12.0,
            mass * length * length / 12.0,
        ],
    }
}

/// MuJoCo's stability bound on `omega dt` for a spring of frequency `omega`: its default
/// integrator (semi-implicit Euler, explicit in the springs' forces) is stable only for
/// `omega dt < 2`.
pub const STABILITY_BOUND: f64 = 2.0;

/// The single chain's `omega_max dt`: a tenth of [`STABILITY_BOUND`]. The highest mode's
/// frequency is then off by `(omega dt)^2 / 24 < 0.2 %`, the first mode's by far less (it is
/// slower by the ratio of the two, squared).
pub const CHAIN_STEP: f64 = 0.2;

/// The mechanism's `omega_max dt`, 1/200 of [`STABILITY_BOUND`]: its closures' time
/// constant is two time steps and must be far faster than every spring
/// ([`super::mjcf_mech`]'s docs).
pub const STEP_FRACTION: f64 = 0.01;

/// Beyond this many time steps per period of the model's lowest mode the export is refused
/// ([`time_step`]): a MuJoCo run of ten periods would take 1e8 steps.
pub const MAX_STEPS_PER_PERIOD: f64 = 1e7;

/// The chain's lowest and highest natural frequencies (rad/s) as written: clamped at the
/// root, free at the tip, in the unloaded straight pose, each link with its (floored) mass
/// and inertia, the revolute and prismatic joints with their springs and nothing else (an
/// MJCF body's slide moves the whole body). In the straight pose the bending (hinges) and
/// the axial motion (slides) decouple; each is `K q = omega^2 M q` with `K` the diagonal of
/// the springs and `M` the links' kinetic energy, solved by Cholesky (`M = C C^T`) and the
/// symmetric eigenvalues of `C^-1 K C^-T`, which keeps the largest to round-off relative to
/// itself. `None` for a chain without springs.
pub fn frequency_range(chain: &Chain) -> Option<(f64, f64)> {
    let segs = &chain.segments;
    // Each body's centre of mass along x from the clamp.
    let centre: Vec<f64> = segs.iter().map(|s| s.start_x + s.mass.com).collect();
    let mut lo = f64::INFINITY;
    let mut hi = 0.0_f64;
    let hinges: Vec<(usize, f64)> = segs
        .iter()
        .enumerate()
        .filter_map(|(i, s)| s.hinge.map(|k| (i, k)))
        .collect();
    let slides: Vec<(usize, f64)> = segs
        .iter()
        .enumerate()
        .filter_map(|(i, s)| s.slide.map(|k| (i, k)))
        .collect();
    let bending = |a: usize, b: usize| -> f64 {
        let (xa, xb) = (segs[a].start_x, segs[b].start_x);
        (a.max(b)..segs.len())
            .map(|i| {
                segs[i].mass.mass * (centre[i] - xa) * (centre[i] - xb) + segs[i].mass.inertia[2]
            })
            .sum()
    };
    let axial = |a: usize, b: usize| -> f64 { segs[a.max(b)..].iter().map(|s| s.mass.mass).sum() };
    for (joints, mass) in [
        (&hinges, &bending as &dyn Fn(usize, usize) -> f64),
        (&slides, &axial),
    ] {
        let n = joints.len();
        if n == 0 {
            continue;
        }
        let m = nalgebra::DMatrix::from_fn(n, n, |r, c| mass(joints[r].0, joints[c].0));
        let c = m.cholesky()?.unpack();
        let c_inv = c.try_inverse()?;
        let k = nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_iterator(
            n,
            joints.iter().map(|j| j.1),
        ));
        let a = &c_inv * k * c_inv.transpose();
        let a = (&a + a.transpose()) * 0.5;
        for w2 in a.symmetric_eigenvalues().iter() {
            let w = w2.max(0.0).sqrt();
            lo = lo.min(w);
            hi = hi.max(w);
        }
    }
    (hi > 0.0 && hi.is_finite() && lo > 0.0).then_some((lo, hi))
}

/// Why a model cannot be simulated at a practical time step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TooStiff {
    /// The time steps one period of the lowest mode would take.
    pub steps_per_period: f64,
    /// The highest over the lowest natural frequency.
    pub ratio: f64,
}

/// The MJCF time step for `chains` at `omega_max dt = fraction` ([`CHAIN_STEP`] for the
/// single chain, [`STEP_FRACTION`] for a mechanism), `omega_max` the highest natural
/// frequency of any of them as written ([`frequency_range`]). For a mechanism each flexure's
/// chain is taken clamped at its root and free at its tip, without the stage and the
/// couplers: the closures only confine the motion and the stage only adds mass, and neither
/// raises the highest frequency (Rayleigh's principle: the largest Rayleigh quotient over a
/// subspace, or with more kinetic energy, is no larger), so the bound holds for the whole
/// mechanism too. `Err` when one period of the lowest mode (a chain's own) would take more
/// than [`MAX_STEPS_PER_PERIOD`] steps: a floored link between stiff springs (raise its mu).
pub fn time_step(chains: &[Chain], fraction: f64) -> Result<f64, TooStiff> {
    let mut omega_max = 0.0_f64;
    let mut omega_min = f64::INFINITY;
    for chain in chains {
        match frequency_range(chain) {
            Some((lo, hi)) => {
                omega_max = omega_max.max(hi);
                omega_min = omega_min.min(lo);
            }
            // Springs whose frequencies do not come out (masses or stiffnesses past what a
            // double holds): no step can be chosen, and a default one would be a guess.
            None if chain
                .segments
                .iter()
                .any(|s| s.hinge.is_some() || s.slide.is_some()) =>
            {
                return Err(TooStiff {
                    steps_per_period: f64::INFINITY,
                    ratio: f64::INFINITY,
                });
            }
            None => {}
        }
    }
    if omega_max == 0.0 {
        // No springs at all (a valid matrix has one); this only keeps the file loadable.
        return Ok(1e-3);
    }
    let dt = fraction / omega_max;
    let steps_per_period = 2.0 * std::f64::consts::PI / omega_min / dt;
    if steps_per_period > MAX_STEPS_PER_PERIOD {
        return Err(TooStiff {
            steps_per_period,
            ratio: omega_max / omega_min,
        });
    }
    Ok(dt)
}

/// `link` of `length` with `tip` (its centre of mass at the link's end) added: the combined
/// mass, centre and inertias about the combined centre (parallel axis theorem; the body's
/// own inertia about each axis taken as its given one).
fn with_tip(link: MassProperties, length: f64, tip: &Body) -> MassProperties {
    let mass = link.mass + tip.mass;
    let com = (link.mass * link.com + tip.mass * length) / mass;
    let (d_link, d_tip) = (link.com - com, length - com);
    let shift = link.mass * d_link * d_link + tip.mass * d_tip * d_tip;
    MassProperties {
        mass,
        com,
        inertia: [
            link.inertia[0] + tip.inertia,
            link.inertia[1] + tip.inertia + shift,
            link.inertia[2] + tip.inertia + shift,
        ],
    }
}

/// A name safe for XML ids and ROS names.
pub fn ident(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect()
}

/// A number as every format writes it: Rust's shortest exponent form, which round-trips.
pub fn g(v: f64) -> String {
    format!("{v:e}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Links carry the mus' share of the beam's mass with a rod's inertia about z; the tip
    /// body joins the last link by the parallel axis theorem.
    #[test]
    fn links_carry_the_mus_and_the_tip_body() {
        let beam = crate::scene::Scene::builtin().beam;
        let m = PrbMatrix::parse("0.15,inf,inf,0.25; 0.85,2.2525,inf,0.75").unwrap();
        let total = 7850.0 * beam.area() * beam.length;
        let chain = Chain::new(&m, &beam, 7850.0, &Body::default());
        let link = chain.segments[1].mass;
        let l = 0.85 * beam.length;
        assert!((link.mass - 0.75 * total).abs() < 1e-15 * total);
        assert!((link.com - l / 2.0).abs() < 1e-15);
        assert!((link.inertia[2] - link.mass * l * l / 12.0).abs() < 1e-12 * link.inertia[2]);
        let tip = Body {
            mass: link.mass,
            inertia: 1e-9,
        };
        let with = Chain::new(&m, &beam, 7850.0, &tip).segments[1].mass;
        // Two equal masses at l/2 and l: centre at 3l/4, each l/4 from it.
        assert!((with.mass - 2.0 * link.mass).abs() < 1e-15);
        assert!((with.com - 0.75 * l).abs() < 1e-15);
        let want = link.inertia[2] + 1e-9 + 2.0 * link.mass * (l / 4.0).powi(2);
        assert!((with.inertia[2] - want).abs() < 1e-12 * want);
    }

    /// The MJCF chain's kinetic energy matrix by finite differences of its forward
    /// kinematics (body k: its hinge turns it about its origin, then its slide moves it along
    /// its own x; its child sits at its length along that x), independent of
    /// [`frequency_range`]'s closed form; with the springs' diagonal, every `omega^2`.
    fn omegas_by_kinematics(chain: &Chain) -> Vec<f64> {
        let segs = &chain.segments;
        let joints: Vec<(usize, bool, f64)> = segs
            .iter()
            .enumerate()
            .flat_map(|(i, s)| {
                let h = s.hinge.map(|k| (i, true, k));
                let x = s.slide.map(|k| (i, false, k));
                h.into_iter().chain(x)
            })
            .collect();
        let n = joints.len();
        // Each body's centre of mass and angle at joint values `q`.
        let pose = |q: &[f64]| -> Vec<[f64; 3]> {
            let (mut base, mut phi) = ([0.0_f64, 0.0_f64], 0.0_f64);
            let mut out = Vec::new();
            for (i, s) in segs.iter().enumerate() {
                let mut delta = 0.0;
                for (j, &(seg, hinge, _)) in joints.iter().enumerate() {
                    if seg == i && hinge {
                        phi += q[j];
                    } else if seg == i {
                        delta = q[j];
                    }
                }
                let (sn, cs) = phi.sin_cos();
                let origin = [base[0] + cs * delta, base[1] + sn * delta];
                out.push([
                    origin[0] + cs * s.mass.com,
                    origin[1] + sn * s.mass.com,
                    phi,
                ]);
                base = [origin[0] + cs * s.length, origin[1] + sn * s.length];
            }
            out
        };
        let h = 1e-7 * chain.beam_length;
        let rates: Vec<Vec<[f64; 3]>> = (0..n)
            .map(|j| {
                let (mut up, mut down) = (vec![0.0; n], vec![0.0; n]);
                up[j] = h;
                down[j] = -h;
                pose(&up)
                    .iter()
                    .zip(pose(&down))
                    .map(|(a, b)| std::array::from_fn(|c| (a[c] - b[c]) / (2.0 * h)))
                    .collect()
            })
            .collect();
        let mass = nalgebra::DMatrix::from_fn(n, n, |a, b| {
            segs.iter()
                .enumerate()
                .map(|(i, s)| {
                    let (va, vb) = (rates[a][i], rates[b][i]);
                    s.mass.mass * (va[0] * vb[0] + va[1] * vb[1])
                        + s.mass.inertia[2] * va[2] * vb[2]
                })
                .sum::<f64>()
        });
        let stiffness = nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_iterator(
            n,
            joints.iter().map(|j| j.2),
        ));
        let Some(inverse) = mass.try_inverse() else {
            panic!("a singular mass matrix")
        };
        let mut w2: Vec<f64> = (inverse * stiffness)
            .complex_eigenvalues()
            .iter()
            .map(|z| z.re)
            .collect();
        w2.sort_by(f64::total_cmp);
        w2
    }

    /// The light link between two springs (the audit's matrix) and a `mu = 0` row: every
    /// link keeps the floor's mass and inertia, the highest frequency is the exported chain's
    /// own (checked against its kinematics), and the time step keeps `omega_max dt` at
    /// [`CHAIN_STEP`], ten times inside MuJoCo's bound, where the old rule (each spring over
    /// the inertia beyond it, 1/100 of its `1 / omega`) left it above the bound.
    /// A chain with springs whose frequencies do not come out (a density no scene allows,
    /// 1e-300 kg/m^3: masses below a double's range, as `--density 1e-300` once gave) is
    /// refused, where the writer took a default step of 1e-3 s and said nothing.
    #[test]
    fn springs_without_frequencies_get_no_time_step() {
        let beam = crate::scene::Scene::builtin().beam;
        let m =
            PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf").unwrap();
        let chain = Chain::new(&m, &beam, 1e-300, &Body::default());
        assert!(frequency_range(&chain).is_none());
        let refused = time_step(std::slice::from_ref(&chain), CHAIN_STEP).unwrap_err();
        assert_eq!(refused.steps_per_period, f64::INFINITY);
        let said = super::super::ExportError::from(refused).to_string();
        assert!(said.contains("cannot be computed"), "{said}");
        // At a real density the same chain has its step.
        let chain = Chain::new(&m, &beam, 7850.0, &Body::default());
        assert!(time_step(std::slice::from_ref(&chain), CHAIN_STEP).unwrap() > 0.0);
    }

    #[test]
    fn the_time_step_keeps_a_light_link_inside_the_stability_bound() {
        let beam = crate::scene::Scene::builtin().beam;
        let rho = 7850.0;
        let total = rho * beam.area() * beam.length;
        for text in [
            "0.1,inf,inf,0.499998; 0.35,3.51,inf,1e-6; 0.4,2.99,inf,1e-6; 0.15,2.58,inf,0.5",
            "0.1,inf,inf,0.1; 0.35,3.51,inf,0; 0.4,2.99,inf,0.4; 0.15,2.58,inf,0.5",
            "0.1,inf,inf,0.25; 0.35,3.51,40,0; 0.4,2.99,inf,0.4; 0.15,2.58,inf,0.35",
        ] {
            let m = PrbMatrix::parse(text).unwrap();
            let chain = Chain::new(&m, &beam, rho, &Body::default());
            for s in &chain.segments {
                assert!(s.mass.mass >= MASS_FLOOR * total, "{text}");
                let least = MASS_FLOOR * total * beam.length * beam.length / 12.0;
                assert!(s.mass.inertia.iter().all(|&i| i >= least), "{text}");
                // MuJoCo's mjMINVAL is 1e-15: the steel blade's floor (4e-13) is far above it.
                assert!(least > 1e-13, "{least}");
            }
            let (lo, hi) = frequency_range(&chain).unwrap();
            let w2 = omegas_by_kinematics(&chain);
            // Finite differences at h = 1e-7 L: O(h^2) in M, round-off 1e-16 / 1e-14 in the
            // rates: 1e-6 covers both.
            assert!(
                (hi * hi / w2[w2.len() - 1] - 1.0).abs() < 1e-6,
                "{text}: {hi} {w2:?}"
            );
            assert!((lo * lo / w2[0] - 1.0).abs() < 1e-6, "{text}: {lo} {w2:?}");
            let dt = time_step(std::slice::from_ref(&chain), CHAIN_STEP).unwrap();
            assert!(hi * dt <= CHAIN_STEP * (1.0 + 1e-12), "{text}: {}", hi * dt);
            // The old rule: the fastest spring over the inertia beyond it.
            let mut old = 0.0_f64;
            for (i, s) in chain.segments.iter().enumerate() {
                let (mut inertia, mut d) = (0.0, 0.0);
                for t in &chain.segments[i..] {
                    let c = d + t.mass.com;
                    inertia += t.mass.inertia[2] + t.mass.mass * c * c;
                    d += t.length;
                }
                if let Some(k) = s.hinge {
                    old = old.max((k / inertia).sqrt());
                }
            }
            let old_dt = 0.01 / old;
            eprintln!(
                "{text}: omega_max {hi:.4e} rad/s, old rule's omega_max dt {:.3}",
                hi * old_dt
            );
            if text.contains("1e-6") {
                assert!(
                    hi * old_dt > STABILITY_BOUND,
                    "the audit's case: {}",
                    hi * old_dt
                );
            }
        }
    }

    /// With the floor out of reach, the chain as written is prbfit's PRB chain: its lowest
    /// frequency is [`crate::prb::PrbSolver::modes`]'s first, in SI.
    #[test]
    fn the_written_chain_rings_at_prbfits_first_frequency() {
        let beam = crate::scene::Scene::builtin().beam;
        let rho = 7850.0;
        let m =
            PrbMatrix::parse("0.1,inf,inf; 0.35,3.51,inf; 0.4,2.99,inf; 0.15,2.58,inf").unwrap();
        let tip = Body {
            mass: 0.0005,
            inertia: 1e-9,
        };
        let chain = Chain::new(&m, &beam, rho, &tip);
        let (lo, _) = frequency_range(&chain).unwrap();
        let rho_a = rho * beam.area();
        let unit =
            (beam.youngs_modulus * beam.second_moment() / (rho_a * beam.length.powi(4))).sqrt();
        let body = crate::prb::TipBody {
            mass: tip.mass / (rho_a * beam.length),
            inertia: tip.inertia / (rho_a * beam.length.powi(3)),
        };
        let prb = crate::prb::PrbSolver::new(&m, beam.model().axial_compliance());
        let first = prb
            .modes(crate::beam::Load::new(0.0, 0.0, 0.0), &[0.0; 3], body)
            .unwrap()[0]
            * unit;
        // Both are eigenvalues of 3x3 pencils of the same masses: round-off only.
        assert!((lo / first - 1.0).abs() < 1e-10, "{lo} vs {first}");
    }
}
