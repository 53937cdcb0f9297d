//! URDF: links and joints with limits. URDF has no joint springs; Gazebo's extension elements
//! `springStiffness` and `springReference` carry them, and a comment says so.

use std::fmt::Write as _;

use super::chain::{g, Chain, MassProperties};

fn inertial(m: &MassProperties) -> String {
    let [ixx, iyy, izz] = m.inertia;
    format!(
        "    <inertial>\n      <origin xyz=\"{} 0 0\"/>\n      <mass value=\"{}\"/>\n      \
         <inertia ixx=\"{}\" ixy=\"0\" ixz=\"0\" iyy=\"{}\" iyz=\"0\" izz=\"{}\"/>\n    </inertial>\n",
        g(m.com),
        g(m.mass),
        g(ixx),
        g(iyy),
        g(izz)
    )
}

fn spring(joint: &str, k: f64) -> String {
    format!(
        "  <gazebo reference=\"{joint}\">\n    <springStiffness>{}</springStiffness>\n    \
         <springReference>0</springReference>\n  </gazebo>\n",
        g(k)
    )
}

/// The URDF document of `chain`, with `comment` at the top.
pub fn write(chain: &Chain, comment: &str) -> String {
    let mut out = String::from("<?xml version=\"1.0\"?>\n");
    let _ = writeln!(out, "<!-- {comment} -->");
    let _ = writeln!(
        out,
        "<!-- URDF has no joint springs: each spring is carried by the Gazebo extension \
         elements springStiffness and springReference in the <gazebo reference=\"JOINT\"> \
         blocks below. Simulators that ignore them see free joints. -->"
    );
    let _ = writeln!(out, "<robot name=\"{}\">", chain.name);
    let _ = writeln!(out, "  <link name=\"base\"/>");
    let mut parent = "base".to_string();
    let mut offset = 0.0;
    let mut gazebo = String::new();
    let max_stretch = chain.beam_length;
    for seg in &chain.segments {
        let link = seg.link();
        // A revolute joint (or a fixed one) into the segment, then, for an extension spring,
        // a prismatic joint from an intermediate link.
        let first_child = seg.first_child();
        if seg.slide.is_some() {
            let _ = writeln!(out, "  <link name=\"{first_child}\">");
            out.push_str(&inertial(&chain.hinge_link_mass));
            let _ = writeln!(out, "  </link>");
        }
        let joint = seg.root_joint();
        match seg.hinge {
            Some(k) => {
                let _ = writeln!(
                    out,
                    "  <joint name=\"{joint}\" type=\"revolute\">\n    <parent link=\"{parent}\"/>\n    \
                     <child link=\"{first_child}\"/>\n    <origin xyz=\"{} 0 0\"/>\n    \
                     <axis xyz=\"0 0 1\"/>\n    <limit lower=\"-3.14159265\" upper=\"3.14159265\" effort=\"1e9\" velocity=\"1e3\"/>\n  </joint>",
                    g(offset)
                );
                gazebo.push_str(&spring(&joint, k));
            }
            None => {
                let _ = writeln!(
                    out,
                    "  <joint name=\"{joint}\" type=\"fixed\">\n    <parent link=\"{parent}\"/>\n    \
                     <child link=\"{first_child}\"/>\n    <origin xyz=\"{} 0 0\"/>\n  </joint>",
                    g(offset)
                );
            }
        }
        if let Some(k) = seg.slide {
            let slide = seg.slide_joint();
            let _ = writeln!(
                out,
                "  <joint name=\"{slide}\" type=\"prismatic\">\n    <parent link=\"{first_child}\"/>\n    \
                 <child link=\"{link}\"/>\n    <origin xyz=\"0 0 0\"/>\n    <axis xyz=\"1 0 0\"/>\n    \
                 <limit lower=\"{}\" upper=\"{}\" effort=\"1e9\" velocity=\"1e3\"/>\n  </joint>",
                g(-seg.length.min(max_stretch)),
                g(max_stretch)
            );
            gazebo.push_str(&spring(&slide, k));
        }
        let _ = writeln!(out, "  <link name=\"{link}\">");
        out.push_str(&inertial(&seg.mass));
        let _ = writeln!(
            out,
            "    <visual>\n      <origin xyz=\"{} 0 0\"/>\n      <geometry><box size=\"{} {} {}\"/></geometry>\n    </visual>",
            g(seg.length / 2.0),
            g(seg.length.max(1e-9)),
            g(chain.thickness),
            g(chain.width)
        );
        let _ = writeln!(out, "  </link>");
        parent = link;
        offset = seg.length;
    }
    let _ = writeln!(
        out,
        "  <link name=\"tip\"/>\n  <joint name=\"tip\" type=\"fixed\">\n    <parent link=\"{parent}\"/>\n    \
         <child link=\"tip\"/>\n    <origin xyz=\"{} 0 0\"/>\n  </joint>",
        g(offset)
    );
    out.push_str(&gazebo);
    let _ = writeln!(out, "</robot>");
    out
}
