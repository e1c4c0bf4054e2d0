//! The fuzz targets: one per input path of the library and the CLI. Each has a seed corpus
//! (the files under `examples/` plus small files written with the library's own writers), an
//! optional structure-aware generator, and a function that feeds one input to the code under
//! test. Results (`Ok` or a typed error) are accepted; the oracles watch for panics, hangs and
//! allocations (see [`crate::exec`]). A few invariants of successful reads are checked too
//! (clouds hold only finite points and unit normals).
//!
//! Parsers that only take a path get the bytes written to a file in the per-process work
//! directory ([`Ctx::dir`]), which also holds the small files a document may name
//! (`robot.urdf`, `candidates.json`, `mesh.obj`, `cloud.pcd`, `three_finger_hand.urdf`, ...).
//!
//! The table of targets is here; their feed functions are in `feeds.rs` and their seed corpora
//! in `seeds.rs`. The grasp-file and MJCF/SRDF targets' seeds, generators and feeds are in
//! [`crate::readers`].

use crate::readers;
use crate::rng::Rng;
use crate::structured::{draw, pcd_file, task_yaml, urdf_document};
use graspath::cloud::{
    load_cloud_argument, pcd_bytes, ply_bytes, read_mesh, read_pcd_bytes, read_ply_bytes,
    sample_shape, PcdEncoding, PlyEncoding, PointCloud, SampleOptions,
};
use graspath::geometry::pose_from_rows;
use graspath::geometry::shape::Shape;
use graspath::grasp::model::{
    candidates_json, generate, train, Demonstration, GenerateOptions, GraspModel,
};
use graspath::grasp::read_candidates;
use graspath::manipulability::{inverse_condition, yoshikawa, JacobianPart};
use graspath::robot::builtin::{baxter, Arm};
use graspath::robot::{
    solve_ik, solve_trajectory, Chain, IkOptions, TrajectoryIkOptions, UrdfRobot,
};
use nalgebra::{Point3, Vector3};
use serde::Deserialize;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

mod feeds;
mod seeds;

use feeds::*;
use seeds::*;
pub use seeds::{ascii_stl, binary_stl, small_cloud};

/// The repository's `examples/` folder (seed corpus).
pub fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// The shared robot models, when present (extra URDF seeds).
pub fn shared_robots_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../../shared/robots")
}

const HAND_URDF: &str = include_str!("../../../graspath/tests/data/three_finger_hand.urdf");
const THREE_FINGER_DEMO: &str = include_str!("../../../graspath/tests/data/three_finger_demo.json");

/// Where per-process files go: `/dev/shm` when it exists (a file write there costs
/// microseconds, against milliseconds on some disks), else the system's temporary directory.
pub fn scratch_root() -> PathBuf {
    let shm = Path::new("/dev/shm");
    if shm.is_dir() {
        shm.to_path_buf()
    } else {
        std::env::temp_dir()
    }
}

pub use crate::fixtures::SMALL_ROBOT_URDF;

const CUBE_OBJ: &str = "# unit cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

const QUAD_OBJ: &str = "v 0 0 0\nv 0.1 0 0\nv 0.1 0.1 0\nv 0 0.1 0\nvn 0 0 1\nvt 0 0\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf -4 -3 -2\n";

/// The shared state of one worker process: its work directory and the chains and model the
/// targets use.
pub struct Ctx {
    /// The per-process work directory (input files and the support files they name).
    pub dir: PathBuf,
    model: OnceLock<Result<GraspModel, String>>,
    baxter: OnceLock<Chain>,
}

impl Ctx {
    /// Creates the work directory `<scratch>/graspath-fuzz-<pid>` with its support files (a
    /// further context in the same process, as tests running side by side make, gets
    /// `graspath-fuzz-<pid>-<k>`: each removes its own directory when dropped).
    pub fn new() -> std::io::Result<Self> {
        static CONTEXTS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let pid = std::process::id();
        let dir = match CONTEXTS.fetch_add(1, std::sync::atomic::Ordering::Relaxed) {
            0 => Self::dir_of(pid),
            k => scratch_root().join(format!("graspath-fuzz-{pid}-{k}")),
        };
        std::fs::create_dir_all(&dir)?;
        let cloud = box_cloud(2000, true);
        std::fs::write(dir.join("robot.urdf"), SMALL_ROBOT_URDF)?;
        std::fs::write(dir.join("three_finger_hand.urdf"), HAND_URDF)?;
        std::fs::write(dir.join("mesh.obj"), CUBE_OBJ)?;
        std::fs::write(dir.join("mesh.stl"), binary_stl(CUBE_OBJ))?;
        std::fs::write(
            dir.join("cloud.ply"),
            ply_bytes(&cloud, PlyEncoding::Ascii).unwrap_or_default(),
        )?;
        std::fs::write(
            dir.join("cloud.pcd"),
            pcd_bytes(&cloud, PcdEncoding::Binary).unwrap_or_default(),
        )?;
        std::fs::write(
            dir.join("candidates.json"),
            candidate_json_seeds()[0].as_bytes(),
        )?;
        std::fs::write(dir.join("candidates.csv"), CANDIDATES_CSV)?;
        Ok(Self {
            dir,
            model: OnceLock::new(),
            baxter: OnceLock::new(),
        })
    }

    /// The work directory of process `pid`.
    pub fn dir_of(pid: u32) -> PathBuf {
        scratch_root().join(format!("graspath-fuzz-{pid}"))
    }

    /// Writes `bytes` to `name` in the work directory and returns its path.
    pub fn file(&self, name: &str, bytes: &[u8]) -> PathBuf {
        crate::fixtures::write_input(&self.dir, name, bytes)
    }

    /// Builds what `target` needs (the trained model, the Baxter chain) before executions are
    /// timed.
    pub fn warm_up(&self, target: &Target) {
        let _ = self.baxter();
        if target.name == "model" || target.name == "generate" {
            let _ = self.model();
        }
    }

    fn baxter(&self) -> &Chain {
        self.baxter.get_or_init(|| baxter(Arm::Left))
    }

    /// A small grasp model trained from the box demonstration on a 2000-point cloud (`None`
    /// when training fails; [`Ctx::model_error`] says why).
    pub fn model(&self) -> Option<&GraspModel> {
        self.trained_model().as_ref().ok()
    }

    /// Why the fixed model could not be trained, if it could not.
    pub fn model_error(&self) -> Option<&str> {
        self.trained_model().as_ref().err().map(String::as_str)
    }

    fn trained_model(&self) -> &Result<GraspModel, String> {
        self.model.get_or_init(|| {
            let path = examples_dir().join("grasp/demo_box.json");
            let text =
                std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
            let demo: Demonstration = serde_json::from_str(&text).map_err(|e| e.to_string())?;
            let hand = demo
                .hand
                .load(&self.dir, "demo_box.json")
                .map_err(|e| e.to_string())?;
            let shape = Shape::cuboid([0.05, 0.04, 0.14]).map_err(|e| e.to_string())?;
            let options = SampleOptions {
                points: 2000,
                seed: 1,
                ..SampleOptions::default()
            };
            let cloud = sample_shape(&shape, &options).map_err(|e| e.to_string())?;
            train(&demo, hand, &cloud, "demo_box.json").map_err(|e| e.to_string())
        })
    }
}

impl Drop for Ctx {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// A fuzz target.
pub struct Target {
    /// Its name on the command line.
    pub name: &'static str,
    /// What it feeds.
    pub description: &'static str,
    /// The extension of reproducer files.
    pub extension: &'static str,
    /// The seed corpus.
    pub seeds: fn(&Ctx) -> Vec<Vec<u8>>,
    /// A structure-aware generator, when the target has one.
    pub structured: Option<fn(&mut Rng) -> Vec<u8>>,
    /// Feeds one input to the code under test.
    pub run: fn(&Ctx, &[u8]),
    /// Executions of the deterministic CI slice.
    pub ci_execs: u64,
}

/// Every target, in a fixed order.
pub fn all() -> &'static [Target] {
    TARGETS
}

/// The target named `name`.
pub fn by_name(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}

/// Input `index` of `target` in a campaign seeded with `seed`: a structure-aware document
/// (half of the inputs, when the target has a generator, a third of those mutated further) or
/// a mutated seed.
pub fn generate_input(target: &Target, corpus: &[Vec<u8>], seed: u64, index: u64) -> Vec<u8> {
    let mut rng = Rng::for_input(seed, target.name, index);
    if let Some(structured) = target.structured {
        if rng.chance(1, 2) {
            let mut data = structured(&mut rng);
            if rng.chance(1, 3) {
                crate::mutate::mutate_once(&mut rng, &mut data, corpus);
            }
            return data;
        }
    }
    crate::mutate::mutate(&mut rng, corpus)
}

static TARGETS: &[Target] = &[
    Target {
        name: "urdf",
        description: "UrdfRobot::from_xml, every root-to-link chain (FK, Jacobian, IK at the mid configuration), hand_from_urdf",
        extension: "urdf",
        seeds: urdf_seeds,
        structured: Some(|rng| draw(&urdf_document(), rng).into_bytes()),
        run: run_urdf,
        ci_execs: 3000,
    },
    Target {
        name: "ply",
        description: "read_ply_bytes (ascii, binary little and big endian)",
        extension: "ply",
        seeds: ply_seeds,
        structured: None,
        run: |_, bytes| check_cloud(read_ply_bytes(bytes, "fuzz.ply")),
        ci_execs: 3000,
    },
    Target {
        name: "pcd",
        description: "read_pcd_bytes (ascii, binary, binary_compressed)",
        extension: "pcd",
        seeds: pcd_seeds,
        structured: Some(|rng| draw(&pcd_file(), rng)),
        run: |_, bytes| check_cloud(read_pcd_bytes(bytes, "fuzz.pcd")),
        ci_execs: 3000,
    },
    Target {
        name: "obj",
        description: "read_mesh on a .obj file, then area-weighted sampling of 64 points",
        extension: "obj",
        seeds: |_| vec![CUBE_OBJ.into(), QUAD_OBJ.into()],
        structured: None,
        run: |ctx, bytes| {
            if let Ok(mesh) = read_mesh(&ctx.file("fuzz.obj", bytes)) {
                sample_mesh(&mesh);
            }
        },
        ci_execs: 3000,
    },
    Target {
        name: "stl",
        description: "read_mesh on a .stl file (ascii and binary), then area-weighted sampling of 64 points",
        extension: "stl",
        seeds: |_| vec![ascii_stl(CUBE_OBJ).into_bytes(), binary_stl(CUBE_OBJ), binary_stl(QUAD_OBJ)],
        structured: None,
        run: |ctx, bytes| {
            if let Ok(mesh) = read_mesh(&ctx.file("fuzz.stl", bytes)) {
                sample_mesh(&mesh);
            }
        },
        ci_execs: 3000,
    },
    Target {
        name: "cloud_json",
        description: "load_cloud_argument on a .json cloud source (primitive, mesh or file)",
        extension: "json",
        seeds: cloud_json_seeds,
        structured: None,
        run: |ctx, bytes| check_cloud(load_cloud_argument(&ctx.file("cloud_source.json", bytes))),
        ci_execs: 800,
    },
    Target {
        name: "task_yaml",
        description: "task loading from YAML (robot, candidates, sampled path, settings)",
        extension: "yaml",
        seeds: task_yaml_seeds,
        structured: Some(|rng| draw(&task_yaml(), rng).into_bytes()),
        run: |ctx, bytes| load_task(&ctx.file("task.yaml", bytes)),
        ci_execs: 2000,
    },
    Target {
        name: "task_json",
        description: "task loading from JSON",
        extension: "json",
        seeds: task_json_seeds,
        structured: None,
        run: |ctx, bytes| load_task(&ctx.file("task.json", bytes)),
        ci_execs: 2000,
    },
    Target {
        name: "candidates_json",
        description: "read_candidates on a .json file (wrapped and bare, matrix and quaternion forms)",
        extension: "json",
        seeds: |_| candidate_json_seeds().into_iter().map(String::into_bytes).collect(),
        structured: None,
        run: |ctx, bytes| {
            let _ = read_candidates(&ctx.file("fuzz_candidates.json", bytes));
        },
        ci_execs: 3000,
    },
    Target {
        name: "candidates_csv",
        description: "read_candidates on a .csv file",
        extension: "csv",
        seeds: |_| vec![CANDIDATES_CSV.into(), CANDIDATES_CSV_LIKELIHOOD.into()],
        structured: None,
        run: |ctx, bytes| {
            let _ = read_candidates(&ctx.file("fuzz_candidates.csv", bytes));
        },
        ci_execs: 3000,
    },
    Target {
        name: "model",
        description: "GraspModel::from_json, then a small generate() on a 300-point box cloud",
        extension: "json",
        seeds: |ctx| ctx.model().and_then(|m| m.to_json().ok()).into_iter().collect(),
        structured: None,
        run: run_model,
        ci_execs: 200,
    },
    Target {
        name: "generate",
        description: "a PLY or PCD cloud read, then a small generate() with a fixed trained model",
        extension: "cloud",
        seeds: generate_seeds,
        structured: Some(|rng| draw(&pcd_file(), rng)),
        run: run_generate,
        ci_execs: 200,
    },
    Target {
        name: "demo",
        description: "a demonstration file: Demonstration::read, hand and cloud loading, training",
        extension: "json",
        seeds: demo_seeds,
        structured: None,
        run: run_demo,
        ci_execs: 100,
    },
    Target {
        name: "kinematics",
        description: "`graspath kinematics` JSON Lines {\"q\":[...]} on Baxter's left arm",
        extension: "jsonl",
        seeds: |_| vec![KINEMATICS_LINES.into()],
        structured: None,
        run: run_kinematics,
        ci_execs: 3000,
    },
    Target {
        name: "ik",
        description: "`graspath ik` JSON Lines {\"pose\":[[4x4]]} on Baxter's left arm (5 ms per pose)",
        extension: "jsonl",
        seeds: |_| vec![IK_LINES.into()],
        structured: None,
        run: run_ik,
        ci_execs: 1000,
    },
    Target {
        name: "ik_trajectory",
        description: "`graspath ik --trajectory` document {\"poses\":[...]} on Baxter's left arm",
        extension: "json",
        seeds: |_| vec![IK_TRAJECTORY.into()],
        structured: None,
        run: run_ik_trajectory,
        ci_execs: 300,
    },
    Target {
        name: "npy",
        description: "read_grasp_file on a .npy (guessed, poses, graspnet): header checks, every dtype and order, object arrays (pickles)",
        extension: "npy",
        seeds: |_| readers::npy_seeds(),
        structured: Some(readers::npy_structured),
        run: |ctx, bytes| readers::run_npy(&ctx.dir, bytes),
        ci_execs: 3000,
    },
    Target {
        name: "npz",
        description: "read_grasp_file on an .npz (guessed, contact_graspnet, m2t2): archives of generated or fixture members under the layouts' names",
        extension: "npz",
        seeds: |_| readers::npz_seeds(),
        structured: Some(readers::npz_structured),
        run: |ctx, bytes| readers::run_npz(&ctx.dir, bytes),
        ci_execs: 2000,
    },
    Target {
        name: "pickle",
        description: "the restricted pickle reader: each input the object member of a Contact-GraspNet and an M2T2 .npz",
        extension: "pkl",
        seeds: |_| readers::pickle_seeds(),
        structured: Some(readers::pickle_structured),
        run: |ctx, bytes| readers::run_pickle(&ctx.dir, bytes),
        ci_execs: 3000,
    },
    Target {
        name: "hdf5",
        description: "read_grasp_file on an ACRONYM .h5 (hdf5-reader, dataset shapes checked before reading)",
        extension: "h5",
        seeds: |_| readers::hdf5_seeds(),
        structured: None,
        run: |ctx, bytes| readers::run_hdf5(&ctx.dir, bytes),
        ci_execs: 1000,
    },
    Target {
        name: "grasp_text",
        description: "read_grasp_file on GraspGen YAML/JSON and ACRONYM JSON (as .json and .yaml, guessed and forced)",
        extension: "json",
        seeds: |_| readers::grasp_text_seeds(),
        structured: None,
        run: |ctx, bytes| readers::run_grasp_text(&ctx.dir, bytes),
        ci_execs: 2000,
    },
    Target {
        name: "mjcf",
        description: "MjcfRobot::from_xml_in, collisions, chains from the first body (FK + Jacobian)",
        extension: "xml",
        seeds: |_| readers::mjcf_seeds(),
        structured: None,
        run: |ctx, bytes| readers::run_mjcf(&ctx.dir, bytes),
        ci_execs: 1000,
    },
    Target {
        name: "srdf",
        description: "Srdf::parse, then check_links",
        extension: "srdf",
        seeds: |_| readers::srdf_seeds(),
        structured: None,
        run: |ctx, bytes| readers::run_srdf(&ctx.dir, bytes),
        ci_execs: 3000,
    },
    Target {
        name: "xacro",
        description: "RobotSource::load of a robot file not named *.xacro (never handed to xacro), and one input in 64 expanded as *.xacro by a stand-in program (its folder and environment checked)",
        extension: "urdf",
        seeds: |_| crate::xacro::xacro_seeds(),
        structured: Some(crate::xacro::xacro_document),
        run: |ctx, bytes| crate::xacro::run_xacro(&ctx.dir, bytes),
        ci_execs: 3000,
    },
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_target_has_seeds_and_the_model_trains() {
        let ctx = Ctx::new().expect("work directory");
        assert_eq!(ctx.model_error(), None, "the fixed model must train");
        for target in all() {
            let seeds = (target.seeds)(&ctx);
            assert!(!seeds.is_empty(), "{} has no seeds", target.name);
        }
    }
}

#[cfg(test)]
mod seed_tests {
    use super::*;

    /// Mutating valid inputs reaches past the parsers: the seeds themselves must be accepted.
    #[test]
    fn demo_and_task_seeds_are_valid_inputs() {
        let ctx = Ctx::new().expect("work directory");
        for (k, seed) in demo_seeds(&ctx).iter().enumerate() {
            let path = ctx.file(&format!("seed{k}.json"), seed);
            if let Err(e) = graspath::grasp::model::train_file(&path) {
                panic!("demo seed {k}: {e}");
            }
        }
        for (k, seed) in task_json_seeds(&ctx).iter().enumerate().take(7) {
            let path = ctx.file(&format!("seed{k}.json"), seed);
            if let Err(e) = graspath::task::Task::load(&path) {
                panic!("task seed {k}: {e}");
            }
        }
    }
}
