//! The equilibrium the modes are taken about, sampled at the quadrature's nodes.
//!
//! Under a dead tip force the internal force is the same vector `(alpha_x, alpha_y)` all
//! along the beam, so the statics of DESIGN §2 reduce to two states, `psi` and `M`, whose
//! slopes depend on them alone: `psi' = M / (E I)(N)`, `M' = -(1 + eps) Q + gamma N`, with
//! `N`, `Q` the force's components along and across the section. They are integrated from
//! the clamp with the statics' root moment by the classical Runge-Kutta method, landing on
//! every node, in steps of `0.02 / lambda` (`lambda` the larger of `sqrt|alpha|`, the
//! moments and 1: the fastest rate at which the shape turns), whose global error is about
//! 1e-9 (fourth order; the frequencies it moves by less, measured against steps four times
//! smaller). The root moment is then polished by the secant method until the tip moment is
//! the load's `beta` to 1e-12, so the sample does not inherit the statics' tolerance.
//!
//! Range: one shot spans the beam, and perturbations grow like `exp(sqrt(|alpha|))` along
//! it, so past forces of several hundred `E I / L^2` the polish cannot meet the tip moment
//! and the modes say so ([`ModesError::Equilibrium`]) rather than answer.

use super::super::{BeamModel, Load};
use super::ModesError;

/// One node's state: the equilibrium's fields and the section's tangent stiffness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NodeState {
    /// The section's rotation.
    pub psi: f64,
    /// Axial and shear strains.
    pub eps: f64,
    /// Shear strain.
    pub gamma: f64,
    /// Axial force.
    pub n: f64,
    /// Shear force.
    pub q: f64,
    /// The tangent stiffness `d(N, Q, M) / d(eps, gamma, kappa)` over the strains the
    /// model has (symmetrised), row-major; the rows and columns of absent strains are zero.
    pub d: [[f64; 3]; 3],
}

/// The equilibrium at the nodes, and its tip.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Sampled {
    /// One state per node.
    pub nodes: Vec<NodeState>,
    /// The root moment that holds the load (polished).
    pub root_moment: f64,
}

/// Slopes `(psi', M')` of the statics at `(psi, M)`.
fn slopes(model: &BeamModel, load: &Load, psi: f64, m: f64) -> Result<(f64, f64), ModesError> {
    let (s, c) = psi.sin_cos();
    let n = load.alpha_x * c + load.alpha_y * s;
    let q = -load.alpha_x * s + load.alpha_y * c;
    let (eps, gamma, stiffness) = model
        .section_strains(n, q)
        .ok_or(ModesError::MaterialLimit { axial_force: n })?;
    Ok((m / stiffness, -(1.0 + eps) * q + gamma * n))
}

/// Integrates from the clamp with root moment `m0`, recording `(psi, M)` at `nodes`
/// (ascending);
/// returns the tip moment.
fn shoot(
    model: &BeamModel,
    load: &Load,
    m0: f64,
    nodes: &[f64],
    out: &mut [(f64, f64)],
    step: f64,
) -> Result<f64, ModesError> {
    let (mut psi, mut m, mut s) = (0.0, m0, 0.0);
    for (k, &target) in nodes.iter().chain(std::iter::once(&1.0)).enumerate() {
        let len = target - s;
        let count = (len / step).ceil().max(1.0);
        let h = len / count;
        for _ in 0..count as usize {
            let (k1p, k1m) = slopes(model, load, psi, m)?;
            let (k2p, k2m) = slopes(model, load, psi + 0.5 * h * k1p, m + 0.5 * h * k1m)?;
            let (k3p, k3m) = slopes(model, load, psi + 0.5 * h * k2p, m + 0.5 * h * k2m)?;
            let (k4p, k4m) = slopes(model, load, psi + h * k3p, m + h * k3m)?;
            psi += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
            m += h / 6.0 * (k1m + 2.0 * k2m + 2.0 * k3m + k4m);
        }
        s = target;
        if k < out.len() {
            out[k] = (psi, m);
        }
        if !(psi.is_finite() && m.is_finite()) {
            return Err(ModesError::Equilibrium(
                "the shot from the clamp overflowed".to_string(),
            ));
        }
    }
    Ok(m)
}

/// The equilibrium under `load` with root moment about `m0`, at `nodes`.
pub(crate) fn sample(
    model: &BeamModel,
    load: &Load,
    m0: f64,
    nodes: &[f64],
) -> Result<Sampled, ModesError> {
    if !(load.is_finite() && m0.is_finite()) {
        return Err(ModesError::NotFinite("the load or root moment"));
    }
    let force = load.alpha_x.hypot(load.alpha_y);
    let rate = force.sqrt().max(m0.abs()).max(load.beta.abs()).max(1.0);
    let step = 0.02 / rate;
    let mut psi = vec![(0.0, 0.0); nodes.len()];
    let scale = 1.0 + load.beta.abs() + m0.abs();
    let mut m0 = m0;
    let mut residual = shoot(model, load, m0, nodes, &mut psi, step)? - load.beta;
    // Secant polish of the root moment: the tip moment is smooth in it, and the statics'
    // value is already within their tolerance, so two or three steps reach round-off (which
    // grows with the shot's amplification, up to `exp(sqrt(alpha))`): stop there.
    // Near a critical point the first frequency is sensitive to the equilibrium (it goes
    // like the square root of the distance), so the polish goes to 1e-12 when it can.
    let mut iterations = 0;
    // Whether `psi` holds the shot of the current `m0`.
    let mut current = true;
    while residual.abs() > 1e-12 * scale {
        iterations += 1;
        let delta = 1e-7 * scale;
        let shifted = shoot(model, load, m0 + delta, nodes, &mut psi, step)? - load.beta;
        let slope = (shifted - residual) / delta;
        if !(slope.is_finite() && slope != 0.0) {
            return Err(ModesError::Equilibrium(
                "the tip moment does not depend on the root moment (a critical point)".to_string(),
            ));
        }
        let next_m0 = m0 - residual / slope;
        let next = shoot(model, load, next_m0, nodes, &mut psi, step)? - load.beta;
        if next.abs() >= 0.5 * residual.abs() || iterations >= 6 {
            // Round-off: keep the better of the two.
            if next.abs() < residual.abs() {
                m0 = next_m0;
                residual = next;
            } else {
                current = false;
            }
            break;
        }
        m0 = next_m0;
        residual = next;
    }
    if residual.abs() > 1e-8 * scale {
        return Err(ModesError::Equilibrium(format!(
            "the tip moment misses the load's by {residual:.3e} after polishing the root moment \
             (past forces of several hundred E I/L^2 one shot from the clamp cannot meet it)"
        )));
    }
    if !current {
        shoot(model, load, m0, nodes, &mut psi, step)?;
    }
    let mut states = Vec::with_capacity(psi.len());
    for &(p, m) in &psi {
        let mut state = node_state(model, load, p)?;
        tangent(model, &mut state, m)?;
        states.push(state);
    }
    Ok(Sampled {
        nodes: states,
        root_moment: m0,
    })
}

/// The section's state at rotation `psi`, its tangent still to fill (`tangent`).
fn node_state(model: &BeamModel, load: &Load, psi: f64) -> Result<NodeState, ModesError> {
    let (s, c) = psi.sin_cos();
    let n = load.alpha_x * c + load.alpha_y * s;
    let q = -load.alpha_x * s + load.alpha_y * c;
    let (eps, gamma, _) = model
        .section_strains(n, q)
        .ok_or(ModesError::MaterialLimit { axial_force: n })?;
    Ok(NodeState {
        psi,
        eps,
        gamma,
        n,
        q,
        d: [[0.0; 3]; 3],
    })
}

/// Fills a node's tangent stiffness, given the bending moment there.
fn tangent(model: &BeamModel, state: &mut NodeState, moment: f64) -> Result<(), ModesError> {
    let fx = model.effects;
    let (_, de_dn, p) = model
        .axial_strain(state.n)
        .map_err(|_| ModesError::MaterialLimit {
            axial_force: state.n,
        })?;
    // Compliance d(eps, gamma, kappa) / d(N, Q, M), lower triangular in that order.
    let dp_dn = if fx.poisson { -model.nu * de_dn } else { 0.0 };
    let plate = model.plate_compliance();
    let bend = if fx.poisson { plate / p.powi(4) } else { plate };
    let mut c = [[0.0; 3]; 3];
    c[0][0] = if fx.extension { de_dn } else { 1.0 };
    if fx.shear {
        let cs = model.shear_compliance();
        c[1][1] = cs / (p * p);
        c[1][0] = -2.0 * cs * state.q / (p * p * p) * dp_dn;
    } else {
        c[1][1] = 1.0;
    }
    c[2][2] = bend;
    c[2][0] = if fx.poisson {
        -4.0 * moment * bend / p * dp_dn
    } else {
        0.0
    };
    // Invert the lower-triangular compliance.
    let mut d = [[0.0; 3]; 3];
    d[0][0] = 1.0 / c[0][0];
    d[1][1] = 1.0 / c[1][1];
    d[2][2] = 1.0 / c[2][2];
    d[1][0] = -c[1][0] * d[0][0] * d[1][1];
    d[2][0] = -c[2][0] * d[0][0] * d[2][2];
    // The Poisson law is not hyperelastic (the bending stiffness depends on the axial strain
    // but the axial force not on the curvature): the symmetric part is the conservative
    // tangent the modes use. The skew part is a product of strains times nu, below 1e-6 of
    // the diagonal for any beam the statics accept at slenderness >= 10.
    let mut sym = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            sym[i][j] = 0.5 * (d[i][j] + d[j][i]);
        }
    }
    let active = [fx.extension, fx.shear, true];
    for i in 0..3 {
        for j in 0..3 {
            if !(active[i] && active[j]) {
                sym[i][j] = 0.0;
            }
        }
    }
    state.d = sym;
    Ok(())
}
