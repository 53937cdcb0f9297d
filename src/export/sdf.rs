//! SDF 1.10: links posed in the model frame, joints with `axis/dynamics/spring_stiffness`
//! and `spring_reference`, a `tip` frame at the free end.

use std::fmt::Write as _;

use super::chain::{g, Chain, MassProperties};

fn link(chain: &Chain, name: &str, x: f64, length: f64, m: &MassProperties) -> String {
    let [ixx, iyy, izz] = m.inertia;
    format!(
        "    <link name=\"{name}\">\n      <pose>{} 0 0 0 0 0</pose>\n      <inertial>\n        \
         <pose>{} 0 0 0 0 0</pose>\n        <mass>{}</mass>\n        <inertia><ixx>{}</ixx><ixy>0</ixy><ixz>0</ixz>\
         <iyy>{}</iyy><iyz>0</iyz><izz>{}</izz></inertia>\n      </inertial>\n      \
         <visual name=\"visual\">\n        <pose>{} 0 0 0 0 0</pose>\n        \
         <geometry><box><size>{} {} {}</size></box></geometry>\n      </visual>\n    </link>\n",
        g(x),
        g(m.com),
        g(m.mass),
        g(ixx),
        g(iyy),
        g(izz),
        g(length / 2.0),
        g(length.max(1e-9)),
        g(chain.thickness),
        g(chain.width)
    )
}

fn spring(k: f64) -> String {
    format!(
        "        <dynamics>\n          <spring_stiffness>{}</spring_stiffness>\n          \
         <spring_reference>0</spring_reference>\n        </dynamics>\n",
        g(k)
    )
}

/// The SDF document of `chain`, with `comment` at the top.
pub fn write(chain: &Chain, comment: &str) -> String {
    let mut out = String::from("<?xml version=\"1.0\"?>\n");
    let _ = writeln!(out, "<!-- {comment} -->");
    let _ = writeln!(out, "<sdf version=\"1.10\">");
    let _ = writeln!(out, "  <model name=\"{}\">", chain.name);
    let mut x = 0.0;
    let mut parent = "world".to_string();
    for seg in &chain.segments {
        let name = seg.link();
        let first_child = seg.first_child();
        if seg.slide.is_some() {
            out.push_str(&link(
                chain,
                &first_child,
                x,
                chain.hinge_link_length(),
                &chain.hinge_link_mass,
            ));
        }
        out.push_str(&link(chain, &name, x, seg.length, &seg.mass));
        let joint = seg.root_joint();
        match seg.hinge {
            Some(k) => {
                let _ = write!(
                    out,
                    "    <joint name=\"{joint}\" type=\"revolute\">\n      <parent>{parent}</parent>\n      \
                     <child>{first_child}</child>\n      <axis>\n        <xyz>0 0 1</xyz>\n{}      </axis>\n    </joint>\n",
                    spring(k)
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "    <joint name=\"{joint}\" type=\"fixed\">\n      <parent>{parent}</parent>\n      \
                     <child>{first_child}</child>\n    </joint>"
                );
            }
        }
        if let Some(k) = seg.slide {
            let _ = write!(
                out,
                "    <joint name=\"{}\" type=\"prismatic\">\n      <parent>{first_child}</parent>\n      \
                 <child>{name}</child>\n      <axis>\n        <xyz>1 0 0</xyz>\n{}      </axis>\n    </joint>\n",
                seg.slide_joint(),
                spring(k)
            );
        }
        parent = name;
        x += seg.length;
    }
    let _ = writeln!(
        out,
        "    <frame name=\"tip\" attached_to=\"{parent}\">\n      <pose relative_to=\"{parent}\">{} 0 0 0 0 0</pose>\n    </frame>",
        g(chain.segments.last().map_or(0.0, |s| s.length))
    );
    let _ = writeln!(out, "  </model>\n</sdf>");
    out
}
