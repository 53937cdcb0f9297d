//! How far a wide section is from the narrow beam (plane stress, `E I`) towards the plate
//! (plane strain, `E I / (1 - nu^2)`): the *plate fraction* `phi`, 0 for the beam and 1 for
//! the plate, the share of the stiffening `nu^2 / (1 - nu^2)` a section shows.
//!
//! A bent strip curls across its width (anticlastic curvature, `-nu` times the curvature
//! along it) as a narrow beam does; whatever stops it from curling makes it stiffer, up to the
//! plate modulus. Two things do:
//!
//! - **Large curvature** (Searle 1908; Ashwell 1950): the curl across a width `b` lifts the
//!   edges by about `nu b^2 / (8 R)`, and the longitudinal fibres there, stretched and
//!   squeezed by that lift times the curvature `1 / R`, pull the section flat. Only the
//!   parameter `b^2 / (R t)` (Searle's) matters: the curl is an elastic-foundation problem
//!   `D w'''' + E t w / R^2 = 0` across the width with free edges, whose solution gives the
//!   bending stiffness `E I (1 - nu^2 Phi(lambda)) / (1 - nu^2)` with
//!   `lambda = (3 (1 - nu^2))^(1/4) sqrt(b^2 / (R t)) / 2` and `Phi = <g''^2>`, the mean
//!   square of the curl's curvature normalised by its free-edge value
//!   ([`anticlastic_fraction`] is `1 - Phi`). Beam-like below `b^2 / (R t)` of about 1,
//!   plate-like above about 20. A. D. S. Searle, *Experimental Elasticity*, Cambridge 1908;
//!   G. D. Ashwell, "The anticlastic curvature of rectangular beams and plates", J. Royal
//!   Aeronautical Society 54 (1950) 708-715.
//! - **The ends**: a clamp, and the rigid body bolted to the tip, hold the section flat, and
//!   the flattening fades over a length of the order of the width, so even at small loads a
//!   strip as wide as a good part of its length is stiffer; a thick section (width a few
//!   thicknesses) is less of a plate and stiffens less. [`ends_fraction`]
//!   `= 1 - exp(-0.92 (b / L) (1 - exp(-b / (2.8 t))))` is a fit to prbfit's own 3D FEA
//!   (`prbfit fea --section solid`, C3D20R, clamped root and rigid tip, tip rotation under a
//!   small transverse force `alpha_y = 0.1`), no literature giving it: measured plate
//!   fractions (fit in brackets)
//!
//!   | b / t | b / L | nu   | measured | fit  |
//!   |-------|-------|------|----------|------|
//!   | 10    | 0.25  | 0.3  | 0.20     | 0.20 |
//!   | 10    | 0.33  | 0.3  | 0.27     | 0.26 |
//!   | 10    | 0.67  | 0.3  | 0.47     | 0.45 |
//!   | 10    | 0.67  | 0.49 | 0.51     | 0.45 |
//!   | 30    | 2     | 0.3  | 0.83     | 0.84 |
//!   | 3.3   | 0.83  | 0.3  | 0.41     | 0.41 |
//!   | 3.3   | 0.83  | 0.49 | 0.42     | 0.41 |
//!
//! The anticlastic part is averaged along the beam with the weight of the bending compliance
//! `M(s)^2` (the curvature varies along a beam under a tip force), and the two parts are
//! combined by [`combined_fraction`]: the mean of the larger of the two (which the 3D FEA
//! shows to underestimate, by up to 0.13) and of the two as independent restraints,
//! `1 - (1 - a)(1 - b)` (which overestimates, by up to 0.12). Measured on the strips of the
//! table under tip moments (`tests/fea.rs` prints it):
//!
//! | b / t | b / L | beta | measured | max  | independent | combined |
//! |-------|-------|------|----------|------|-------------|----------|
//! | 10    | 0.25  | 1.5  | 0.39     | 0.29 | 0.43        | 0.36     |
//! | 10    | 0.67  | 0.75 | 0.58     | 0.45 | 0.67        | 0.56     |
//! | 10    | 0.67  | 1.5  | 0.68     | 0.64 | 0.80        | 0.72     |
//! | 30    | 2     | 1.5  | 0.89     | 0.88 | 0.98        | 0.93     |
//!
//! **Guided flexures** (DESIGN §13). A flexure clamped to the ground and to a stage that
//! keeps its tip from turning (a parallel stage's, a fixed-guided segment) is held flat at
//! both ends and bent in an S: its bending moment peaks at *both* held ends, so more of its
//! bending compliance lies where the ends flatten the section (within one width of an end:
//! 87 % of it for `b / L = 1/4`, against 58 % for a cantilever under a tip force), and it
//! stiffens far more than the cantilever's rule says. [`guided_ends_fraction`]
//! `= 1 - exp(-2.06 (b / L)^0.84 (1 - exp(-b / (2.4 t))))` is a fit to prbfit's own 3D FEA
//! of mechanisms (`prbfit fea --section solid` on a parallel stage of two such flexures
//! pushed sideways by `alpha_y = 0.2`, so only the ends act): the plate fraction is
//! `(1 - dy_solid / dy_plane_stress) / (nu^2 s_b)`, the two FEA runs on the same bricks
//! along and through (their mesh errors cancel in part) and `s_b` the bending share of the
//! beam mechanism's compliance (shear excluded). `tests/fea_mech.rs`
//! (`guided_flexure_plate_fraction_sweep`, `--ignored`) prints it. Measured (mesh density
//! `n` = bricks along; the fit's stiffness gap `nu^2 |phi - fit| / (1 - nu^2 phi)`):
//!
//! | b / t | b / L | nu   | n  | measured | coarser mesh   | cantilever's rule | fit  | gap    |
//! |-------|-------|------|----|----------|----------------|-------------------|------|--------|
//! | 10    | 0.25  | 0.3  | 80 | 0.43     | 0.46 (40), 0.50 (20) | 0.20        | 0.47 | 0.36 % |
//! | 30    | 0.25  | 0.3  | 80 | 0.48     | 0.50 (40)      | 0.21              | 0.47 | 0.06 % |
//! | 10    | 0.5   | 0.3  | 40 | 0.67     |                | 0.36              | 0.68 | 0.12 % |
//! | 10    | 0.67  | 0.49 | 60 | 0.78     | 0.84 (30)      | 0.45              | 0.76 | 0.36 % |
//! | 10    | 1     | 0.3  | 30 | 0.83     |                | 0.59              | 0.87 | 0.35 % |
//! | 3.3   | 0.83  | 0.3  | 24 | 0.74     |                | 0.41              | 0.74 | 0.02 % |
//! | 30    | 2     | 0.3  | 30 | 0.95     |                | 0.84              | 0.98 | 0.30 % |
//!
//! The fit holds every measurement within 0.4 % of stiffness (the cantilever's rule would
//! miss them by 2-5 %). The measurements are not mesh-converged: the 3D model's fraction
//! falls by 0.02-0.06 per halving of the bricks (the width's bricks refine with the others,
//! and the flattening's boundary layer at the clamps converges slowly), so the converged
//! fractions may lie up to about 0.1 below the table. At `nu = 0.3` that is under 1 % of
//! stiffness; at `nu = 0.49` up to 2.4 %. A flexure pinned or coupled to the stage keeps
//! the cantilever's rule (its tip moment is zero: its bending peaks at the clamp alone), and
//! a clamped flexure bent mostly by a stage moment (a cross-axis pivot's) has a uniform
//! moment, between the two and not measured here: it takes the guided rule, an upper bound.
//! [`crate::scene::Flexure::model`] chooses.
//!
//! The plane-strain effect ([`crate::beam::Effects::plane_strain`]) is this fraction put to
//! use: a case's modulus is `E / (1 - nu^2 phi)`. [`crate::beam::BeamSolver`] follows a load
//! path as a narrow beam first, takes each case's fraction from that solution
//! ([`case_fraction`]) and solves the case at it, from the unloaded beam along the same ray
//! (so on the same branch). A beam solved without its own path (a mechanism's flexure) takes
//! the ends' fraction alone (the guided one when it is clamped to the stage). Against the 3D FEA the effect leaves at most 1 % of the gap in
//! stiffness (`tests/fea.rs`), where the plate modulus overshoots by 3-5 %.

/// The plate fraction the ends give a strip of width `b`, thickness `t` and length `L` (a
/// fit to 3D FEA, see the module docs).
pub fn ends_fraction(width_over_length: f64, width_over_thickness: f64) -> f64 {
    let plate_like = 1.0 - (-width_over_thickness.max(0.0) / 2.8).exp();
    1.0 - (-0.92 * width_over_length.max(0.0) * plate_like).exp()
}

/// The plate fraction the ends give a strip held flat at both ends and bent in an S by
/// them, as a flexure clamped to the ground and to a guided stage is (a parallel stage's),
/// of width `b`, thickness `t` and length `L`: a fit to 3D FEA of guided pairs (see the
/// module docs), `1 - exp(-GUIDED_SCALE (b / L)^GUIDED_POWER (1 - exp(-b / (GUIDED_THICK t))))`.
pub fn guided_ends_fraction(width_over_length: f64, width_over_thickness: f64) -> f64 {
    let plate_like = 1.0 - (-width_over_thickness.max(0.0) / GUIDED_THICK).exp();
    1.0 - (-GUIDED_SCALE * width_over_length.max(0.0).powf(GUIDED_POWER) * plate_like).exp()
}

/// The guided rule's scale (see [`guided_ends_fraction`]).
pub const GUIDED_SCALE: f64 = 2.06;
/// The guided rule's power of `b / L`.
pub const GUIDED_POWER: f64 = 0.84;
/// The guided rule's thickness scale: the section is plate-like beyond a few of these.
pub const GUIDED_THICK: f64 = 2.4;

/// The plate fraction of a load case from its ends' and anticlastic fractions: the mean of
/// their maximum and of `1 - (1 - ends)(1 - anticlastic)` (fitted to 3D FEA, see the module
/// docs). Either alone is returned as it is when the other is zero.
pub fn combined_fraction(ends: f64, anticlastic: f64) -> f64 {
    let independent = 1.0 - (1.0 - ends) * (1.0 - anticlastic);
    0.5 * (ends.max(anticlastic) + independent)
}

/// The plate fraction of one load case of a strip `w0 / t0 = width_ratio` wide, from its
/// solution as a narrow beam (plane stress): the anticlastic fraction at each shape point's
/// Searle parameter `w0^2 / (R t0)`, averaged along the beam with the weight of the bending
/// compliance `M(s)^2`, combined with the ends' ([`combined_fraction`]). Also returns the
/// largest Searle parameter along the beam.
pub fn case_fraction(
    width_ratio: f64,
    slenderness: f64,
    nu: f64,
    solution: &super::BeamSolution,
) -> (f64, f64) {
    let (w_t, w_l) = (width_ratio, width_ratio / slenderness);
    let ends = ends_fraction(w_l, w_t);
    let (ax, ay, be) = (
        solution.load.alpha_x,
        solution.load.alpha_y,
        solution.load.beta,
    );
    let tip = solution.tip;
    // The bending moment (E I0 / L) at a point is the curvature there times L; Searle's
    // parameter is w0^2 / (R t0) = (w0 / t0) (w0 / L) (L / R). A solution sampled without its
    // shape has the root and the tip.
    let root = super::ShapePoint {
        s: 0.0,
        x: 0.0,
        y: 0.0,
        psi: 0.0,
    };
    let tip_point = super::ShapePoint {
        s: 1.0,
        x: tip.a,
        y: tip.b,
        psi: tip.phi,
    };
    let ends_only = [root, tip_point];
    let points: &[super::ShapePoint] = if solution.shape.len() >= 2 {
        &solution.shape
    } else {
        &ends_only
    };
    let (mut weighted, mut weight, mut largest) = (0.0, 0.0, 0.0_f64);
    let n = points.len();
    for (i, p) in points.iter().enumerate() {
        let m = be + ay * (tip.a - p.x) - ax * (tip.b - p.y);
        let searle = w_t * w_l * m.abs();
        largest = largest.max(searle);
        // Trapezoid weights over the uniformly spaced points.
        let w = if i == 0 || i + 1 == n { 0.5 } else { 1.0 } * m * m;
        weighted += w * anticlastic_fraction(ashwell_lambda(searle, nu));
        weight += w;
    }
    let anticlastic = if weight > 0.0 { weighted / weight } else { 0.0 };
    (combined_fraction(ends, anticlastic), largest)
}

/// Ashwell's `lambda` for Searle's parameter `b^2 / (R t)` and Poisson's ratio `nu`.
pub fn ashwell_lambda(searle: f64, nu: f64) -> f64 {
    (3.0 * (1.0 - nu * nu)).powf(0.25) * searle.max(0.0).sqrt() / 2.0
}

/// The plate fraction `1 - Phi(lambda)` of a strip bent to a uniform curvature, from the
/// anticlastic curl's solution `g = A cosh(l e) cos(l e) + B sinh(l e) sin(l e)` across the
/// half-width `e in [0, 1]` with the free-edge conditions `g''(1) = 1`, `g'''(1) = 0`.
/// `Phi = <g''^2>` (by parts from the curl's equation); beyond `lambda = 15` its boundary-layer
/// form `3 / (4 lambda)` (the two agree to 1e-5 there).
pub fn anticlastic_fraction(lambda: f64) -> f64 {
    if lambda.is_nan() || lambda <= 1e-3 {
        return 0.0;
    }
    if lambda > 15.0 {
        return 1.0 - 0.75 / lambda;
    }
    let l = lambda;
    // The edge values of C = cosh cos and S = sinh sin (of l e at e = 1): their second and
    // third derivatives.
    let (ch, sh) = (l.cosh(), l.sinh());
    let (s, c) = l.sin_cos();
    let c2 = -2.0 * l * l * sh * s;
    let s2 = 2.0 * l * l * ch * c;
    let c3 = -2.0 * l * l * l * (ch * s + sh * c);
    let s3 = 2.0 * l * l * l * (sh * c - ch * s);
    // [c2 s2; c3 s3] [A; B] = [1; 0].
    let det = c2 * s3 - s2 * c3;
    let (a, b) = (s3 / det, -c3 / det);
    // Phi = <(A C'' + B S'')^2> = 4 l^4 <(B cosh cos - A sinh sin)^2> over e in [0, 1], in
    // closed form: with x = l e and u = 2 l, the squares and the product are sums of cosh 2x,
    // cos 2x and their products, whose means over [0, 1] are
    //   <cosh 2x> = sinh u / u,  <cos 2x> = sin u / u,
    //   <cosh 2x cos 2x> = (sinh u cos u + cosh u sin u) / (2 u),
    //   <sinh 2x sin 2x> = (cosh u sin u - sinh u cos u) / (2 u).
    // Six transcendental calls instead of a quadrature's thousands: a wide section's every
    // case evaluates this at each of its shape points.
    let u = 2.0 * l;
    let (ch2, sh2) = (u.cosh(), u.sinh());
    let (s2u, c2u) = u.sin_cos();
    let mean_cosh = sh2 / u;
    let mean_cos = s2u / u;
    let mean_cosh_cos = (sh2 * c2u + ch2 * s2u) / (2.0 * u);
    let mean_sinh_sin = (ch2 * s2u - sh2 * c2u) / (2.0 * u);
    // sinh^2 sin^2 = (cosh 2x - 1)(1 - cos 2x) / 4, cosh^2 cos^2 = (cosh 2x + 1)(1 + cos 2x) / 4,
    // sinh cosh sin cos = sinh 2x sin 2x / 4.
    let ss = 0.25 * (mean_cosh - mean_cosh_cos - 1.0 + mean_cos);
    let cc = 0.25 * (mean_cosh + mean_cosh_cos + 1.0 + mean_cos);
    let sc = 0.25 * mean_sinh_sin;
    let phi = 4.0 * l.powi(4) * (a * a * ss + b * b * cc - 2.0 * a * b * sc);
    (1.0 - phi).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form of `Phi` against the quadrature it replaced (composite Simpson with
    /// 4000 panels: its error, `h^4` times the integrand's fourth derivative of order
    /// `lambda^4`, is below 1e-11 up to `lambda = 15`), and its boundary-layer limit at the
    /// switch.
    #[test]
    fn the_closed_form_is_the_quadrature() {
        let simpson = |l: f64| {
            let d23 = |e: f64| {
                let (ch, sh) = ((l * e).cosh(), (l * e).sinh());
                let (s, c) = (l * e).sin_cos();
                (
                    -2.0 * l * l * sh * s,
                    2.0 * l * l * ch * c,
                    -2.0 * l * l * l * (ch * s + sh * c),
                    2.0 * l * l * l * (sh * c - ch * s),
                )
            };
            let (c2, s2, c3, s3) = d23(1.0);
            let det = c2 * s3 - s2 * c3;
            let (a, b) = (s3 / det, -c3 / det);
            let n = 4000;
            let h = 1.0 / n as f64;
            let sum: f64 = (0..=n)
                .map(|k| {
                    let (c2, s2, _, _) = d23(k as f64 * h);
                    let g2 = a * c2 + b * s2;
                    let w = if k == 0 || k == n {
                        1.0
                    } else {
                        (2 + 2 * (k % 2)) as f64
                    };
                    w * g2 * g2
                })
                .sum();
            (1.0 - sum * h / 3.0).clamp(0.0, 1.0)
        };
        let mut l = 0.01;
        while l < 15.0 {
            let (closed, quad) = (anticlastic_fraction(l), simpson(l));
            // Below lambda ~ 0.1 the fraction (~ lambda^4 / 10) is 1 - Phi with Phi ~ 1: both
            // lose the same digits to that subtraction.
            assert!(
                (closed - quad).abs() < 1e-9,
                "lambda {l}: {closed} vs {quad}"
            );
            l *= 1.1;
        }
        assert!((anticlastic_fraction(15.0) - (1.0 - 0.75 / 15.0)).abs() < 2e-5);
    }

    #[test]
    fn the_limits_are_the_beam_and_the_plate() {
        assert_eq!(anticlastic_fraction(0.0), 0.0);
        assert!(anticlastic_fraction(0.1) < 1e-4);
        assert!(anticlastic_fraction(1000.0) > 0.999);
        assert_eq!(ends_fraction(0.0, 10.0), 0.0);
        assert!(ends_fraction(10.0, 100.0) > 0.9998);
        // The fitted table of the module docs.
        for (b_t, b_l, fit) in [
            (10.0, 0.25, 0.20),
            (10.0, 2.0 / 3.0, 0.45),
            (30.0, 2.0, 0.84),
            (10.0 / 3.0, 0.8333, 0.41),
        ] {
            assert!((ends_fraction(b_l, b_t) - fit).abs() < 0.006, "{b_t} {b_l}");
        }
    }

    /// The guided rule of the module docs: its fit column, and the measured fractions (3D
    /// FEA, `tests/fea_mech.rs`) within its stated stiffness gap of 0.4 %.
    #[test]
    fn the_guided_rule_meets_its_table() {
        for (b_t, b_l, nu, measured, fit) in [
            (10.0, 0.25, 0.3, 0.431, 0.469),
            (30.0, 0.25, 0.3, 0.481, 0.474),
            (10.0, 0.5, 0.3, 0.665, 0.678),
            (10.0, 2.0 / 3.0, 0.49, 0.776, 0.764),
            (10.0, 1.0, 0.3, 0.833, 0.868),
            (10.0 / 3.0, 0.8333, 0.3, 0.737, 0.735),
            (30.0, 2.0, 0.3, 0.945, 0.975),
        ] {
            let got = guided_ends_fraction(b_l, b_t);
            assert!((got - fit).abs() < 0.001, "{b_t} {b_l}: {got}");
            let gap = nu * nu * (measured - got).abs() / (1.0 - nu * nu * got.max(measured));
            assert!(gap < 0.004, "{b_t} {b_l}: gap {gap}");
            // Stiffer than the cantilever's ends: held at both ends.
            assert!(got > ends_fraction(b_l, b_t));
        }
        assert_eq!(guided_ends_fraction(0.0, 10.0), 0.0);
    }

    #[test]
    fn quadrature_meets_the_boundary_layer_form() {
        // Both sides of the switch at lambda = 15 agree.
        let below = anticlastic_fraction(14.999);
        let above = anticlastic_fraction(15.001);
        assert!((below - above).abs() < 1e-5, "{below} vs {above}");
        // Values checked against an independent solution (Gauss-Legendre, 200 points, of
        // <g''> - 4 lambda^4 <g^2>).
        for (lambda, expected) in [(1.0, 0.1489), (1.5, 0.4421), (2.0, 0.6341), (4.0, 0.8119)] {
            let got = anticlastic_fraction(lambda);
            assert!((got - expected).abs() < 1e-4, "lambda {lambda}: {got}");
        }
        // Monotone.
        let mut last = 0.0;
        for k in 1..200 {
            let v = anticlastic_fraction(k as f64 * 0.1);
            assert!(v >= last - 1e-12, "at {}", k as f64 * 0.1);
            last = v;
        }
    }
}
#[cfg(test)]
mod shape_tests {
    use crate::beam::{BeamModel, BeamSolver, Effects, Load, Resolution};

    /// The shape returned ends at the tip returned, at any plate fraction (Newton's last
    /// update used to reach the tip only: with `phi >= 0.8` under this load the shape lagged
    /// it by 3e-6 L). The tip is good to about 10 tol.
    #[test]
    fn the_shape_ends_at_the_tip_at_every_plate_fraction() {
        let e = Effects::NONE.with_plane_strain(true);
        for phi in [0.0, 0.5, 0.8, 0.9, 1.0] {
            let m = BeamModel::new(100.0, 0.3, None, e)
                .unwrap()
                .with_plate_fraction(phi);
            let sol = BeamSolver::new(m, Resolution::default())
                .unwrap()
                .solve(Load::new(-1.0, -2.0, -0.5))
                .unwrap();
            let end = sol.shape.last().unwrap();
            let gap = (sol.tip.a - end.x)
                .abs()
                .max((sol.tip.b - end.y).abs())
                .max((sol.tip.phi - end.psi).abs());
            assert!(gap < 1e-8, "phi {phi}: the shape ends {gap} from the tip");
        }
    }
}
