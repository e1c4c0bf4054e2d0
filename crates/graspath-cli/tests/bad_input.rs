//! The bad-input table: one row per bad input (command line, files written into a fresh
//! temporary folder, the expected exit code and a fragment of the one-line message). For every
//! row the binary must not panic, must print nothing on stdout when it fails, and must leave the
//! folder exactly as it found it — no output file or folder, no temporary file — except for the
//! entries a row says it leaves (`nothing selected` still writes its results).
//!
//! Adding a row is one line: `row(name, "args with {d} for the folder", &[(file, text)], code,
//! "fragment")`, plus `.stdin(..)`, `.setup(..)` or `.leaves(..)` when needed.

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// One row of the table.
struct Row {
    name: &'static str,
    args: &'static str,
    files: &'static [(&'static str, &'static str)],
    code: i32,
    message: &'static str,
    stdin: &'static str,
    setup: Option<fn(&Path)>,
    leaves: &'static [&'static str],
}

fn row(
    name: &'static str,
    args: &'static str,
    files: &'static [(&'static str, &'static str)],
    code: i32,
    message: &'static str,
) -> Row {
    Row {
        name,
        args,
        files,
        code,
        message,
        stdin: "",
        setup: None,
        leaves: &[],
    }
}

impl Row {
    fn stdin(mut self, text: &'static str) -> Self {
        self.stdin = text;
        self
    }
    fn setup(mut self, setup: fn(&Path)) -> Self {
        self.setup = Some(setup);
        self
    }
    fn leaves(mut self, entries: &'static [&'static str]) -> Self {
        self.leaves = entries;
        self
    }
}

/// A task whose IK tolerance would accept any pose.
const TASK_HUGE_IK_TOLERANCE: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { family: { edge: { count: 5 } } }
trajectory: { steps: [ { lift: 0.2 } ] }
ik: { tolerance: 1e308 }
"#;

/// A task whose robot is a URDF in the folder `robot/`.
const TASK_URDF_IN_FOLDER: &str = r#"
robot: { urdf: robot/arm.urdf, chains: { arm: { base: a, tip: b } } }
object: { pose: { xyz: [0.75, 0.0, -0.10] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { family: { edge: { count: 5 } } }
trajectory: { steps: [ { lift: 0.2 } ] }
"#;

const TASK: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { family: { edge: { count: 5 } } }
trajectory:
  samples_per_step: 3
  steps: [ { lift: 0.2 }, { move: [0, 0.3, 0] }, { place: 0.2 } ]
"#;

/// The task with a scene obstacle read from the cloud `c.ply`.
const TASK_SCENE_CLOUD: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { family: { edge: { count: 5 } } }
trajectory: { samples_per_step: 3, steps: [ { lift: 0.2 } ] }
scene: { obstacles: [ { name: scan, cloud: c.ply, radius: 0.01 } ] }
"#;

/// The task file with the candidates read from `c.json` / `c.csv`.
const TASK_FILE_JSON: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { file: c.json }
trajectory: { samples_per_step: 3, steps: [ { lift: 0.2 } ] }
"#;
const TASK_FILE_CSV: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { file: c.csv }
trajectory: { samples_per_step: 3, steps: [ { lift: 0.2 } ] }
"#;
/// The task file with the candidates read from a generator's grasp file `g.*` (copied from
/// graspath's `tests/data/grasp_files/bad/` by the row's setup).
const TASK_GRASP_H5: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] } }
candidates: { file: g.h5 }
trajectory: { samples_per_step: 3, steps: [ { lift: 0.2 } ] }
"#;
const TASK_GRASP_NPY: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] } }
candidates: { file: g.npy }
trajectory: { samples_per_step: 3, steps: [ { lift: 0.2 } ] }
"#;
const TASK_GRASP_NPZ: &str = r#"
robot: { builtin: baxter }
arms: left
object: { pose: { xyz: [0.75, 0.0, -0.10] } }
candidates: { file: g.npz, world_from_camera: { xyz: [0, 0, 1] } }
trajectory: { samples_per_step: 3, steps: [ { lift: 0.2 } ] }
"#;

/// Copies the bad grasp file `name` of graspath's test data to `dir/to`.
fn bad_grasp_file(name: &str, dir: &Path, to: &str) {
    let from = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../graspath/tests/data/grasp_files/bad")
        .join(name);
    std::fs::copy(&from, dir.join(to)).unwrap_or_else(|e| panic!("{}: {e}", from.display()));
}

const TASK_URDF: &str = r#"
robot: { urdf: two.urdf, chains: { left: { base: base, tip: nope } } }
arms: left
object: { pose: { xyz: [0.3, 0.0, 0.0] }, shape: { box: { size: [0.06, 0.40, 0.10] } } }
candidates: { family: { edge: { count: 3 } } }
trajectory: { samples_per_step: 3, steps: [ { lift: 0.2 } ] }
"#;
const TWO_LINK_URDF: &str = r#"<robot name="two">
  <link name="base"/><link name="l1"/><link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="tip"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"#;
const IDENTITY: &str = r#"{"pose":[[1,0,0,0.5],[0,1,0,0.2],[0,0,1,0.1],[0,0,0,1]]}"#;

/// Task variants by file name (`v-NAME.yaml`): `TASK` with `from` replaced by `to` (once).
fn variants() -> BTreeMap<&'static str, (&'static str, &'static str)> {
    BTreeMap::from([
        (
            "v-unknown-field.yaml",
            ("arms: left", "arms: left\ncolour: red"),
        ),
        ("v-unknown-arm.yaml", ("arms: left", "arms: middle")),
        (
            "v-obstacle-cone.yaml",
            (
                "arms: left",
                "arms: left\nscene: { obstacles: [ { name: c, cone: { radius: 0.1 } } ] }",
            ),
        ),
        (
            "v-obstacle-mesh-missing.yaml",
            (
                "arms: left",
                "arms: left\nscene: { obstacles: [ { name: bin, mesh: no-bin.stl } ] }",
            ),
        ),
        (
            "v-obstacle-mesh-broken.yaml",
            (
                "arms: left",
                "arms: left\nscene: { obstacles: [ { name: bin, mesh: broken.stl } ] }",
            ),
        ),
        (
            "v-srdf-unknown-link.yaml",
            (
                "arms: left",
                "arms: left\nscene: {}\ncollision: { srdf: robot.srdf }",
            ),
        ),
        (
            "v-gripper-opening-zero.yaml",
            ("arms: left", "arms: left\ngripper: { opening: 0 }"),
        ),
        (
            "v-xyz-short.yaml",
            ("xyz: [0.75, 0.0, -0.10]", "xyz: [0.75, 0.0]"),
        ),
        (
            "v-xyz-nan.yaml",
            ("xyz: [0.75, 0.0, -0.10]", "xyz: [.nan, 0.0, -0.10]"),
        ),
        (
            "v-two-rotations.yaml",
            (
                "xyz: [0.75, 0.0, -0.10] }",
                "xyz: [0.75, 0.0, -0.10], rpy: [0, 0, 0], rpy_deg: [0, 0, 0] }",
            ),
        ),
        (
            "v-negative-duration.yaml",
            ("{ lift: 0.2 }", "{ lift: 0.2, duration: -1 }"),
        ),
        ("v-unknown-step.yaml", ("{ lift: 0.2 }", "{ lfit: 0.2 }")),
        ("v-builtin-kuka.yaml", ("builtin: baxter", "builtin: kuka")),
        (
            "v-missing-urdf.yaml",
            (
                "{ builtin: baxter }",
                "{ urdf: missing.urdf, chains: { left: { base: a, tip: b } } }",
            ),
        ),
        (
            "v-box-size.yaml",
            ("size: [0.06, 0.40, 0.10]", "size: [0.06, -0.40, 0.10]"),
        ),
        (
            "v-norm.yaml",
            ("arms: left", "arms: left\nselection: { norm: l3 }"),
        ),
        (
            "v-mode.yaml",
            ("arms: left", "arms: left\nindex: { mode: sideways }"),
        ),
        (
            "v-missing-candidates.yaml",
            (
                "candidates: { family: { edge: { count: 5 } } }",
                "candidates: { file: nowhere.json }",
            ),
        ),
        (
            "v-two-sources.yaml",
            (
                "candidates: { family: { edge: { count: 5 } } }",
                "candidates: { file: c.json, family: { edge: { count: 5 } } }",
            ),
        ),
        (
            "v-unknown-family.yaml",
            ("edge: { count: 5 }", "spiral: { count: 5 }"),
        ),
        (
            "v-far.yaml",
            ("xyz: [0.75, 0.0, -0.10]", "xyz: [3.0, 0.0, -0.10]"),
        ),
        (
            "v-far-both.yaml",
            (
                "arms: left\nobject: { pose: { xyz: [0.75, 0.0, -0.10] }",
                "arms: both\nobject: { pose: { xyz: [3.0, 0.0, -0.10] }",
            ),
        ),
        ("v-bad-yaml.yaml", ("arms: left", "arms: [left")),
        (
            "v-samples-huge.yaml",
            ("samples_per_step: 3", "samples_per_step: 1000000000"),
        ),
        (
            "v-samples-total-huge.yaml",
            ("samples_per_step: 3", "samples: 1000000000"),
        ),
        (
            "v-spacing-tiny.yaml",
            (
                "samples_per_step: 3",
                "spacing: { translation: 1.0e-12, rotation_deg: 1 }",
            ),
        ),
        (
            "v-count-huge.yaml",
            ("edge: { count: 5 }", "edge: { count: 1000000000 }"),
        ),
        (
            "v-iterations-huge.yaml",
            ("arms: left", "arms: left\nik: { iterations: 4294967296 }"),
        ),
        (
            "v-branches-huge.yaml",
            ("arms: left", "arms: left\nik: { branches: 100000 }"),
        ),
        (
            "v-work-huge.yaml",
            (
                "arms: left",
                "arms: left\nik: { iterations: 1000000 }\nlimits: { max_work: 1000000 }",
            ),
        ),
        (
            "v-memory-tight.yaml",
            ("arms: left", "arms: left\nlimits: { max_memory_mib: 0 }"),
        ),
        (
            "v-limits-unknown.yaml",
            ("arms: left", "arms: left\nlimits: { max_sample: 10 }"),
        ),
        (
            "v-quaternion-norm.yaml",
            (
                "xyz: [0.75, 0.0, -0.10]",
                "xyz: [0.75, 0.0, -0.10], quaternion: [0, 0, 0, 2]",
            ),
        ),
    ])
}

fn table() -> Vec<Row> {
    vec![
        // Usage (clap).
        row("no subcommand", "", &[], 2, "Usage"),
        row("unknown subcommand", "frobnicate", &[], 2, "unrecognized subcommand 'frobnicate'"),
        row("select without --task", "select --out {d}/out", &[], 2, "--task"),
        row("unknown option", "select --task {d}/t.yaml --bogus", &[("t.yaml", TASK)], 2, "unexpected argument '--bogus'"),
        row("tolerance not a number", "ik --robot baxter --tolerance abc", &[], 2, "invalid value 'abc'"),
        row("urdf without base", "kinematics --urdf {d}/two.urdf", &[("two.urdf", TWO_LINK_URDF)], 2, "--base"),
        // Task files.
        row("missing task file", "select --task {d}/missing.yaml --out {d}/out", &[], 2, "missing.yaml"),
        row("task yaml syntax", "select --task {d}/v-bad-yaml.yaml --out {d}/out", &[], 2, "v-bad-yaml.yaml"),
        row("task unknown field", "select --task {d}/v-unknown-field.yaml --out {d}/out", &[], 2, "unknown field `colour`"),
        row("task unknown arm", "select --task {d}/v-unknown-arm.yaml --out {d}/out", &[], 2, "middle"),
        row("task pose xyz short", "select --task {d}/v-xyz-short.yaml --out {d}/out", &[], 2, "object.pose"),
        row("task pose NaN", "select --task {d}/v-xyz-nan.yaml --out {d}/out", &[], 2, "line 4 column 25: non-finite float"),
        row("task pose two rotations", "select --task {d}/v-two-rotations.yaml --out {d}/out", &[], 2, "object.pose"),
        row("task negative duration", "select --task {d}/v-negative-duration.yaml --out {d}/out", &[], 2, "trajectory.steps[0].duration"),
        row("task unknown obstacle type", "select --task {d}/v-obstacle-cone.yaml --out {d}/out", &[], 2, "unknown field `cone`"),
        row("task obstacle mesh missing", "select --task {d}/v-obstacle-mesh-missing.yaml --out {d}/out", &[], 2, "scene.obstacles[0].mesh"),
        row("task obstacle mesh broken", "select --task {d}/v-obstacle-mesh-broken.yaml --out {d}/out", &[("broken.stl", "solid x\nendsolid x\n")], 2, "scene.obstacles[0].mesh"),
        row("task srdf unknown link", "select --task {d}/v-srdf-unknown-link.yaml --out {d}/out", &[("robot.srdf", "<robot name=\"baxter\"><disable_collisions link1=\"left_wrist\" link2=\"left_wirst\"/></robot>")], 2, "left_wirst"),
        row("task gripper opening 0", "select --task {d}/v-gripper-opening-zero.yaml --out {d}/out", &[], 2, "gripper.opening"),
        row("task unknown step", "select --task {d}/v-unknown-step.yaml --out {d}/out", &[], 2, "lfit"),
        row("task unknown builtin", "select --task {d}/v-builtin-kuka.yaml --out {d}/out", &[], 2, "kuka"),
        row("task missing urdf", "select --task {d}/v-missing-urdf.yaml --out {d}/out", &[], 2, "missing.urdf"),
        row("task negative box size", "select --task {d}/v-box-size.yaml --out {d}/out", &[], 2, "object.shape"),
        row("task samples per step 1e9", "select --task {d}/v-samples-huge.yaml --out {d}/out", &[], 2, "more than the limit 100000"),
        row("task total samples 1e9", "select --task {d}/v-samples-total-huge.yaml --out {d}/out", &[], 2, "raise limits.max_samples"),
        row("task spacing 1e-12 m", "select --task {d}/v-spacing-tiny.yaml --out {d}/out", &[], 2, "field 'trajectory'"),
        row("task family count 1e9", "select --task {d}/v-count-huge.yaml --out {d}/out", &[], 2, "candidates.family.edge.count"),
        row("task ik iterations 2^32", "select --task {d}/v-iterations-huge.yaml --out {d}/out", &[], 2, "field 'ik.iterations'"),
        row("task ik branches 1e5", "select --task {d}/v-branches-huge.yaml --out {d}/out", &[], 2, "field 'ik.branches'"),
        row("task work beyond its limit", "select --task {d}/v-work-huge.yaml --out {d}/out", &[], 2, "raise limits.max_work"),
        row("selection held whole beyond the memory limit", "select --task {d}/v-memory-tight.yaml --out {d}/out", &[], 2, "limits.max_memory_mib"),
        row("task limits unknown field", "select --task {d}/v-limits-unknown.yaml --out {d}/out", &[], 2, "limits.max_sample"),
        row("task quaternion norm 2", "select --task {d}/v-quaternion-norm.yaml --out {d}/out", &[], 2, "object.pose.quaternion"),
        row("task unknown norm", "select --task {d}/v-norm.yaml --out {d}/out", &[], 2, "l3"),
        row("task unknown index mode", "select --task {d}/v-mode.yaml --out {d}/out", &[], 2, "sideways"),
        row("task unknown family", "select --task {d}/v-unknown-family.yaml --out {d}/out", &[], 2, "spiral"),
        row("task two candidate sources", "select --task {d}/v-two-sources.yaml --out {d}/out", &[], 2, "candidates"),
        row("task urdf missing link", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_URDF), ("two.urdf", TWO_LINK_URDF)], 2, "no link named 'nope'"),
        row("task file over the size cap", "select --task {d}/t.yaml --out {d}/out", &[], 2, "t.yaml: cannot read: the file is larger than 268435456 bytes").setup(|d| sparse(d, "t.yaml", graspath::input::MAX_TASK_FILE_BYTES + 1)),
        row("task urdf over the size cap", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_URDF)], 2, "two.urdf: cannot read: the file is larger than 268435456 bytes").setup(|d| sparse(d, "two.urdf", graspath::input::MAX_ROBOT_FILE_BYTES + 1)),
        row("scene cloud over the size cap", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_SCENE_CLOUD)], 2, "c.ply: the file is larger than 4294967296 bytes").setup(|d| sparse(d, "c.ply", graspath::input::MAX_CLOUD_FILE_BYTES + 1)),
        row("task urdf malformed", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_URDF), ("two.urdf", "<robot name=\"x\"><link></robot>")], 2, "two.urdf"),
        // Candidate files.
        row("candidates file missing", "select --task {d}/v-missing-candidates.yaml --out {d}/out", &[], 2, "nowhere.json: file: cannot read: No such file"),
        row("candidates file over the size cap", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON)], 2, "c.json: file: cannot read: the file is larger than 1073741824 bytes").setup(|d| sparse(d, "c.json", (1 << 30) + 1)), // the documented cap: 1 GiB
        row("candidates empty", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON), ("c.json", r#"{"candidates":[]}"#)], 2, "contains no candidates"),
        row("candidates non-unit quaternion", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON), ("c.json", r#"[{"xyz":[0,0,0.05],"quaternion":[0,0,0,1.1]}]"#)], 2, "candidates[0].quaternion: must be a unit quaternion [x, y, z, w] (its norm is 1.100000"),
        row("candidates zero quaternion", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON), ("c.json", r#"[{"xyz":[0,0,0.05],"quaternion":[0,0,0,0]}]"#)], 2, "candidates[0].quaternion"),
        row("candidates duplicate id", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON), ("c.json", r#"[{"id":4,"xyz":[0,0,0.05],"quaternion":[0,0,0,1]},{"id":4,"xyz":[0,0,0.05],"quaternion":[0,0,0,1]}]"#)], 2, "id 4 is used twice (also by candidates[0])"),
        row("candidates far wrist", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON), ("c.json", r#"[{"xyz":[0,0,50],"quaternion":[0,0,0,1]}]"#)], 2, "are the units metres?"),
        row("candidates unknown field", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON), ("c.json", r#"[{"xyz":[0,0,0.05],"quaternion":[0,0,0,1],"score":2}]"#)], 2, "unknown field `score`"),
        row("candidates skewed matrix", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON), ("c.json", r#"[{"object_from_wrist":[[1,0.5,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]"#)], 2, "not orthonormal"),
        row("candidates wrong frame", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON), ("c.json", r#"{"frame":"world","candidates":[{"xyz":[0,0,0],"quaternion":[0,0,0,1]}]}"#)], 2, "object frame"),
        row("candidates negative likelihood", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_JSON), ("c.json", r#"[{"xyz":[0,0,0.05],"quaternion":[0,0,0,1],"likelihood":-1}]"#)], 2, "candidates[0].likelihood"),
        row("candidates csv NaN", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_CSV), ("c.csv", "x,y,z,qx,qy,qz,qw\n0,0,0.05,0,0,0,1\nNaN,0,0,0,0,0,1\n")], 2, "line 3: xyz: not finite"),
        // Generator grasp files (docs/grasp-files.md).
        row("grasp h5 without transforms", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_H5)], 2, "g.h5: grasps/transforms: dataset missing").setup(|d| bad_grasp_file("no_transforms.h5", d, "g.h5")),
        row("grasp h5 huge dataspace", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_H5)], 2, "g.h5: grasps/transforms: declares shape (1099511627776, 4, 4)").setup(|d| bad_grasp_file("huge_header.h5", d, "g.h5")),
        row("grasp npz wrong shape", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_NPZ)], 2, "g.npz: pred_grasps_cam: has shape (3, 4), expected (N, 4, 4)").setup(|d| bad_grasp_file("wrong_shape.npz", d, "g.npz")),
        row("grasp npy not rigid", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_NPY)], 2, "g.npy: g[1]: the 3×3 rotation block is not orthonormal").setup(|d| bad_grasp_file("not_rigid.npy", d, "g.npy")),
        row("grasp npy NaN", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_NPY)], 2, "g.npy: g[0]: entry [2][3] is not a finite number").setup(|d| bad_grasp_file("nan.npy", d, "g.npy")),
        row("grasp npy empty", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_NPY), ("g.npy", "")], 2, "g.npy: file: is empty"),
        row("grasp npz pickle memo bomb", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_NPZ)], 2, "g.npz: pred_grasps_cam: the pickle decodes to more than").setup(|d| bad_grasp_file("memo_bomb.npz", d, "g.npz")),
        row("grasp npz pickle nested 1000 deep", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_NPZ)], 2, "g.npz: pred_grasps_cam: the pickle nests containers more than 64 deep").setup(|d| bad_grasp_file("deep_pickle.npz", d, "g.npz")),
        row("grasp npz complex", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_NPZ)], 2, "g.npz: pred_grasps_cam: dtype 'c8' holds complex numbers").setup(|d| bad_grasp_file("complex_segments.npz", d, "g.npz")),
        row("grasp npy 13-byte header of 4 GiB", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_NPY)], 2, "g.npy: file: the .npy header declares 4294967295 bytes").setup(|d| bad_grasp_file("header_4gib.npy", d, "g.npy")),
        row("kinematics input without a newline", "kinematics --robot baxter --input {d}/z.jsonl", &[], 2, "z.jsonl: line 1: longer than 1048576 bytes").setup(|d| std::fs::write(d.join("z.jsonl"), vec![b'0'; 3 << 20]).unwrap()),
        row("grasp npy huge header", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_GRASP_NPY)], 2, "g: declares 1000000000000 grasps, more than the limit 10000000").setup(|d| bad_grasp_file("huge_header.npy", d, "g.npy")),
        row("grasp unknown format", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", "robot: { builtin: baxter }\narms: left\nobject: { pose: { xyz: [0.75, 0, -0.1] } }\ncandidates: { file: g.npy, format: gpd }\ntrajectory: { steps: [ { lift: 0.2 } ] }\n"), ("g.npy", "")], 2, "field 'candidates.format': 'gpd' is not one of"),
        row("grasp camera frame without camera", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", "robot: { builtin: baxter }\narms: left\nobject: { pose: { xyz: [0.75, 0, -0.1] } }\ncandidates: { file: g.npz, frame: camera }\ntrajectory: { steps: [ { lift: 0.2 } ] }\n"), ("g.npz", "")], 2, "field 'candidates.frame': poses in the camera frame need"),
        row("grasp options without file", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", "robot: { builtin: baxter }\narms: left\nobject: { pose: { xyz: [0.75, 0, -0.1] }, shape: { box: { size: [0.06, 0.4, 0.1] } } }\ncandidates: { family: { edge: { count: 3 } }, frame: world }\ntrajectory: { steps: [ { lift: 0.2 } ] }\n")], 2, "field 'candidates.frame': applies only to a candidate file"),
        row("candidates csv unknown column", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_CSV), ("c.csv", "x,y,z,qx,qy,qz,qw,score\n0,0,0.05,0,0,0,1,1\n")], 2, "unknown column 'score'"),
        row("candidates csv is a link to a secret", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_CSV), ("secret", "root:x:0:0:hunter2:/root:/bin/bash\n")], 2, "an unknown column that is not a column name (34 characters)").setup(|d| symlink(&d.join("secret"), &d.join("c.csv"), false)),
        row("candidates csv non-unit quaternion", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_CSV), ("c.csv", "x,y,z,qx,qy,qz,qw\n0,0,0.05,0,0,0,1\n0,0,0.05,0,0,0.5,0.5\n")], 2, "line 3: quaternion"),
        // Output folders and files.
        row("ik tolerance accepting any pose", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_HUGE_IK_TOLERANCE)], 2, "field 'ik.tolerance': 1e308 accepts almost any pose"),
        row("out is a symlink", "select --task {d}/t.yaml --out {d}/link", &[("t.yaml", TASK)], 2, "is a symbolic link").setup(|d| symlink(&d.join("real"), &d.join("link"), true)),
        row("out is a dangling symlink", "select --task {d}/t.yaml --out {d}/link", &[("t.yaml", TASK)], 2, "is a symbolic link").setup(|d| symlink(&d.join("nowhere"), &d.join("link"), false)),
        row("out is a symlink with a trailing slash", "select --task {d}/t.yaml --out {d}/link/ --force", &[("t.yaml", TASK), ("real/keep", "x")], 2, "is a symbolic link").setup(|d| symlink(&d.join("real"), &d.join("link"), false)),
        row("out force over the task's folder", "select --task {d}/in/t.yaml --out {d}/in --force", &[("in/t.yaml", TASK)], 2, "in/t.yaml, an input of this run"),
        row("out force over a folder the task reads", "select --task {d}/t.yaml --out {d}/robot --force", &[("t.yaml", TASK_URDF_IN_FOLDER), ("robot/arm.urdf", "<robot name=\"r\"/>")], 2, "robot/arm.urdf, an input of this run"),
        row("map out force over the task's folder", "map --task {d}/in/t.yaml --x 0.7 --y 0 --out {d}/in --force", &[("in/t.yaml", TASK)], 2, "an input of this run"),
        row("task is a FIFO", "select --task {d}/fifo.yaml --out {d}/out", &[], 2, "a FIFO (named pipe), not a regular file").setup(|d| mkfifo(&d.join("fifo.yaml"))),
        row("candidate file is a FIFO", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_FILE_CSV)], 2, "a FIFO (named pipe), not a regular file").setup(|d| mkfifo(&d.join("c.csv"))),
        row("robot is a FIFO", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK_URDF_IN_FOLDER)], 2, "a FIFO (named pipe), not a regular file").setup(|d| { std::fs::create_dir(d.join("robot")).unwrap(); mkfifo(&d.join("robot/arm.urdf")) }),
        row("task is a device", "select --task /dev/zero --out {d}/out", &[], 2, "a character device, not a regular file"),
        row("kinematics input is a FIFO", "kinematics --robot panda --input {d}/q.jsonl", &[], 2, "a FIFO (named pipe), not a regular file").setup(|d| mkfifo(&d.join("q.jsonl"))),
        row("out is a device", "select --task {d}/t.yaml --out /dev/null", &[("t.yaml", TASK)], 2, "/dev/null: is a character device"),
        row("out is a FIFO", "select --task {d}/t.yaml --out {d}/fifo", &[("t.yaml", TASK)], 2, "FIFO").setup(|d| mkfifo(&d.join("fifo"))),
        row("out is a non-empty folder", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK), ("out/pairs.json", "[]")], 2, "not empty (it holds 'pairs.json'); use --force"),
        row("out holds a stale summary folder", "select --task {d}/t.yaml --out {d}/out", &[("t.yaml", TASK), ("out/summary.json/x", "")], 2, "use --force"),
        row("out is a file", "select --task {d}/t.yaml --out {d}/t.yaml", &[("t.yaml", TASK)], 2, "is an existing file, but the output is a folder"),
        row("out below a file", "select --task {d}/t.yaml --out {d}/t.yaml/out", &[("t.yaml", TASK)], 2, "a parent of this path is a file"),
        row("out force over the working folder", "select --task {d}/t.yaml --out . --force", &[("t.yaml", TASK)], 2, "refusing to replace the working folder"),
        row("out cannot be created", "select --task {d}/t.yaml --out /proc/graspath-out --quiet", &[("t.yaml", TASK)], 1, "cannot create a temporary folder"),
        row("demo out non-empty", "demo --out {d}/demo", &[("demo/findings.json", "[]")], 2, "use --force"),
        row("demo out symlink", "demo --out {d}/link", &[], 2, "is a symbolic link").setup(|d| symlink(&d.join("real"), &d.join("link"), true)),
        row("train out exists", "train {d}/demo.json --out {d}/model.json", &[("demo.json", "{}"), ("model.json", "old")], 2, "the file exists; use --force"),
        row("train out symlink", "train {d}/demo.json --out {d}/link --force", &[("demo.json", "{}"), ("model.json", "old")], 2, "is a symbolic link").setup(|d| symlink(&d.join("model.json"), &d.join("link"), false)),
        row("train out over its demonstration", "train {d}/demo.json --out {d}/demo.json --force", &[("demo.json", "{}")], 2, "demo.json, an input of this run"),
        row("generate out over its cloud", "generate --model {d}/m.json --cloud {d}/c.ply --out {d}/c.ply --force", &[("m.json", "{}"), ("c.ply", "ply")], 2, "c.ply, an input of this run"),
        row("train out folder", "train {d}/demo.json --out {d}/dir --force", &[("demo.json", "{}"), ("dir/x", "")], 2, "is an existing folder"),
        row("train missing demonstration", "train {d}/missing.json --out {d}/model.json", &[], 2, "missing.json"),
        row("train invalid demonstration", "train {d}/demo.json --out {d}/model.json", &[("demo.json", "{\"hand\": 3}")], 2, "demo.json"),
        row("generate out exists", "generate --model {d}/m.json --cloud {d}/c.ply --out {d}/c.json", &[("c.json", "old")], 2, "the file exists; use --force"),
        row("generate out device", "generate --model {d}/m.json --cloud {d}/c.ply --out /dev/null --force", &[], 2, "character device"),
        row("generate missing model", "generate --model {d}/m.json --cloud {d}/c.ply --out {d}/c.json", &[], 2, "m.json"),
        row("generate invalid model", "generate --model {d}/m.json --cloud {d}/c.ply --out {d}/c.json", &[("m.json", "[1, 2]")], 2, "m.json"),
        // Nothing selected: the results are written, the exit code says so.
        row("nothing feasible", "select --task {d}/v-far.yaml --out {d}/out --quiet", &[], 3, "nothing selected (no feasible candidate)").leaves(&["out"]),
        row("no valid pair", "select --task {d}/v-far-both.yaml --out {d}/out --quiet", &[], 3, "nothing selected (no valid pair of grasps)").leaves(&["out"]),
        row("nothing feasible, allowed", "select --task {d}/v-far.yaml --out {d}/out --quiet --allow-empty", &[], 0, "").leaves(&["out"]),
        // Kinematics.
        row("kinematics bad line", "kinematics --robot baxter --input {d}/q.jsonl", &[("q.jsonl", "{\"q\":[0,0,0,0,0,0,0]}\n{\"q\":[0,\"x\"]}\n")], 2, "q.jsonl: line 2: not a valid input object"),
        row("kinematics wrong dof", "kinematics --robot baxter", &[], 2, "line 1: q has 3 values").stdin("{\"q\":[0,0,0]}\n"),
        row("kinematics unknown field", "kinematics --robot baxter", &[], 2, "unknown field `extra`").stdin("{\"q\":[0,0,0,0,0,0,0],\"extra\":1}\n"),
        row("kinematics number out of range", "kinematics --robot baxter", &[], 2, "line 1").stdin("{\"q\":[1e400,0,0,0,0,0,0]}\n"),
        row("kinematics missing input", "kinematics --robot baxter --input {d}/missing.jsonl", &[], 2, "missing.jsonl: cannot open"),
        row("kinematics unknown robot", "kinematics --robot kuka", &[], 2, "invalid value 'kuka' for '--robot <NAME>'"),
        row("kinematics unknown arm", "kinematics --robot baxter --arm middle", &[], 2, "--arm"),
        row("kinematics no robot", "kinematics", &[], 2, "choose a robot"),
        row("kinematics tool two numbers", "kinematics --robot baxter --tool-xyz 1,2", &[], 2, "three comma-separated numbers"),
        row("kinematics urdf missing link", "kinematics --urdf {d}/two.urdf --base base --tip nope", &[("two.urdf", TWO_LINK_URDF)], 2, "no link named 'nope'"),
        row("kinematics urdf missing file", "kinematics --urdf {d}/none.urdf --base base --tip tip", &[], 2, "none.urdf"),
        // Inverse kinematics.
        row("ik target 1e300 m away", "ik --robot baxter", &[], 2, "are the units metres?").stdin("{\"pose\":[[1,0,0,1e300],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}\n"),
        row("ik target 2 km away", "ik --robot baxter", &[], 2, "line 2: field 'pose'").stdin(concat!(r#"{"pose":[[1,0,0,0.5],[0,1,0,0.2],[0,0,1,0.1],[0,0,0,1]]}"#, "\n", r#"{"pose":[[1,0,0,0],[0,1,0,-2000],[0,0,1,0],[0,0,0,1]]}"#, "\n")),
        row("ik pose not orthonormal", "ik --robot baxter", &[], 2, "rotation block is not orthonormal").stdin("{\"pose\":[[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}\n"),
        row("ik pose bad last row", "ik --robot baxter", &[], 2, "field 'pose'").stdin("{\"pose\":[[1,0,0,0],[0,1,0,0],[0,0,1,0],[1,0,0,1]]}\n"),
        row("ik start not a number", "ik --robot baxter --start 0,0,x,0,0,0,0", &[], 2, "'x' is not a number").stdin(IDENTITY),
        row("ik start wrong count", "ik --robot baxter --start 0,0", &[], 2, "got 2 values").stdin(IDENTITY),
        row("ik negative tolerance", "ik --robot baxter --tolerance=-1", &[], 2, "--tolerance: must be a positive number").stdin(IDENTITY),
        row("ik zero timeout", "ik --robot baxter --timeout-ms 0", &[], 2, "--timeout-ms").stdin(IDENTITY),
        row("ik zero branches", "ik --robot baxter --trajectory --branches 0", &[], 2, "--branches").stdin("{\"poses\":[]}"),
        row("ik trajectory without poses", "ik --robot baxter --trajectory", &[], 2, "the trajectory has no poses").stdin("{\"poses\":[]}"),
        row("ik trajectory not a document", "ik --robot baxter --trajectory", &[], 2, "not a valid trajectory document").stdin("[1,2"),
        row("ik trajectory far pose", "ik --robot baxter --trajectory", &[], 2, "field 'poses[1]'").stdin(r#"{"poses":[[[1,0,0,0.5],[0,1,0,0.2],[0,0,1,0.1],[0,0,0,1]],[[1,0,0,1e30],[0,1,0,0],[0,0,1,0],[0,0,0,1]]]}"#),
    ]
}

fn symlink(target: &Path, link: &Path, make_target_folder: bool) {
    if make_target_folder {
        std::fs::create_dir_all(target).unwrap();
        std::fs::write(target.join("keep"), "k").unwrap();
    }
    std::os::unix::fs::symlink(target, link).unwrap();
}

/// Makes `name` in `dir` a sparse file of `len` bytes (no disk blocks).
fn sparse(dir: &Path, name: &str, len: u64) {
    std::fs::File::create(dir.join(name))
        .unwrap()
        .set_len(len)
        .unwrap();
}

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo runs");
    assert!(status.success());
}

/// Everything under `dir`: relative path → what it is (file bytes, link target, folder).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, String> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let relative = path.strip_prefix(root).unwrap().to_path_buf();
            let file_type = std::fs::symlink_metadata(&path).unwrap().file_type();
            let what = if file_type.is_symlink() {
                format!("link to {}", std::fs::read_link(&path).unwrap().display())
            } else if file_type.is_dir() {
                walk(root, &path, out);
                "folder".to_string()
            } else if file_type.is_file() {
                let metadata = std::fs::metadata(&path).unwrap();
                if metadata.len() > 1 << 20 {
                    // A huge (sparse) input: its length and modification time, not its bytes.
                    format!(
                        "file of {} bytes, {:?}",
                        metadata.len(),
                        metadata.modified().unwrap()
                    )
                } else {
                    format!("file {:?}", std::fs::read(&path).unwrap())
                }
            } else {
                "special".to_string()
            };
            out.insert(relative, what);
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

fn run(
    row: &Row,
    variants: &BTreeMap<&'static str, (&'static str, &'static str)>,
) -> Result<(), String> {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (name, text) in row.files {
        let path = d.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    for (name, (from, to)) in variants {
        if row.args.contains(name) {
            assert!(TASK.contains(from), "{name}: '{from}' is not in the task");
            std::fs::write(d.join(name), TASK.replacen(from, to, 1)).unwrap();
        }
    }
    if let Some(setup) = row.setup {
        setup(d);
    }
    let before = snapshot(d);
    let args: Vec<String> = row
        .args
        .split_whitespace()
        .map(|a| a.replace("{d}", &d.display().to_string()))
        .collect();
    let mut child = Command::new(env!("CARGO_BIN_EXE_graspath"))
        .args(&args)
        .current_dir(d)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    // A command that fails before reading stdin closes it: ignore the broken pipe.
    let _ = stdin.write_all(row.stdin.as_bytes());
    drop(stdin);
    let output = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    let mut problems = Vec::new();
    if output.status.code() != Some(row.code) {
        problems.push(format!(
            "exit code {:?}, expected {}",
            output.status.code(),
            row.code
        ));
    }
    if !stderr.contains(row.message) {
        problems.push(format!("message lacks '{}'", row.message));
    }
    if stderr.contains("panicked") {
        problems.push("panicked".into());
    }
    if row.code == 1 || row.code == 2 {
        if !output.stdout.is_empty() {
            problems.push("printed to stdout".into());
        }
        if stderr
            .lines()
            .filter(|l| l.starts_with("graspath: "))
            .count()
            > 1
        {
            problems.push("more than one error line".into());
        }
    }
    let after = snapshot(d);
    for (path, what) in &after {
        let name = path.display().to_string();
        if name.contains(".graspath-") || name.ends_with(".tmp") {
            problems.push(format!("temporary entry left behind: {name}"));
        }
        let left = row.leaves.iter().any(|l| path.starts_with(l));
        if !left && before.get(path) != Some(what) {
            problems.push(format!("{name} was created or changed"));
        }
    }
    for path in before.keys() {
        if !after.contains_key(path) {
            problems.push(format!("{} was removed", path.display()));
        }
    }
    for l in row.leaves {
        if !after.contains_key(Path::new(l)) {
            problems.push(format!("{l} was not written"));
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{}: {}\n    stderr: {}",
            row.name,
            problems.join("; "),
            stderr.trim()
        ))
    }
}

#[test]
fn every_bad_input_gives_its_exit_code_and_message_and_leaves_nothing_behind() {
    let rows = table();
    assert!(rows.len() >= 45, "{} rows", rows.len());
    let mut names = std::collections::BTreeSet::new();
    for row in &rows {
        assert!(names.insert(row.name), "row '{}' twice", row.name);
    }
    let variants = variants();
    let failures: Vec<String> = rows
        .iter()
        .filter_map(|row| run(row, &variants).err())
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} rows failed:\n{}",
        failures.len(),
        rows.len(),
        failures.join("\n")
    );
}

/// The exit code and stderr of `graspath select --task {dir}/{task}`.
fn select_task(dir: &Path, task: &str) -> (Option<i32>, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_graspath"))
        .args(["select", "--task"])
        .arg(dir.join(task))
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn a_missing_candidate_file_exits_as_a_missing_task_file_does() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("t.yaml"), TASK_FILE_JSON).unwrap();
    let (task_code, task_message) = select_task(d, "missing.yaml");
    let (candidates_code, candidates_message) = select_task(d, "t.yaml");
    assert!(
        task_message.contains("missing.yaml: cannot read"),
        "{task_message}"
    );
    assert!(
        candidates_message.contains("c.json: file: cannot read"),
        "{candidates_message}"
    );
    assert_eq!(candidates_code, task_code);
}

#[test]
fn the_help_documents_the_exit_codes() {
    for args in [&["--help"][..], &["select", "--help"][..]] {
        let output = Command::new(env!("CARGO_BIN_EXE_graspath"))
            .args(args)
            .output()
            .unwrap();
        assert_eq!(output.status.code(), Some(0));
        let text = String::from_utf8_lossy(&output.stdout);
        for code in [
            "0  success",
            "1  internal error",
            "2  bad input",
            "3  select",
        ] {
            assert!(text.contains(code), "{args:?}: '{code}' missing");
        }
    }
}

/// A result that cannot be written to standard output (here a full device) exits 1 — writing
/// the output failed — with a message that says it was standard output, and the system's
/// reason.
#[cfg(target_os = "linux")]
#[test]
fn a_full_standard_output_is_named_and_exits_1() {
    let full = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let calls: [(&[&str], &str); 2] = [
        (
            &["kinematics", "--robot", "baxter"],
            "{\"q\":[0,0,0,0,0,0,0]}\n",
        ),
        (&["ik", "--robot", "baxter"], IDENTITY),
    ];
    for (args, input) in calls {
        let mut child = Command::new(env!("CARGO_BIN_EXE_graspath"))
            .args(args)
            .stdin(Stdio::piped())
            .stdout(full.try_clone().unwrap())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        child
            .stdin
            .take()
            .unwrap()
            .write_all(input.as_bytes())
            .unwrap();
        let output = child.wait_with_output().unwrap();
        let message = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {message}");
        assert!(
            message.contains("cannot write the result to standard output")
                && message.contains("No space left on device"),
            "{args:?}: {message}"
        );
    }
}
