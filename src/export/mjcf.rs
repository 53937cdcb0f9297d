//! MuJoCo MJCF: a body per segment, `hinge` joints with `stiffness` and `springref="0"`,
//! `slide` joints for extension springs (both in the segment's body), each body's
//! `inertial` the segment's mass (DESIGN §10, [`super::chain`]), gravity off, contacts off, a
//! `tip` site at the free end. Verified in MuJoCo by `tests/mujoco.rs` (statics) and
//! `tests/mujoco_modes.rs` (free vibration at prbfit's PRB frequency).
//!
//! The time step: MuJoCo's default semi-implicit Euler integrates a spring of `omega` stably
//! only for `omega dt < 2` ([`super::chain::STABILITY_BOUND`]), and its frequency is right to
//! `(omega dt)^2 / 24`. The file's `timestep` is [`super::chain::time_step`] at
//! `omega_max dt = 0.2` ([`super::chain::CHAIN_STEP`], ten times inside the bound), with
//! `omega_max` the highest natural frequency of the chain exactly as written (its floored
//! masses and inertias included, [`super::chain::frequency_range`]): a light link between two
//! springs rings far above any one spring over the inertia beyond it, which an estimate from
//! the springs alone misses (it gave `omega_max dt = 15` for a link of `1e-6` of the mass).
//! The first mode's frequency is then right to `(0.2 omega_1 / omega_max)^2 / 24`. A model
//! whose first period would take more than 1e7 steps is refused
//! ([`super::ExportError::TooStiff`]).
//!
//! The chain's bodies are written by [`write_chain`], which the whole mechanism's MJCF
//! ([`super::mjcf_mech`]) shares: one chain per flexure, its names prefixed.

use std::fmt::Write as _;

use super::chain::{g, Chain, CHAIN_STEP};

/// The MJCF document of `chain`, with `comment` at the top; `Err` for a model too stiff to
/// simulate at a practical time step ([`super::chain::time_step`]).
pub fn write(chain: &Chain, comment: &str) -> Result<String, super::ExportError> {
    let step = super::chain::time_step(std::slice::from_ref(chain), CHAIN_STEP)?;
    let mut out = String::new();
    let _ = writeln!(out, "<mujoco model=\"{}\">", chain.name);
    let _ = writeln!(out, "  <!-- {comment} -->");
    let _ = writeln!(out, "  <compiler angle=\"radian\" autolimits=\"true\"/>");
    let _ = writeln!(
        out,
        "  <option gravity=\"0 0 0\" timestep=\"{}\"/>",
        g(step)
    );
    let _ = writeln!(
        out,
        "  <default>\n    <geom contype=\"0\" conaffinity=\"0\"/>\n  </default>"
    );
    let _ = writeln!(out, "  <worldbody>");
    let placement = ChainPlacement {
        prefix: "",
        root: [0.0, 0.0],
        angle: 0.0,
    };
    write_chain(
        &mut out,
        chain,
        &placement,
        "    ",
        |out, indent, length| {
            let _ = writeln!(
                out,
                "{indent}<site name=\"tip\" pos=\"{} 0 0\"/>",
                g(length)
            );
        },
    );
    let _ = writeln!(out, "  </worldbody>");
    let _ = writeln!(out, "</mujoco>");
    Ok(out)
}

/// Where a chain sits in the world and how its names are prefixed.
pub struct ChainPlacement<'a> {
    /// Put before every body, joint and geom name (`""` for the single chain).
    pub prefix: &'a str,
    /// The clamp, m.
    pub root: [f64; 2],
    /// The unloaded chain's direction, radians from +x (about +z).
    pub angle: f64,
}

/// Writes the nested bodies of `chain` at `placement`, starting at `indent`. `at_tip` writes
/// what the last segment's body carries at the chain's free end: it gets the output, the
/// indent inside that body and the last segment's length (the tip's x in that body's frame).
pub fn write_chain(
    out: &mut String,
    chain: &Chain,
    placement: &ChainPlacement,
    indent: &str,
    at_tip: impl FnOnce(&mut String, &str, f64),
) {
    let prefix = placement.prefix;
    let mut indent = indent.to_string();
    let n_segments = chain.segments.len();
    let mut at_tip = Some(at_tip);
    for (i, seg) in chain.segments.iter().enumerate() {
        let n = seg.index;
        // Bodies nest: each sits at the end of its parent segment; the first at the clamp,
        // turned by the chain's angle (omitted when zero, so the single chain stays plain).
        let place = if i == 0 {
            let [x, y] = placement.root;
            let mut p = format!("pos=\"{} {} 0\"", g(x), g(y));
            if placement.angle != 0.0 {
                let (s, c) = (placement.angle / 2.0).sin_cos();
                let _ = write!(p, " quat=\"{} 0 0 {}\"", g(c), g(s));
            }
            p
        } else {
            format!("pos=\"{} 0 0\"", g(chain.segments[i - 1].length))
        };
        let _ = writeln!(
            out,
            "{indent}<body name=\"{prefix}{}\" {place}>",
            seg.link()
        );
        let inner = format!("{indent}  ");
        if let Some(k) = seg.hinge {
            let _ = writeln!(
                out,
                "{inner}<joint name=\"{prefix}theta{n}\" type=\"hinge\" axis=\"0 0 1\" stiffness=\"{}\" springref=\"0\"/>",
                g(k)
            );
        }
        if let Some(k) = seg.slide {
            let _ = writeln!(
                out,
                "{inner}<joint name=\"{prefix}{}\" type=\"slide\" axis=\"1 0 0\" stiffness=\"{}\" springref=\"0\"/>",
                seg.slide_joint(),
                g(k)
            );
        }
        let [ix, iy, iz] = seg.mass.inertia;
        let _ = writeln!(
            out,
            "{inner}<inertial pos=\"{} 0 0\" mass=\"{}\" diaginertia=\"{} {} {}\"/>",
            g(seg.mass.com),
            g(seg.mass.mass),
            g(ix),
            g(iy),
            g(iz)
        );
        let _ = writeln!(
            out,
            "{inner}<geom name=\"{prefix}link{n}\" type=\"box\" pos=\"{} 0 0\" size=\"{} {} {}\"/>",
            g(seg.length / 2.0),
            g((seg.length / 2.0).max(1e-9 * chain.beam_length)),
            g(chain.thickness / 2.0),
            g(chain.width / 2.0)
        );
        if i + 1 == n_segments {
            if let Some(f) = at_tip.take() {
                f(out, &inner, seg.length);
            }
        }
        indent.push_str("  ");
    }
    for _ in 0..n_segments {
        indent.truncate(indent.len() - 2);
        let _ = writeln!(out, "{indent}</body>");
    }
}
