//! Structure-aware generators (proptest strategies): mostly-valid URDF documents, task files
//! (YAML) and PCD files (header and payload) whose values are drawn with a bias towards
//! extremes — zero, negative, NaN, infinities, 1e300, 2³² and 10¹² counts, missing and
//! duplicated elements — so that parsing succeeds often enough to reach the code behind it.
//!
//! One file on purpose (about 700 lines): three generators sharing the same extreme-value
//! strategies.

use crate::rng::Rng;
use proptest::collection::vec;
use proptest::prelude::*;
use proptest::sample::select;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// Draws one value of `strategy`, seeded from `rng` (deterministic).
pub fn draw<S: Strategy>(strategy: &S, rng: &mut Rng) -> S::Value {
    let seed = rng.seed_bytes();
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &seed),
    );
    match strategy.new_tree(&mut runner) {
        Ok(tree) => tree.current(),
        // The strategies below use no filters, so a tree is always built.
        Err(reason) => unreachable!("strategy without filters rejected a value: {reason}"),
    }
}

const EXTREMES: &[&str] = &[
    "0",
    "-0",
    "-1",
    "1e300",
    "-1e300",
    "1e20",
    "-1e20",
    "1e-300",
    "NaN",
    "inf",
    "-inf",
    "4294967296",
    "1000000000000",
    "1.7976931348623157e308",
];

const EXTREME_COUNTS: &[&str] = &[
    "0",
    "1",
    "-1",
    "65536",
    "1000000",
    "1000000000",
    "4294967295",
    "4294967296",
    "1000000000000",
    "18446744073709551615",
    "1e9",
    "2.5",
];

/// A number as text: mostly moderate, sometimes extreme or arbitrary.
fn num() -> impl Strategy<Value = String> {
    prop_oneof![
        8 => (-2.0f64..2.0).prop_map(|v| format!("{v:.3}")),
        1 => Just("0".to_string()),
        2 => select(EXTREMES).prop_map(str::to_string),
        1 => any::<f64>().prop_map(|v| format!("{v:e}")),
    ]
}

/// A positive size as text: mostly small and valid, sometimes extreme.
fn size() -> impl Strategy<Value = String> {
    prop_oneof![
        8 => (0.001f64..0.5).prop_map(|v| format!("{v:.4}")),
        2 => select(EXTREMES).prop_map(str::to_string),
    ]
}

/// A count as text: mostly in `typical`, sometimes extreme.
fn count(typical: std::ops::Range<u64>) -> impl Strategy<Value = String> {
    prop_oneof![
        6 => typical.prop_map(|v| v.to_string()),
        1 => select(EXTREME_COUNTS).prop_map(str::to_string),
    ]
}

fn triple() -> impl Strategy<Value = String> {
    (num(), num(), num()).prop_map(|(a, b, c)| format!("{a} {b} {c}"))
}

fn yaml_triple() -> impl Strategy<Value = String> {
    (num(), num(), num()).prop_map(|(a, b, c)| format!("[{a}, {b}, {c}]"))
}

// ---------------------------------------------------------------------------------------------
// URDF

#[derive(Debug, Clone)]
struct UrdfJoint {
    kind: &'static str,
    parent: usize,
    child: usize,
    chained: bool,
    origin: Option<(String, String)>,
    axis: Option<String>,
    limit: Option<(String, String, String, String)>,
    mimic: Option<(usize, Option<String>, Option<String>)>,
}

fn urdf_geometry() -> impl Strategy<Value = String> {
    prop_oneof![
        (size(), size(), size()).prop_map(|(a, b, c)| format!("<box size=\"{a} {b} {c}\"/>")),
        (size(), size()).prop_map(|(r, l)| format!("<cylinder radius=\"{r}\" length=\"{l}\"/>")),
        size().prop_map(|r| format!("<sphere radius=\"{r}\"/>")),
        triple().prop_map(|s| format!(
            "<mesh filename=\"package://robot/meshes/part.stl\" scale=\"{s}\"/>"
        )),
    ]
}

fn urdf_link() -> impl Strategy<Value = Option<(String, String, String)>> {
    proptest::option::weighted(
        0.4,
        (urdf_geometry(), triple(), triple()).prop_map(|(g, xyz, rpy)| (g, xyz, rpy)),
    )
}

fn urdf_joint(links: usize) -> impl Strategy<Value = UrdfJoint> {
    (
        select(&[
            "revolute",
            "revolute",
            "continuous",
            "prismatic",
            "fixed",
            "floating",
            "planar",
            "spherical",
        ]),
        0..=links,
        0..=links,
        prop::bool::weighted(0.8),
        proptest::option::weighted(0.8, (triple(), triple())),
        proptest::option::weighted(0.8, triple()),
        proptest::option::weighted(0.8, (num(), num(), num(), num())),
        proptest::option::weighted(
            0.15,
            (
                0..links + 1,
                proptest::option::of(num()),
                proptest::option::of(num()),
            ),
        ),
    )
        .prop_map(
            |(kind, parent, child, chained, origin, axis, limit, mimic)| UrdfJoint {
                kind,
                parent,
                child,
                chained,
                origin,
                axis,
                limit,
                mimic,
            },
        )
}

fn render_urdf(
    name: &str,
    links: &[Option<(String, String, String)>],
    joints: &[UrdfJoint],
) -> String {
    let n = links.len();
    let link_name = |i: usize| {
        if i < n {
            format!("l{i}")
        } else {
            "ghost".to_string()
        }
    };
    let mut out = format!("<?xml version=\"1.0\"?>\n<robot name=\"{name}\">\n");
    for (i, link) in links.iter().enumerate() {
        match link {
            None => out.push_str(&format!("  <link name=\"{}\"/>\n", link_name(i))),
            Some((geometry, xyz, rpy)) => out.push_str(&format!(
                "  <link name=\"{}\">\n    <collision>\n      <origin xyz=\"{xyz}\" rpy=\"{rpy}\"/>\n      <geometry>{geometry}</geometry>\n    </collision>\n  </link>\n",
                link_name(i)
            )),
        }
    }
    for (k, j) in joints.iter().enumerate() {
        let (parent, child) = if j.chained && k + 1 < n {
            (k, k + 1)
        } else {
            (j.parent, j.child)
        };
        out.push_str(&format!(
            "  <joint name=\"j{k}\" type=\"{}\">\n    <parent link=\"{}\"/>\n    <child link=\"{}\"/>\n",
            j.kind,
            link_name(parent),
            link_name(child)
        ));
        if let Some((xyz, rpy)) = &j.origin {
            out.push_str(&format!("    <origin xyz=\"{xyz}\" rpy=\"{rpy}\"/>\n"));
        }
        if let Some(axis) = &j.axis {
            out.push_str(&format!("    <axis xyz=\"{axis}\"/>\n"));
        }
        if let Some((lower, upper, effort, velocity)) = &j.limit {
            out.push_str(&format!(
                "    <limit lower=\"{lower}\" upper=\"{upper}\" effort=\"{effort}\" velocity=\"{velocity}\"/>\n"
            ));
        }
        if let Some((other, multiplier, offset)) = &j.mimic {
            out.push_str(&format!("    <mimic joint=\"j{other}\""));
            if let Some(m) = multiplier {
                out.push_str(&format!(" multiplier=\"{m}\""));
            }
            if let Some(o) = offset {
                out.push_str(&format!(" offset=\"{o}\""));
            }
            out.push_str("/>\n");
        }
        out.push_str("  </joint>\n");
    }
    out.push_str("</robot>\n");
    out
}

/// A URDF document: 1 to 8 links, mostly chained joints of every type, with extreme origins,
/// axes, limits (sometimes missing) and mimic references (sometimes dangling).
pub fn urdf_document() -> impl Strategy<Value = String> {
    (1usize..9)
        .prop_flat_map(|n| {
            (
                select(&["r", "fuzz_robot", "", "a b"]),
                vec(urdf_link(), n),
                vec(urdf_joint(n), 0..n + 2),
            )
        })
        .prop_map(|(name, links, joints)| render_urdf(name, &links, &joints))
}

// ---------------------------------------------------------------------------------------------
// Task files

fn yaml_pose() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (yaml_triple(), proptest::option::of(yaml_triple())).prop_map(|(xyz, rpy)| match rpy {
            Some(rpy) => format!("{{ xyz: {xyz}, rpy: {rpy} }}"),
            None => format!("{{ xyz: {xyz} }}"),
        }),
        1 => (yaml_triple(), num(), num(), num(), num()).prop_map(|(xyz, a, b, c, d)| format!(
            "{{ xyz: {xyz}, quaternion: [{a}, {b}, {c}, {d}] }}"
        )),
        1 => (yaml_triple(), yaml_triple()).prop_map(|(xyz, rpy)| format!(
            "{{ xyz: {xyz}, rpy_deg: {rpy} }}"
        )),
        1 => vec(num(), 16).prop_map(|v| format!(
            "{{ matrix: [[{}], [{}], [{}], [{}]] }}",
            v[0..4].join(", "), v[4..8].join(", "), v[8..12].join(", "), v[12..16].join(", ")
        )),
    ]
}

fn yaml_shape() -> impl Strategy<Value = String> {
    prop_oneof![
        (size(), size(), size())
            .prop_map(|(a, b, c)| format!("{{ box: {{ size: [{a}, {b}, {c}] }} }}")),
        (size(), size())
            .prop_map(|(r, l)| format!("{{ cylinder: {{ radius: {r}, length: {l} }} }}")),
        (size(), size(), size(), size(), size()).prop_map(|(a, b, c, r, l)| format!(
            "{{ t_shape: {{ bar: [{a}, {b}, {c}], stem: {{ cylinder: {{ radius: {r}, length: {l} }} }} }} }}"
        )),
    ]
}

fn yaml_candidates() -> impl Strategy<Value = String> {
    prop_oneof![
        (
            count(1..40),
            proptest::option::of(num()),
            proptest::option::of(num())
        )
            .prop_map(|(c, d, m)| {
                let mut s = format!("{{ family: {{ edge: {{ count: {c}");
                if let Some(d) = d {
                    s.push_str(&format!(", depth: {d}"));
                }
                if let Some(m) = m {
                    s.push_str(&format!(", margin: {m}"));
                }
                s + " } } }"
            }),
        (count(1..40), num(), proptest::option::of(num())).prop_map(|(c, step, start)| {
            let mut s = format!("{{ family: {{ yaw: {{ count: {c}, step_deg: {step}");
            if let Some(start) = start {
                s.push_str(&format!(", start_deg: {start}"));
            }
            s + " } } }"
        }),
        (
            count(1..20),
            select(&["[]", "[top]", "[bottom, x+]", "[nonsense]"])
        )
            .prop_map(|(c, ex)| format!(
                "{{ family: {{ faces: {{ count: {c}, exclude: {ex} }} }} }}"
            )),
        select(&["candidates.json", "candidates.csv", "missing.json"])
            .prop_map(|f| format!("{{ file: {f} }}")),
    ]
}

fn yaml_step() -> impl Strategy<Value = String> {
    (
        prop_oneof![
            num().prop_map(|v| format!("lift: {v}")),
            num().prop_map(|v| format!("place: {v}")),
            yaml_triple().prop_map(|v| format!("move: {v}")),
            (proptest::option::of(yaml_triple()), num()).prop_map(|(axis, angle)| match axis {
                Some(axis) => format!("rotate: {{ axis: {axis}, angle_deg: {angle} }}"),
                None => format!("rotate: {{ angle_deg: {angle} }}"),
            }),
            yaml_pose().prop_map(|p| format!("pose: {p}")),
        ],
        proptest::option::weighted(0.3, num()),
        proptest::option::weighted(0.2, select(&["pick", "move", ""])),
    )
        .prop_map(|(body, duration, label)| {
            let mut s = format!("{{ {body}");
            if let Some(d) = duration {
                s.push_str(&format!(", duration: {d}"));
            }
            if let Some(l) = label {
                s.push_str(&format!(", label: \"{l}\""));
            }
            s + " }"
        })
}

fn yaml_robot() -> impl Strategy<Value = (String, Option<String>)> {
    prop_oneof![
        3 => select(&[None, Some("left"), Some("right"), Some("[left, right]"), Some("[left, left]")])
            .prop_map(|arms| ("{ builtin: baxter }".to_string(), arms.map(str::to_string))),
        2 => (proptest::option::of(yaml_pose()), select(&["base", "l1", "nowhere"]), select(&["tip", "l1", "base"]))
            .prop_map(|(pose, base, tip)| {
                let pose = pose.map(|p| format!(", base_pose: {p}")).unwrap_or_default();
                (
                    format!("{{ urdf: robot.urdf, chains: {{ arm: {{ base: {base}, tip: {tip}{pose} }} }} }}"),
                    Some("arm".to_string()),
                )
            }),
        1 => Just(("{ builtin: ur5 }".to_string(), None)),
    ]
}

/// A task file (YAML): a robot, an object, candidates, a trajectory and the index, selection
/// and IK sections, with extreme sizes, counts and sample numbers.
pub fn task_yaml() -> impl Strategy<Value = String> {
    (
        yaml_robot(),
        yaml_pose(),
        proptest::option::weighted(0.8, yaml_shape()),
        yaml_candidates(),
        vec(yaml_step(), 0..5),
        (
            proptest::option::weighted(0.4, count(2..50)),
            proptest::option::weighted(0.3, count(1..30)),
            proptest::option::weighted(0.2, (size(), num())),
        ),
        (
            select(&["twist", "translation", "rotation", "bogus"]),
            proptest::option::weighted(0.3, num()),
        ),
        (
            select(&["l2", "l1"]),
            proptest::option::weighted(0.3, num()),
            proptest::option::weighted(0.3, count(1..20)),
            proptest::option::weighted(0.3, num()),
            select(&[
                "product",
                "ignore",
                "{ weighted: { weight: 0.5 } }",
                "{ weighted: { weight: -1 } }",
            ]),
        ),
        (
            proptest::option::weighted(0.3, num()),
            proptest::option::weighted(0.3, count(1..8)),
            proptest::option::weighted(0.3, count(1..500)),
            proptest::option::weighted(0.3, num()),
            any::<bool>(),
        ),
    )
        .prop_map(
            |(
                (robot, arms),
                object_pose,
                shape,
                candidates,
                steps,
                (samples, per_step, spacing),
                (mode, length_scale),
                (norm, mu0, pairs, separation, likelihood),
                (joint_step, branches, iterations, tolerance, compare),
            )| {
                let mut s = format!("robot: {robot}\n");
                if let Some(arms) = arms {
                    s.push_str(&format!("arms: {arms}\n"));
                }
                s.push_str(&format!("object:\n  pose: {object_pose}\n"));
                if let Some(shape) = shape {
                    s.push_str(&format!("  shape: {shape}\n"));
                }
                s.push_str(&format!("candidates: {candidates}\ntrajectory:\n"));
                if let Some(n) = samples {
                    s.push_str(&format!("  samples: {n}\n"));
                }
                if let Some(n) = per_step {
                    s.push_str(&format!("  samples_per_step: {n}\n"));
                }
                if let Some((t, r)) = spacing {
                    s.push_str(&format!(
                        "  spacing: {{ translation: {t}, rotation_deg: {r} }}\n"
                    ));
                }
                s.push_str("  steps:\n");
                for step in &steps {
                    s.push_str(&format!("    - {step}\n"));
                }
                s.push_str(&format!("index: {{ mode: {mode}"));
                if let Some(l) = length_scale {
                    s.push_str(&format!(", length_scale: {l}"));
                }
                s.push_str(&format!(
                    " }}\nselection: {{ norm: {norm}, likelihood: {likelihood}"
                ));
                if let Some(m) = mu0 {
                    s.push_str(&format!(", mu0: {m}"));
                }
                if let Some(p) = pairs {
                    s.push_str(&format!(", pairs: {p}"));
                }
                if let Some(d) = separation {
                    s.push_str(&format!(", min_separation: {d}"));
                }
                s.push_str(&format!(
                    " }}\nik: {{ redundancy: {}",
                    if compare { "best_branch" } else { "first" }
                ));
                if let Some(v) = joint_step {
                    s.push_str(&format!(", max_joint_step: {v}"));
                }
                if let Some(v) = branches {
                    s.push_str(&format!(", branches: {v}"));
                }
                if let Some(v) = iterations {
                    s.push_str(&format!(", iterations: {v}"));
                }
                if let Some(v) = tolerance {
                    s.push_str(&format!(", tolerance: {v}"));
                }
                s.push_str(" }\n");
                s
            },
        )
}

// ---------------------------------------------------------------------------------------------
// PCD

#[derive(Debug, Clone)]
struct PcdField {
    name: &'static str,
    size: &'static str,
    kind: &'static str,
    count: &'static str,
}

fn pcd_field() -> impl Strategy<Value = PcdField> {
    (
        select(&[
            "x",
            "y",
            "z",
            "normal_x",
            "normal_y",
            "normal_z",
            "rgb",
            "intensity",
            "_",
        ]),
        prop_oneof![6 => Just("4"), 1 => select(&["8", "1", "2", "0", "3", "16"])],
        prop_oneof![6 => Just("F"), 1 => select(&["I", "U", "X", "f"])],
        prop_oneof![8 => Just("1"), 1 => select(&["0", "3", "4294967295", "1000000000000", "-1"])],
    )
        .prop_map(|(name, size, kind, count)| PcdField {
            name,
            size,
            kind,
            count,
        })
}

/// An LZF stream made only of literal runs (valid LZF) holding `raw`.
pub fn lzf_literals(raw: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(raw.len() + raw.len() / 32 + 1);
    for chunk in raw.chunks(32) {
        out.push((chunk.len() - 1) as u8);
        out.extend_from_slice(chunk);
    }
    out
}

/// A PCD file: a header whose field lists, sizes, types, counts, WIDTH/HEIGHT/POINTS and DATA
/// kind are drawn with extremes and inconsistencies, followed by a payload of 0 to 6 points
/// (ascii numbers, binary records, or an LZF stream whose announced sizes may lie).
pub fn pcd_file() -> impl Strategy<Value = Vec<u8>> {
    let standard = Just(vec![
        PcdField {
            name: "x",
            size: "4",
            kind: "F",
            count: "1",
        },
        PcdField {
            name: "y",
            size: "4",
            kind: "F",
            count: "1",
        },
        PcdField {
            name: "z",
            size: "4",
            kind: "F",
            count: "1",
        },
    ]);
    (
        prop_oneof![3 => standard, 2 => vec(pcd_field(), 1..7)],
        prop::bool::weighted(0.3),
        (0usize..7, count(1..7), count(1..3), proptest::option::weighted(0.5, count(1..7))),
        select(&["ascii", "binary", "binary_compressed", "binary_compressed", "binary_compressed", "bogus"]),
        (0usize..4, any::<u64>(), vec(num(), 0..48)),
        select(&["VERSION 0.7", "VERSION .7", "VERSION 0.6", "VERSION x"]),
        prop::bool::weighted(0.1),
    )
        .prop_map(
            |(mut fields, normals, (points, width, height, announced), data, (lie, seed, numbers), version, bad_list)| {
                if normals {
                    for name in ["normal_x", "normal_y", "normal_z"] {
                        fields.push(PcdField { name, size: "4", kind: "F", count: "1" });
                    }
                }
                let list = |f: &dyn Fn(&PcdField) -> &'static str| {
                    let mut items: Vec<&str> = fields.iter().map(f).collect();
                    if bad_list {
                        items.pop();
                    }
                    items.join(" ")
                };
                let width = if lie == 0 { width } else { points.to_string() };
                let announced = announced.unwrap_or_else(|| points.to_string());
                let mut out = format!(
                    "# .PCD v0.7 - Point Cloud Data file format\n{version}\nFIELDS {}\nSIZE {}\nTYPE {}\nCOUNT {}\nWIDTH {width}\nHEIGHT {height}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {announced}\nDATA {data}\n",
                    list(&|f| f.name),
                    list(&|f| f.size),
                    list(&|f| f.kind),
                    list(&|f| f.count),
                )
                .into_bytes();
                let mut rng = Rng::new(seed);
                let record: usize = fields
                    .iter()
                    .map(|f| f.size.parse::<usize>().unwrap_or(4) * f.count.parse::<usize>().unwrap_or(1).min(4))
                    .sum();
                let mut value = |k: usize| -> f32 {
                    numbers
                        .get(k % numbers.len().max(1))
                        .and_then(|s| s.parse::<f32>().ok())
                        .unwrap_or_else(|| (rng.below(2000) as f32 - 1000.0) * 1e-3)
                };
                match data {
                    "ascii" => {
                        for p in 0..points {
                            let line: Vec<String> = (0..fields.len())
                                .map(|k| value(p * fields.len() + k).to_string())
                                .collect();
                            out.extend_from_slice(line.join(" ").as_bytes());
                            out.push(b'\n');
                        }
                    }
                    "binary" => {
                        for k in 0..points * record / 4 {
                            out.extend_from_slice(&value(k).to_le_bytes());
                        }
                    }
                    _ => {
                        let raw: Vec<u8> = (0..points * record / 4)
                            .flat_map(|k| value(k).to_le_bytes())
                            .collect();
                        let compressed = lzf_literals(&raw);
                        let (c, r) = match lie {
                            0 | 1 => (compressed.len(), raw.len()),
                            2 => (compressed.len() + 7, raw.len()),
                            _ => (compressed.len(), raw.len() / 2 + 1),
                        };
                        out.extend_from_slice(&(c as u32).to_le_bytes());
                        out.extend_from_slice(&(r as u32).to_le_bytes());
                        out.extend_from_slice(&compressed);
                    }
                }
                out
            },
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_are_deterministic() {
        let a = draw(&urdf_document(), &mut Rng::new(5));
        let b = draw(&urdf_document(), &mut Rng::new(5));
        assert_eq!(a, b);
        assert!(a.starts_with("<?xml"));
    }

    #[test]
    fn generated_documents_often_parse() {
        // Structure-aware generation is only useful if much of it gets past the parser.
        let mut rng = Rng::new(1);
        let urdf_ok = (0..200)
            .filter(|_| {
                graspath::robot::UrdfRobot::from_xml(&draw(&urdf_document(), &mut rng), "g.urdf")
                    .is_ok()
            })
            .count();
        assert!(urdf_ok > 60, "{urdf_ok} of 200 URDF documents parsed");
        let task_ok = (0..200)
            .filter(|_| {
                graspath::task::TaskFile::parse(&draw(&task_yaml(), &mut rng), "g.yaml", "yaml")
                    .is_ok()
            })
            .count();
        // Shapes are checked while parsing (a negative size is a parse error), so fewer of the
        // extreme documents get through than URDFs do.
        assert!(task_ok > 40, "{task_ok} of 200 task files parsed");
        // The PCD reader now refuses every header whose counts disagree (WIDTH × HEIGHT,
        // POINTS, the bytes present), which most generated headers do; a few still get through
        // to the payload decoders. A panic counts as not parsed.
        let pcd_ok = (0..400)
            .filter(|_| {
                let file = draw(&pcd_file(), &mut rng);
                std::panic::catch_unwind(|| graspath::cloud::read_pcd_bytes(&file, "g.pcd").is_ok())
                    .unwrap_or(false)
            })
            .count();
        assert!(pcd_ok > 5, "{pcd_ok} of 400 PCD files parsed");
    }

    #[test]
    fn lzf_literal_stream_round_trips_through_the_pcd_reader() {
        // Independent check of the literal encoder: a hand-built compressed PCD reads back.
        let values = [0.5f32, -1.0, 2.0, 0.25, 0.0, 3.0];
        let raw: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        // Field-major: x of both points, then y, then z.
        let compressed = lzf_literals(&raw);
        let mut file = b"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA binary_compressed\n".to_vec();
        file.extend_from_slice(&(compressed.len() as u32).to_le_bytes());
        file.extend_from_slice(&(raw.len() as u32).to_le_bytes());
        file.extend_from_slice(&compressed);
        let cloud = graspath::cloud::read_pcd_bytes(&file, "c.pcd").expect("valid file");
        assert_eq!(cloud.points.len(), 2);
        assert_eq!(cloud.points[0], nalgebra::Point3::new(0.5, 2.0, 0.0));
        assert_eq!(cloud.points[1], nalgebra::Point3::new(-1.0, 0.25, 3.0));
    }
}
