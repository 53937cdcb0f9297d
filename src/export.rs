//! Exporting a PRB model where designers use it: prbfit's own model file (TOML, JSON), MuJoCo
//! (MJCF), URDF, SDF 1.10, and CSV of the load cases.
//!
//! The scene supplies the beam, so every format also carries SI values:
//! segment lengths `gamma L`, torsion springs `K_theta = k_theta E I0 / L` (N m/rad) and
//! extension springs `K_ex = k_ex E A0 / L` (N/m). Each chain lies along +x from the clamp
//! (the world origin) in its unloaded pose; revolute joints turn about +z.
//!
//! Masses come from the beam's cross-section and a density (default 1000 kg/m^3): they matter
//! only for dynamics, never for the static equilibrium the model was fitted for.

use std::fmt::Write as _;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::eval::{evaluate, Baseline, ErrorFigures};
use crate::prb::{PrbMatrix, PrbSolver};
use crate::scene::{ModelFile, ModelFormat, Scene};

/// The formats `prbfit export` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportFormat {
    Toml,
    Json,
    Mjcf,
    Urdf,
    Sdf,
    Csv,
}

impl FromStr for ExportFormat {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ok(match s {
            "toml" => ExportFormat::Toml,
            "json" => ExportFormat::Json,
            "mjcf" => ExportFormat::Mjcf,
            "urdf" => ExportFormat::Urdf,
            "sdf" => ExportFormat::Sdf,
            "csv" => ExportFormat::Csv,
            other => {
                return Err(format!(
                    "unknown format `{other}` (expected toml, json, mjcf, urdf, sdf or csv)"
                ))
            }
        })
    }
}

impl ExportFormat {
    /// The format a file name suggests (`.xml` and `.mjcf` are MuJoCo).
    pub fn from_extension(path: &std::path::Path) -> Option<ExportFormat> {
        match path.extension()?.to_str()? {
            "toml" => Some(ExportFormat::Toml),
            "json" => Some(ExportFormat::Json),
            "mjcf" | "xml" => Some(ExportFormat::Mjcf),
            "urdf" => Some(ExportFormat::Urdf),
            "sdf" => Some(ExportFormat::Sdf),
            "csv" => Some(ExportFormat::Csv),
            _ => None,
        }
    }
}

/// One segment in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SiSegment {
    /// m
    pub length: f64,
    /// N m/rad at the segment's root end; absent: no joint.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_theta: Option<f64>,
    /// N/m along the segment; absent: fixed length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_ex: Option<f64>,
}

/// The model in SI units for the scene's beam.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SiModel {
    pub beam_length: f64,
    pub width: f64,
    pub thickness: f64,
    pub youngs_modulus: f64,
    pub segments: Vec<SiSegment>,
}

/// The scene's loads, nondimensional and in SI (N, N m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LoadRange {
    pub alpha_x: [f64; 2],
    pub alpha_y: [f64; 2],
    pub beta: [f64; 2],
    pub fx: [f64; 2],
    pub fy: [f64; 2],
    pub mz: [f64; 2],
}

/// The SI values of `matrix` for the scene's beam.
pub fn si_model(matrix: &PrbMatrix, scene: &Scene) -> SiModel {
    let b = &scene.beam;
    let l = b.length;
    let ei = b.youngs_modulus * b.second_moment();
    let ea = b.youngs_modulus * b.area();
    SiModel {
        beam_length: l,
        width: b.width,
        thickness: b.thickness,
        youngs_modulus: b.youngs_modulus,
        segments: matrix
            .rows()
            .iter()
            .map(|r| SiSegment {
                length: r.gamma * l,
                k_theta: r.k_theta.is_finite().then(|| r.k_theta * ei / l),
                k_ex: r.k_ex.is_finite().then(|| r.k_ex * ea / l),
            })
            .collect(),
    }
}

/// The range of the scene's load cases (the paths run from zero, so zero is included).
pub fn load_range(scene: &Scene) -> LoadRange {
    let b = &scene.beam;
    let ei = b.youngs_modulus * b.second_moment();
    let l = b.length;
    let span = |f: &dyn Fn(&crate::beam::Load) -> f64| {
        scene.loads.iter().fold([0.0_f64, 0.0_f64], |acc, p| {
            let v = f(&p.end);
            [acc[0].min(v), acc[1].max(v)]
        })
    };
    let ax = span(&|l| l.alpha_x);
    let ay = span(&|l| l.alpha_y);
    let be = span(&|l| l.beta);
    let force = ei / (l * l);
    let moment = ei / l;
    LoadRange {
        alpha_x: ax,
        alpha_y: ay,
        beta: be,
        fx: [ax[0] * force, ax[1] * force],
        fy: [ay[0] * force, ay[1] * force],
        mz: [be[0] * moment, be[1] * moment],
    }
}

/// Everything an export needs.
pub struct ExportInput<'a> {
    pub name: String,
    pub matrix: &'a PrbMatrix,
    pub scene: &'a Scene,
    /// The model judged on the scene (for the figures and the CSV).
    pub baseline: &'a Baseline,
    pub fidelity: String,
    /// kg/m^3, for masses.
    pub density: f64,
}

/// Why an export failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExportError {
    #[error("the model cannot follow the scene's loads: {0}")]
    Eval(String),
    #[error("density must be a finite number > 0, got {0}")]
    Density(f64),
}

/// The text of the export in `format`.
pub fn export(input: &ExportInput, format: ExportFormat) -> Result<String, ExportError> {
    if !(input.density.is_finite() && input.density > 0.0) {
        return Err(ExportError::Density(input.density));
    }
    let weight = input.scene.fit.angle_weight;
    let evaluation = evaluate(input.matrix, input.baseline, weight)
        .map_err(|e| ExportError::Eval(e.to_string()))?;
    Ok(match format {
        ExportFormat::Toml => own(input, &evaluation.figures).to_text(ModelFormat::Toml),
        ExportFormat::Json => own(input, &evaluation.figures).to_text(ModelFormat::Json),
        ExportFormat::Mjcf => mjcf(input),
        ExportFormat::Urdf => urdf(input),
        ExportFormat::Sdf => sdf(input),
        ExportFormat::Csv => csv(input)?,
    })
}

fn own(input: &ExportInput, figures: &ErrorFigures) -> ModelFile {
    let mut file = ModelFile::fitted(input.matrix, input.scene, &input.fidelity, figures);
    file.name = input.name.clone();
    file.title = Some(format!(
        "{} for {}",
        input.matrix.topology(),
        input.scene.name
    ));
    file.source = Some(format!("prbfit {} export", env!("CARGO_PKG_VERSION")));
    file
}

/// XML-escapes text for attributes and comments.
fn xml_text(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
        .replace("--", "- -")
}

/// A name safe for XML ids and ROS names.
fn ident(s: &str) -> String {
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

fn header_comment(input: &ExportInput) -> String {
    format!(
        "PRB model {} exported by prbfit {} ({}) for the scene \"{}\".\n     \
         Matrix (nondimensional): {}\n     \
         Units: m, kg, N m/rad (torsion springs), N/m (extension springs). The chain lies \
         along +x from the clamp at the origin; hinges turn about +z.",
        xml_text(&input.matrix.topology()),
        env!("CARGO_PKG_VERSION"),
        crate::files::utc_timestamp(),
        xml_text(&input.scene.name),
        xml_text(&input.matrix.to_text()),
    )
}

/// Mass and inertia of a segment: a box `length x width x thickness` of the density.
fn segment_mass(input: &ExportInput, length: f64) -> (f64, [f64; 3]) {
    let b = &input.scene.beam;
    let length = length.max(1e-9 * b.length);
    let m = input.density * length * b.width * b.thickness;
    let ixx = m * (b.width.powi(2) + b.thickness.powi(2)) / 12.0;
    let iyy = m * (length.powi(2) + b.thickness.powi(2)) / 12.0;
    let izz = m * (length.powi(2) + b.width.powi(2)) / 12.0;
    (m, [ixx, iyy, izz])
}

fn g(v: f64) -> String {
    format!("{v:e}")
}

/// MuJoCo MJCF: a body per segment, `hinge` joints with `stiffness` and `springref="0"`,
/// `slide` joints for extension springs, gravity off, a `tip` site at the free end.
fn mjcf(input: &ExportInput) -> String {
    let si = si_model(input.matrix, input.scene);
    let b = &input.scene.beam;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<mujoco model=\"prbfit_{}\">",
        ident(&input.matrix.topology())
    );
    let _ = writeln!(out, "  <!-- {} -->", header_comment(input));
    let _ = writeln!(out, "  <compiler angle=\"radian\" autolimits=\"true\"/>");
    let _ = writeln!(out, "  <option gravity=\"0 0 0\"/>");
    let _ = writeln!(
        out,
        "  <default>\n    <geom contype=\"0\" conaffinity=\"0\"/>\n  </default>"
    );
    let _ = writeln!(out, "  <worldbody>");
    let mut indent = String::from("    ");
    for (i, seg) in si.segments.iter().enumerate() {
        let n = i + 1;
        let pos = if i == 0 {
            0.0
        } else {
            si.segments[i - 1].length
        };
        let _ = writeln!(
            out,
            "{indent}<body name=\"segment{n}\" pos=\"{} 0 0\">",
            g(pos)
        );
        let inner = format!("{indent}  ");
        if let Some(k) = seg.k_theta {
            let _ = writeln!(
                out,
                "{inner}<joint name=\"theta{n}\" type=\"hinge\" axis=\"0 0 1\" stiffness=\"{}\" springref=\"0\"/>",
                g(k)
            );
        }
        if let Some(k) = seg.k_ex {
            let _ = writeln!(
                out,
                "{inner}<joint name=\"delta{n}\" type=\"slide\" axis=\"1 0 0\" stiffness=\"{}\" springref=\"0\"/>",
                g(k)
            );
        }
        let (mass, _) = segment_mass(input, seg.length);
        let _ = writeln!(
            out,
            "{inner}<geom name=\"link{n}\" type=\"box\" pos=\"{} 0 0\" size=\"{} {} {}\" mass=\"{}\"/>",
            g(seg.length / 2.0),
            g((seg.length / 2.0).max(1e-9 * b.length)),
            g(b.thickness / 2.0),
            g(b.width / 2.0),
            g(mass)
        );
        if n == si.segments.len() {
            let _ = writeln!(
                out,
                "{inner}<site name=\"tip\" pos=\"{} 0 0\"/>",
                g(seg.length)
            );
        }
        indent.push_str("  ");
    }
    for _ in 0..si.segments.len() {
        indent.truncate(indent.len() - 2);
        let _ = writeln!(out, "{indent}</body>");
    }
    let _ = writeln!(out, "  </worldbody>");
    let _ = writeln!(out, "</mujoco>");
    out
}

fn urdf_inertial(input: &ExportInput, length: f64) -> String {
    let (m, [ixx, iyy, izz]) = segment_mass(input, length);
    format!(
        "    <inertial>\n      <origin xyz=\"{} 0 0\"/>\n      <mass value=\"{}\"/>\n      \
         <inertia ixx=\"{}\" ixy=\"0\" ixz=\"0\" iyy=\"{}\" iyz=\"0\" izz=\"{}\"/>\n    </inertial>\n",
        g(length / 2.0),
        g(m),
        g(ixx),
        g(iyy),
        g(izz)
    )
}

/// URDF: links and joints with limits. URDF has no joint springs; Gazebo's extension elements
/// `springStiffness` and `springReference` carry them, and a comment says so.
fn urdf(input: &ExportInput) -> String {
    let si = si_model(input.matrix, input.scene);
    let b = &input.scene.beam;
    let mut out = String::from("<?xml version=\"1.0\"?>\n");
    let _ = writeln!(out, "<!-- {} -->", header_comment(input));
    let _ = writeln!(
        out,
        "<!-- URDF has no joint springs: each spring is carried by the Gazebo extension \
         elements springStiffness and springReference in the <gazebo reference=\"JOINT\"> \
         blocks below. Simulators that ignore them see free joints. -->"
    );
    let _ = writeln!(
        out,
        "<robot name=\"prbfit_{}\">",
        ident(&input.matrix.topology())
    );
    let _ = writeln!(out, "  <link name=\"base\"/>");
    let mut parent = "base".to_string();
    let mut offset = 0.0;
    let mut gazebo = String::new();
    let max_stretch = b.length;
    for (i, seg) in si.segments.iter().enumerate() {
        let n = i + 1;
        let link = format!("segment{n}");
        // A revolute joint (or a fixed one) into the segment, then, for an extension spring,
        // a prismatic joint from an intermediate link.
        let first_child = if seg.k_ex.is_some() {
            format!("segment{n}_hinge")
        } else {
            link.clone()
        };
        if seg.k_ex.is_some() {
            let _ = writeln!(out, "  <link name=\"{first_child}\">");
            out.push_str(&urdf_inertial(input, 1e-6 * b.length));
            let _ = writeln!(out, "  </link>");
        }
        match seg.k_theta {
            Some(k) => {
                let _ = writeln!(
                    out,
                    "  <joint name=\"theta{n}\" type=\"revolute\">\n    <parent link=\"{parent}\"/>\n    \
                     <child link=\"{first_child}\"/>\n    <origin xyz=\"{} 0 0\"/>\n    \
                     <axis xyz=\"0 0 1\"/>\n    <limit lower=\"-3.14159265\" upper=\"3.14159265\" effort=\"1e9\" velocity=\"1e3\"/>\n  </joint>",
                    g(offset)
                );
                let _ = writeln!(
                    gazebo,
                    "  <gazebo reference=\"theta{n}\">\n    <springStiffness>{}</springStiffness>\n    \
                     <springReference>0</springReference>\n  </gazebo>",
                    g(k)
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "  <joint name=\"fixed{n}\" type=\"fixed\">\n    <parent link=\"{parent}\"/>\n    \
                     <child link=\"{first_child}\"/>\n    <origin xyz=\"{} 0 0\"/>\n  </joint>",
                    g(offset)
                );
            }
        }
        if let Some(k) = seg.k_ex {
            let _ = writeln!(
                out,
                "  <joint name=\"delta{n}\" type=\"prismatic\">\n    <parent link=\"{first_child}\"/>\n    \
                 <child link=\"{link}\"/>\n    <origin xyz=\"0 0 0\"/>\n    <axis xyz=\"1 0 0\"/>\n    \
                 <limit lower=\"{}\" upper=\"{}\" effort=\"1e9\" velocity=\"1e3\"/>\n  </joint>",
                g(-seg.length.min(max_stretch)),
                g(max_stretch)
            );
            let _ = writeln!(
                gazebo,
                "  <gazebo reference=\"delta{n}\">\n    <springStiffness>{}</springStiffness>\n    \
                 <springReference>0</springReference>\n  </gazebo>",
                g(k)
            );
        }
        let _ = writeln!(out, "  <link name=\"{link}\">");
        out.push_str(&urdf_inertial(input, seg.length));
        let _ = writeln!(
            out,
            "    <visual>\n      <origin xyz=\"{} 0 0\"/>\n      <geometry><box size=\"{} {} {}\"/></geometry>\n    </visual>",
            g(seg.length / 2.0),
            g(seg.length.max(1e-9)),
            g(b.thickness),
            g(b.width)
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

/// SDF 1.10: links posed in the model frame, joints with
/// `axis/dynamics/spring_stiffness` and `spring_reference`.
fn sdf(input: &ExportInput) -> String {
    let si = si_model(input.matrix, input.scene);
    let b = &input.scene.beam;
    let mut out = String::from("<?xml version=\"1.0\"?>\n");
    let _ = writeln!(out, "<!-- {} -->", header_comment(input));
    let _ = writeln!(out, "<sdf version=\"1.10\">");
    let _ = writeln!(
        out,
        "  <model name=\"prbfit_{}\">",
        ident(&input.matrix.topology())
    );
    let mut x = 0.0;
    let mut parent = "world".to_string();
    let link_xml = |name: &str, x: f64, length: f64| {
        let (m, [ixx, iyy, izz]) = segment_mass(input, length);
        format!(
            "    <link name=\"{name}\">\n      <pose>{} 0 0 0 0 0</pose>\n      <inertial>\n        \
             <pose>{} 0 0 0 0 0</pose>\n        <mass>{}</mass>\n        <inertia><ixx>{}</ixx><ixy>0</ixy><ixz>0</ixz>\
             <iyy>{}</iyy><iyz>0</iyz><izz>{}</izz></inertia>\n      </inertial>\n      \
             <visual name=\"visual\">\n        <pose>{} 0 0 0 0 0</pose>\n        \
             <geometry><box><size>{} {} {}</size></box></geometry>\n      </visual>\n    </link>\n",
            g(x),
            g(length / 2.0),
            g(m),
            g(ixx),
            g(iyy),
            g(izz),
            g(length / 2.0),
            g(length.max(1e-9)),
            g(b.thickness),
            g(b.width)
        )
    };
    let spring = |k: f64| {
        format!(
            "        <dynamics>\n          <spring_stiffness>{}</spring_stiffness>\n          \
             <spring_reference>0</spring_reference>\n        </dynamics>\n",
            g(k)
        )
    };
    for (i, seg) in si.segments.iter().enumerate() {
        let n = i + 1;
        let link = format!("segment{n}");
        let first_child = if seg.k_ex.is_some() {
            format!("segment{n}_hinge")
        } else {
            link.clone()
        };
        if seg.k_ex.is_some() {
            out.push_str(&link_xml(&first_child, x, 1e-6 * b.length));
        }
        out.push_str(&link_xml(&link, x, seg.length));
        match seg.k_theta {
            Some(k) => {
                let _ = write!(
                    out,
                    "    <joint name=\"theta{n}\" type=\"revolute\">\n      <parent>{parent}</parent>\n      \
                     <child>{first_child}</child>\n      <axis>\n        <xyz>0 0 1</xyz>\n{}      </axis>\n    </joint>\n",
                    spring(k)
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "    <joint name=\"fixed{n}\" type=\"fixed\">\n      <parent>{parent}</parent>\n      \
                     <child>{first_child}</child>\n    </joint>"
                );
            }
        }
        if let Some(k) = seg.k_ex {
            let _ = write!(
                out,
                "    <joint name=\"delta{n}\" type=\"prismatic\">\n      <parent>{first_child}</parent>\n      \
                 <child>{link}</child>\n      <axis>\n        <xyz>1 0 0</xyz>\n{}      </axis>\n    </joint>\n",
                spring(k)
            );
        }
        parent = link;
        x += seg.length;
    }
    let _ = writeln!(
        out,
        "    <frame name=\"tip\" attached_to=\"{parent}\">\n      <pose relative_to=\"{parent}\">{} 0 0 0 0 0</pose>\n    </frame>",
        g(si.segments.last().map_or(0.0, |s| s.length))
    );
    let _ = writeln!(out, "  </model>\n</sdf>");
    out
}

/// CSV: per load case, the beam tip and the PRB tip, then both shapes (units of L, radians).
fn csv(input: &ExportInput) -> Result<String, ExportError> {
    let baseline = input.baseline;
    let solver = PrbSolver::new(input.matrix, baseline.model.axial_compliance());
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# prbfit {} export: model {} ({}) on scene \"{}\"; positions in units of L, angles in radians",
        env!("CARGO_PKG_VERSION"),
        input.name,
        input.matrix.to_text(),
        input.scene.name.replace('"', "'")
    );
    let _ = writeln!(out, "case,alpha_x,alpha_y,beta,curve,index,x,y,angle");
    let mut case = 0usize;
    for path in &baseline.paths {
        let mut rows = Vec::new();
        solver
            .solve_path_with(path.end, path.steps, |case| rows.push(case.to_solution()))
            .map_err(|e| ExportError::Eval(e.to_string()))?;
        for sol in rows {
            let beam = &baseline.solutions[case];
            let l = sol.load;
            let head = format!("{},{},{},{}", case + 1, l.alpha_x, l.alpha_y, l.beta);
            let _ = writeln!(
                out,
                "{head},beam_tip,0,{},{},{}",
                beam.tip.a, beam.tip.b, beam.tip.phi
            );
            let _ = writeln!(
                out,
                "{head},prb_tip,0,{},{},{}",
                sol.tip.a, sol.tip.b, sol.tip.phi
            );
            for (i, p) in beam.shape.iter().enumerate() {
                let _ = writeln!(out, "{head},beam_shape,{i},{},{},{}", p.x, p.y, p.psi);
            }
            for (i, p) in solver.joint_positions(&sol.q).iter().enumerate() {
                let _ = writeln!(out, "{head},prb_linkage,{i},{},{},", p[0], p[1]);
            }
            case += 1;
        }
    }
    Ok(out)
}
