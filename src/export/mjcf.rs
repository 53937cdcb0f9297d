//! MuJoCo MJCF: a body per segment, `hinge` joints with `stiffness` and `springref="0"`,
//! `slide` joints for extension springs (both in the segment's body), gravity off, contacts
//! off, a `tip` site at the free end. Verified in MuJoCo by `tests/mujoco.rs`.

use std::fmt::Write as _;

use super::chain::{g, Chain};

/// The MJCF document of `chain`, with `comment` at the top.
pub fn write(chain: &Chain, comment: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "<mujoco model=\"{}\">", chain.name);
    let _ = writeln!(out, "  <!-- {comment} -->");
    let _ = writeln!(out, "  <compiler angle=\"radian\" autolimits=\"true\"/>");
    let _ = writeln!(out, "  <option gravity=\"0 0 0\"/>");
    let _ = writeln!(
        out,
        "  <default>\n    <geom contype=\"0\" conaffinity=\"0\"/>\n  </default>"
    );
    let _ = writeln!(out, "  <worldbody>");
    let mut indent = String::from("    ");
    let n_segments = chain.segments.len();
    for (i, seg) in chain.segments.iter().enumerate() {
        let n = seg.index;
        // Bodies nest: each sits at the end of its parent segment.
        let pos = if i == 0 {
            0.0
        } else {
            chain.segments[i - 1].length
        };
        let _ = writeln!(
            out,
            "{indent}<body name=\"{}\" pos=\"{} 0 0\">",
            seg.link(),
            g(pos)
        );
        let inner = format!("{indent}  ");
        if let Some(k) = seg.hinge {
            let _ = writeln!(
                out,
                "{inner}<joint name=\"theta{n}\" type=\"hinge\" axis=\"0 0 1\" stiffness=\"{}\" springref=\"0\"/>",
                g(k)
            );
        }
        if let Some(k) = seg.slide {
            let _ = writeln!(
                out,
                "{inner}<joint name=\"{}\" type=\"slide\" axis=\"1 0 0\" stiffness=\"{}\" springref=\"0\"/>",
                seg.slide_joint(),
                g(k)
            );
        }
        let _ = writeln!(
            out,
            "{inner}<geom name=\"link{n}\" type=\"box\" pos=\"{} 0 0\" size=\"{} {} {}\" mass=\"{}\"/>",
            g(seg.length / 2.0),
            g((seg.length / 2.0).max(1e-9 * chain.beam_length)),
            g(chain.thickness / 2.0),
            g(chain.width / 2.0),
            g(seg.mass.mass)
        );
        if i + 1 == n_segments {
            let _ = writeln!(
                out,
                "{inner}<site name=\"tip\" pos=\"{} 0 0\"/>",
                g(seg.length)
            );
        }
        indent.push_str("  ");
    }
    for _ in 0..n_segments {
        indent.truncate(indent.len() - 2);
        let _ = writeln!(out, "{indent}</body>");
    }
    let _ = writeln!(out, "  </worldbody>");
    let _ = writeln!(out, "</mujoco>");
    out
}
