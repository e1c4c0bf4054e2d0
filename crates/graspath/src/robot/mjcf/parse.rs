//! From the element tree to bodies, joints and geoms: the `<compiler>` settings (angle unit,
//! Euler sequence, mesh folder), `<default>` classes (nested, inherited, chosen by `class` or
//! an enclosing `childclass`), mesh assets, the body tree and its joints. Attribute values and
//! poses are read in `values.rs`, geoms in `geom.rs`, the classes' storage in `defaults.rs`;
//! errors name the line, the element and the attribute. Names are checked for repeats as
//! MuJoCo's compiler checks them (bodies, joints, geoms, meshes), through hash maps: reading is
//! linear in the number of elements.

use super::defaults::ClassDefaults;
use super::dom::Element;
use crate::geometry::shape::Shape;
use crate::robot::chain::unit_axis;
use crate::robot::error::RobotError;
use crate::robot::spec::RigidBody;
use nalgebra::{Isometry3, Unit, Vector3};
use std::collections::HashMap;

/// The class of elements outside any `class` / `childclass`.
const MAIN: &str = "main";

/// `<compiler>` settings that change how numbers are read.
#[derive(Debug, Clone)]
pub(crate) struct Compiler {
    /// `angle="degree"` (MuJoCo's default) or `"radian"`.
    pub degrees: bool,
    /// `eulerseq`: lower case rotates about the moving axes, upper case about the fixed ones.
    pub euler_seq: [u8; 3],
    /// `meshdir` (else `assetdir`), relative to the model file's folder.
    pub mesh_dir: Option<String>,
    /// `autolimits` (default true): a joint with a `range` and no `limited` is limited.
    pub auto_limits: bool,
    /// `inertiafromgeom="true"`: MuJoCo ignores every `<inertial>` and takes the bodies'
    /// mass properties from their geoms, which this reader does not compute.
    pub inertia_from_geom_only: bool,
}

/// The motion a joint allows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum JointType {
    Hinge,
    Slide,
    Ball,
    Free,
}

impl JointType {
    pub(super) fn word(self) -> &'static str {
        match self {
            JointType::Hinge => "hinge",
            JointType::Slide => "slide",
            JointType::Ball => "ball",
            JointType::Free => "free",
        }
    }
}

/// One joint of a body, in the body frame.
#[derive(Debug, Clone)]
pub(crate) struct Joint {
    /// The `name` attribute, or `#k` (its index in the body) when unnamed.
    pub name: String,
    /// 1-based line of the `<joint>` element.
    pub line: usize,
    pub kind: JointType,
    /// The anchor point in the body frame (m).
    pub pos: Vector3<f64>,
    /// Unit axis in the body frame.
    pub axis: Unit<Vector3<f64>>,
    /// `[lower, upper]` (rad or m) when limited.
    pub range: Option<(f64, f64)>,
    /// `ref`: the joint value (rad or m) at which the body has its written pose.
    pub reference: f64,
    /// The largest torque (N·m) or force (N) the joint's actuators can apply: its
    /// `actuatorfrcrange`, else the actuators' `forcerange` times their gear.
    pub effort: Option<f64>,
}

/// What a geom is made of.
#[derive(Debug, Clone)]
pub(crate) enum GeomKind {
    Shape(Shape),
    /// A mesh asset: its file as written, relative to the mesh folder, and its scale.
    Mesh {
        file: String,
        scale: [f64; 3],
    },
    /// Not turned into a collision shape, and why.
    Skipped(String),
}

/// One colliding geom of a body.
#[derive(Debug, Clone)]
pub(crate) struct Geom {
    pub name: Option<String>,
    pub line: usize,
    /// The geom frame in the body frame (m).
    pub body_from_geom: Isometry3<f64>,
    pub kind: GeomKind,
}

/// One body: its frame in its parent's, its joints (in order) and colliding geoms.
#[derive(Debug, Clone)]
pub(crate) struct Body {
    pub name: String,
    /// 1-based line of the `<body>` element (0 for the world body).
    pub line: usize,
    pub parent: Option<usize>,
    pub parent_from_body: Isometry3<f64>,
    pub joints: Vec<Joint>,
    pub geoms: Vec<Geom>,
    /// The body's `<inertial>`, in the body frame.
    pub inertial: Option<RigidBody>,
}

/// A mesh asset.
#[derive(Debug, Clone)]
pub(super) struct MeshAsset {
    pub file: Option<String>,
    pub scale: [f64; 3],
}

/// The parsed model.
#[derive(Debug, Clone)]
pub(crate) struct Model {
    pub name: String,
    pub compiler: Compiler,
    /// Body 0 is the world body.
    pub bodies: Vec<Body>,
    /// Each body's index by name.
    pub body_index: HashMap<String, usize>,
    /// Each body's children, in file order.
    pub children: Vec<Vec<usize>>,
}

pub(super) struct Reader<'a> {
    pub(super) source_name: &'a str,
    pub(super) compiler: Compiler,
    pub(super) classes: HashMap<String, ClassDefaults>,
    pub(super) meshes: HashMap<String, MeshAsset>,
    pub(super) bodies: Vec<Body>,
    /// Each body's index by name.
    pub(super) body_index: HashMap<String, usize>,
    /// Each named joint: its body, its index in the body, its line.
    pub(super) joint_index: HashMap<String, (usize, usize, usize)>,
    /// Each named geom's line.
    pub(super) geom_lines: HashMap<String, usize>,
    /// The mesh assets' lines, by name.
    pub(super) mesh_lines: HashMap<String, usize>,
}

/// Reads the model under the root `<mujoco>` element.
pub(crate) fn read(root: &Element, source_name: &str) -> Result<Model, RobotError> {
    let mut reader = Reader {
        source_name,
        compiler: Compiler {
            degrees: true,
            euler_seq: *b"xyz",
            mesh_dir: None,
            auto_limits: true,
            inertia_from_geom_only: false,
        },
        classes: HashMap::new(),
        meshes: HashMap::new(),
        bodies: vec![Body {
            name: "world".into(),
            line: 0,
            parent: None,
            parent_from_body: Isometry3::identity(),
            joints: Vec::new(),
            geoms: Vec::new(),
            inertial: None,
        }],
        body_index: HashMap::from([("world".to_string(), 0)]),
        joint_index: HashMap::new(),
        geom_lines: HashMap::new(),
        mesh_lines: HashMap::new(),
    };
    if root.name != "mujoco" {
        return Err(reader.error(
            root,
            "-",
            format!("the root element is <{}>, not <mujoco>", root.name),
        ));
    }
    for child in &root.children {
        match child.name.as_str() {
            "compiler" => reader.compiler(child)?,
            "include" => return Err(reader.unsupported(child, "inline the included file")),
            _ => {}
        }
    }
    reader.classes.insert(MAIN.into(), ClassDefaults::default());
    for child in root.children.iter().filter(|c| c.name == "default") {
        reader.defaults(child, None)?;
    }
    for asset in root.children.iter().filter(|c| c.name == "asset") {
        for mesh in asset.children.iter().filter(|c| c.name == "mesh") {
            reader.mesh_asset(mesh)?;
        }
    }
    for world in root.children.iter().filter(|c| c.name == "worldbody") {
        reader.walk(world, 0, Isometry3::identity(), MAIN, false)?;
    }
    for actuators in root.children.iter().filter(|c| c.name == "actuator") {
        reader.actuators(actuators)?;
    }
    let mut children = vec![Vec::new(); reader.bodies.len()];
    for (index, body) in reader.bodies.iter().enumerate() {
        if let Some(parent) = body.parent {
            children[parent].push(index);
        }
    }
    Ok(Model {
        name: root.get("model").unwrap_or("MuJoCo Model").to_string(),
        compiler: reader.compiler,
        bodies: reader.bodies,
        body_index: reader.body_index,
        children,
    })
}

/// `<tag name="...">` for messages.
fn describe(element: &Element) -> String {
    match element.get("name") {
        Some(name) => format!("<{} name=\"{name}\">", element.name),
        None => format!("<{}>", element.name),
    }
}

impl Reader<'_> {
    pub(super) fn error(&self, element: &Element, attribute: &str, message: String) -> RobotError {
        RobotError::Mjcf {
            source_name: self.source_name.to_string(),
            line: element.line,
            element: describe(element),
            attribute: attribute.to_string(),
            message,
        }
    }

    /// The error for a name that element kind `what` already used (MuJoCo refuses repeated
    /// names within one kind).
    pub(super) fn repeated(
        &self,
        element: &Element,
        what: &str,
        name: &str,
        first_line: usize,
    ) -> RobotError {
        let first = if first_line == 0 {
            "the world body's name".to_string()
        } else {
            format!("first used on line {first_line}")
        };
        self.error(
            element,
            "name",
            format!("a second {what} named '{name}' ({first}); MuJoCo requires {what} names to be unique"),
        )
    }

    fn unsupported(&self, element: &Element, hint: &str) -> RobotError {
        self.error(
            element,
            "-",
            format!("<{}> is not supported; {hint}", element.name),
        )
    }

    fn compiler(&mut self, element: &Element) -> Result<(), RobotError> {
        if let Some(angle) = element.get("angle") {
            self.compiler.degrees = match angle {
                "degree" => true,
                "radian" => false,
                other => {
                    return Err(self.error(
                        element,
                        "angle",
                        format!("'{other}' is neither degree nor radian"),
                    ))
                }
            };
        }
        if let Some(seq) = element.get("eulerseq") {
            let bytes = seq.as_bytes();
            let ok = bytes.len() == 3 && bytes.iter().all(|b| b"xyzXYZ".contains(b));
            if !ok {
                return Err(self.error(
                    element,
                    "eulerseq",
                    format!("'{seq}' is not three of x, y, z, X, Y, Z"),
                ));
            }
            self.compiler.euler_seq = [bytes[0], bytes[1], bytes[2]];
        }
        if let Some(dir) = element.get("meshdir").or(element.get("assetdir")) {
            self.compiler.mesh_dir = Some(dir.to_string());
        }
        if let Some(value) = element.get("autolimits") {
            self.compiler.auto_limits = self.boolean(element, "autolimits", value)?;
        }
        if let Some(value) = element.get("inertiafromgeom") {
            self.compiler.inertia_from_geom_only = match value {
                "auto" => false,
                other => self.boolean(element, "inertiafromgeom", other)?,
            };
        }
        Ok(())
    }

    /// One `<default>` element and the classes nested in it.
    fn defaults(&mut self, element: &Element, parent: Option<&str>) -> Result<(), RobotError> {
        let class = match (element.get("class"), parent) {
            (Some(class), _) => class.to_string(),
            (None, None) => MAIN.to_string(),
            (None, Some(_)) => {
                return Err(self.error(element, "class", "a nested <default> needs a class".into()))
            }
        };
        let mut values = match parent {
            Some(parent) => self.classes.get(parent).cloned().unwrap_or_default(),
            None => self.classes.get(&class).cloned().unwrap_or_default(),
        };
        if parent.is_some() && self.classes.contains_key(&class) {
            return Err(self.error(
                element,
                "class",
                format!("default class '{class}' is defined twice"),
            ));
        }
        for child in element.children.iter().filter(|c| c.name != "default") {
            self.orientation_attribute(child)?;
            values.apply(&child.name, &child.attributes);
        }
        self.classes.insert(class.clone(), values);
        for child in element.children.iter().filter(|c| c.name == "default") {
            self.defaults(child, Some(&class))?;
        }
        Ok(())
    }

    /// The class an element takes: its own `class`, else the enclosing `childclass`.
    pub(super) fn class_of<'e>(
        &self,
        element: &'e Element,
        inherited: &'e str,
    ) -> Result<&'e str, RobotError> {
        match element.get("class") {
            Some(class) => self.require_class(element, "class", class),
            None => Ok(inherited),
        }
    }

    /// `class` if it is a defined default class, else an error naming `attribute`.
    pub(super) fn require_class<'e>(
        &self,
        element: &Element,
        attribute: &str,
        class: &'e str,
    ) -> Result<&'e str, RobotError> {
        if self.classes.contains_key(class) {
            Ok(class)
        } else {
            let known: Vec<&str> = self.classes.keys().map(String::as_str).collect();
            let count = known.len();
            let close = crate::robot::error::closest_names(class, known);
            let hint = if close.is_empty() {
                String::new()
            } else {
                format!("; did you mean: {}?", close.join(", "))
            };
            Err(self.error(
                element,
                attribute,
                format!("no default class '{class}' ({count} classes defined{hint})"),
            ))
        }
    }

    /// The attribute as written, else from the element's default class.
    pub(super) fn value<'e>(
        &'e self,
        element: &'e Element,
        class: &str,
        key: &str,
    ) -> Option<&'e str> {
        element.get(key).or_else(|| {
            self.classes
                .get(class)
                .and_then(|c| c.get(&element.name, key))
        })
    }

    fn mesh_asset(&mut self, element: &Element) -> Result<(), RobotError> {
        let class = self.class_of(element, MAIN)?;
        let file = self.value(element, class, "file").map(str::to_string);
        let scale = match self.value(element, class, "scale") {
            Some(text) => {
                let v = self.vector(element, "scale", text)?;
                if v.iter().any(|s| *s == 0.0) {
                    return Err(self.error(
                        element,
                        "scale",
                        format!("must be non-zero, got \"{text}\""),
                    ));
                }
                [v.x, v.y, v.z]
            }
            None => [1.0; 3],
        };
        let name = match (element.get("name"), &file) {
            (Some(name), _) => name.to_string(),
            (None, Some(file)) => {
                let stem = std::path::Path::new(file).file_stem();
                stem.map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| file.clone())
            }
            (None, None) => {
                return Err(self.error(element, "name", "a mesh needs a name or a file".into()))
            }
        };
        if let Some(&first) = self.mesh_lines.get(&name) {
            return Err(self.repeated(element, "mesh", &name, first));
        }
        self.mesh_lines.insert(name.clone(), element.line);
        self.meshes.insert(name, MeshAsset { file, scale });
        Ok(())
    }

    /// The children of a body (or of a `<frame>` inside it, placed at `body_from_frame`).
    fn walk(
        &mut self,
        element: &Element,
        body: usize,
        body_from_frame: Isometry3<f64>,
        childclass: &str,
        in_frame: bool,
    ) -> Result<(), RobotError> {
        for child in &element.children {
            match child.name.as_str() {
                "body" => {
                    let inner = match child.get("childclass") {
                        Some(class) => self.require_class(child, "childclass", class)?,
                        None => childclass,
                    }
                    .to_string();
                    let index = self.bodies.len();
                    let name = match child.get("name") {
                        Some(name) => name.to_string(),
                        None => format!("unnamed_body_{index}"),
                    };
                    if let Some(&first) = self.body_index.get(&name) {
                        let line = self.bodies[first].line;
                        return Err(self.repeated(child, "body", &name, line));
                    }
                    let parent_from_body = body_from_frame * self.pose(child, None)?;
                    self.body_index.insert(name.clone(), index);
                    self.bodies.push(Body {
                        name,
                        line: child.line,
                        parent: Some(body),
                        parent_from_body,
                        joints: Vec::new(),
                        geoms: Vec::new(),
                        inertial: None,
                    });
                    self.walk(child, index, Isometry3::identity(), &inner, false)?;
                }
                "frame" => {
                    let inner = match child.get("childclass") {
                        Some(class) => self.require_class(child, "childclass", class)?,
                        None => childclass,
                    }
                    .to_string();
                    let frame = body_from_frame * self.pose(child, None)?;
                    self.walk(child, body, frame, &inner, true)?;
                }
                "joint" | "freejoint" => {
                    if in_frame {
                        return Err(self.unsupported(
                            child,
                            "a joint inside a <frame>: move it into the body",
                        ));
                    }
                    let k = self.bodies[body].joints.len();
                    let joint = self.joint(child, childclass, k)?;
                    if let Some(name) = child.get("name") {
                        if let Some(&(_, _, first)) = self.joint_index.get(name) {
                            return Err(self.repeated(child, "joint", name, first));
                        }
                        self.joint_index
                            .insert(name.to_string(), (body, k, child.line));
                    }
                    self.bodies[body].joints.push(joint);
                }
                "inertial" => {
                    let inertial = self.inertial(child)?;
                    self.bodies[body].inertial = Some(inertial.transformed(&body_from_frame));
                }
                "geom" => {
                    if let Some(name) = child.get("name") {
                        if let Some(&first) = self.geom_lines.get(name) {
                            return Err(self.repeated(child, "geom", name, first));
                        }
                        self.geom_lines.insert(name.to_string(), child.line);
                    }
                    if let Some(geom) = self.geom(child, childclass)? {
                        let geom = Geom {
                            body_from_geom: body_from_frame * geom.body_from_geom,
                            ..geom
                        };
                        self.bodies[body].geoms.push(geom);
                    }
                }
                "include" | "replicate" | "attach" | "composite" | "flexcomp" => {
                    return Err(self.unsupported(child, "expand it into plain bodies first"))
                }
                _ => {}
            }
        }
        Ok(())
    }

    fn joint(
        &self,
        element: &Element,
        childclass: &str,
        index: usize,
    ) -> Result<Joint, RobotError> {
        let name = element
            .get("name")
            .map_or_else(|| format!("#{index}"), str::to_string);
        if element.name == "freejoint" {
            return Ok(Joint {
                name,
                line: element.line,
                kind: JointType::Free,
                pos: Vector3::zeros(),
                axis: Vector3::z_axis(),
                range: None,
                reference: 0.0,
                effort: None,
            });
        }
        let class = self.class_of(element, childclass)?;
        let get = |key: &str| self.value(element, class, key);
        let kind = match get("type").unwrap_or("hinge") {
            "hinge" => JointType::Hinge,
            "slide" => JointType::Slide,
            "ball" => JointType::Ball,
            "free" => JointType::Free,
            other => {
                return Err(self.error(
                    element,
                    "type",
                    format!("'{other}' is not hinge, slide, ball or free"),
                ))
            }
        };
        let pos = match get("pos") {
            Some(text) => self.vector(element, "pos", text)?,
            None => Vector3::zeros(),
        };
        let axis = match get("axis") {
            Some(text) => {
                let v = self.vector(element, "axis", text)?;
                unit_axis(&v).ok_or_else(|| {
                    self.error(element, "axis", format!("must be non-zero, got \"{text}\""))
                })?
            }
            None => Vector3::z(),
        };
        let angular = kind == JointType::Hinge;
        let convert = |v: f64| if angular { self.angle(v) } else { v };
        let range_text = get("range");
        let limited = match get("limited").unwrap_or("auto") {
            "auto" => self.compiler.auto_limits && range_text.is_some(),
            value => self.boolean(element, "limited", value)?,
        };
        let range = match (limited, range_text) {
            (false, _) => None,
            (true, None) => {
                return Err(self.error(
                    element,
                    "range",
                    "the joint is limited=\"true\" but has no range".into(),
                ))
            }
            (true, Some(text)) => {
                let v = self.numbers(element, "range", text, 2..=2)?;
                if matches!(kind, JointType::Hinge | JointType::Slide) && v[0] > v[1] {
                    return Err(self.error(
                        element,
                        "range",
                        format!("lower {} is above upper {}", v[0], v[1]),
                    ));
                }
                Some((convert(v[0]), convert(v[1])))
            }
        };
        let reference = match get("ref") {
            Some(text) => convert(self.numbers(element, "ref", text, 1..=1)?[0]),
            None => 0.0,
        };
        let effort = match get("actuatorfrcrange") {
            Some(text) => self.force_range(element, "actuatorfrcrange", text, 1.0)?,
            None => None,
        };
        Ok(Joint {
            name,
            line: element.line,
            kind,
            pos,
            axis: Unit::new_unchecked(axis),
            range,
            reference,
            effort,
        })
    }
}
