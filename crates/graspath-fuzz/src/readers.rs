//! The targets of the grasp-file readers (`.npy`, `.npz`, the restricted pickle reader, HDF5,
//! the JSON/YAML generator layouts) and of the robot files that are not URDF (MJCF, SRDF):
//! their seed corpora, structure-aware generators and feed functions. The table of targets
//! is in [`crate::targets`].
//!
//! An `.npz` is a zip archive whose members carry CRC-32 checksums: a mutated archive is
//! mostly refused by the zip reader before any member is parsed. So the generators here build
//! archives ([`stored_zip`]) around generated or mutated members, and the `pickle` target
//! wraps each input in a valid archive, so that the bytes reach the readers behind the zip.

use crate::rng::Rng;
use graspath::grasp::{read_grasp_file, GraspFileOptions, GraspFormat};
use graspath::robot::{MjcfRobot, Srdf};
use std::path::Path;

/// The candidate limit the grasp-file targets read with (the default task limit is 10⁷: a
/// smaller one makes the count checks bind on small generated shapes too).
const MAX_CANDIDATES: usize = 100_000;

macro_rules! fixture {
    ($name:literal) => {
        include_bytes!(concat!("../../graspath/tests/data/grasp_files/", $name)).as_slice()
    };
}

macro_rules! mjcf_fixture {
    ($name:literal) => {
        include_bytes!(concat!("../../graspath/tests/data/mjcf/", $name)).as_slice()
    };
}

/// Reads `bytes` written as `name` with each of `formats` (`None`: guessed).
fn read_as(dir: &Path, name: &str, bytes: &[u8], formats: &[Option<GraspFormat>]) {
    let path = dir.join(name);
    // A failed write shows up as a read error, which is not a finding.
    let _ = std::fs::write(&path, bytes);
    for format in formats {
        let options = GraspFileOptions {
            format: *format,
            max_candidates: Some(MAX_CANDIDATES),
            ..GraspFileOptions::default()
        };
        let _ = read_grasp_file(&path, &options);
    }
}

// ---------------------------------------------------------------------------------------------
// .npy

/// An `.npy` image: version-1 preamble, `header` padded to 64 bytes, `data`.
pub fn npy_image(header: &str, data: &[u8]) -> Vec<u8> {
    let mut h = header.to_string();
    while !(10 + h.len() + 1).is_multiple_of(64) {
        h.push(' ');
    }
    h.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(h.len() as u16).to_le_bytes());
    bytes.extend_from_slice(h.as_bytes());
    bytes.extend_from_slice(data);
    bytes
}

fn identity_poses(n: usize) -> Vec<f64> {
    (0..n)
        .flat_map(|_| {
            let mut m = [0.0; 16];
            for k in 0..4 {
                m[5 * k] = 1.0;
            }
            m
        })
        .collect()
}

/// Seeds: the fixtures as generators write them, the refused ones, and small arrays of every
/// dtype and order the reader meets.
pub fn npy_seeds() -> Vec<Vec<u8>> {
    let poses: Vec<u8> = identity_poses(2)
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let poses_f4: Vec<u8> = identity_poses(2)
        .iter()
        .flat_map(|&v| (v as f32).to_le_bytes())
        .collect();
    vec![
        fixture!("poses.npy").to_vec(),
        fixture!("graspnet.npy").to_vec(),
        fixture!("bad/longdouble.npy").to_vec(),
        fixture!("bad/header_4gib.npy").to_vec(),
        fixture!("bad/huge_header.npy").to_vec(),
        npy_image(
            "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 4, 4), }",
            &poses,
        ),
        npy_image(
            "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 4, 4), }",
            &poses_f4,
        ),
        npy_image(
            "{'descr': '>i8', 'fortran_order': False, 'shape': (4, 4), }",
            &[0; 128],
        ),
        npy_image(
            "{'descr': '<c16', 'fortran_order': False, 'shape': (2, 17), }",
            &[0; 544],
        ),
        npy_image(
            "{'descr': '|O', 'fortran_order': False, 'shape': (), }",
            &pickle_seeds_raw()[0],
        ),
    ]
}

const DESCRS: &[&str] = &[
    "<f8",
    "<f4",
    ">f8",
    "<i8",
    "<i4",
    "|u1",
    "|b1",
    "<u8",
    "<c16",
    "<c8",
    "<f16",
    "<f2",
    "|O",
    "<U4",
    "f0",
    "",
    "[('a', '<f8')]",
    "('<f8', (3,))",
];

const SHAPES: &[&str] = &[
    "(N, 4, 4)",
    "(N, 17)",
    "(N,)",
    "()",
    "(N, 3)",
    "(2, N, 4, 4)",
    "(4294967296, 4294967296)",
    "(18446744073709551615,)",
    "(N, 4, 4, 1)",
    "(-1, 4)",
    "(N, 0)",
    "(0, 4, 4)",
];

/// An `.npy` header from the tables above and data of the declared length or not.
fn npy_document(rng: &mut Rng) -> Vec<u8> {
    let descr = *rng.pick(DESCRS);
    let n = *rng.pick(&[0usize, 1, 2, 3, 5]);
    let shape = rng.pick(SHAPES).replace('N', &n.to_string());
    let fortran = if rng.chance(1, 2) { "True" } else { "False" };
    let descr_text = if descr.starts_with('[') || descr.starts_with('(') {
        descr.to_string()
    } else {
        format!("'{descr}'")
    };
    let header =
        format!("{{'descr': {descr_text}, 'fortran_order': {fortran}, 'shape': {shape}, }}");
    let data: Vec<u8> = if descr == "|O" {
        pickle_document(rng)
    } else if rng.chance(2, 3) {
        identity_poses(n.max(1) * 2)
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .take(rng.below(600))
            .collect()
    } else {
        (0..rng.below(300)).map(|_| rng.next_u64() as u8).collect()
    };
    npy_image(&header, &data)
}

/// The `npy` target: the bytes as `fuzz.npy`, guessed, as poses and as GraspNet.
pub fn run_npy(dir: &Path, bytes: &[u8]) {
    read_as(
        dir,
        "fuzz.npy",
        bytes,
        &[None, Some(GraspFormat::Poses), Some(GraspFormat::GraspNet)],
    );
}

/// A generated `.npy` (the `npy` target's generator).
pub fn npy_structured(rng: &mut Rng) -> Vec<u8> {
    npy_document(rng)
}

// ---------------------------------------------------------------------------------------------
// .npz

/// The CRC-32 (IEEE) of `bytes`, as zip records it.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A zip archive of uncompressed members (what `np.savez` writes).
pub fn stored_zip(members: &[(String, Vec<u8>)]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut central = Vec::new();
    for (name, data) in members {
        let offset = out.len() as u32;
        let crc = crc32(data);
        let size = data.len() as u32;
        let fields = |out: &mut Vec<u8>| {
            out.extend_from_slice(&20u16.to_le_bytes()); // version needed
            out.extend_from_slice(&0u16.to_le_bytes()); // flags
            out.extend_from_slice(&0u16.to_le_bytes()); // stored
            out.extend_from_slice(&0u32.to_le_bytes()); // time, date
            out.extend_from_slice(&crc.to_le_bytes());
            out.extend_from_slice(&size.to_le_bytes());
            out.extend_from_slice(&size.to_le_bytes());
            out.extend_from_slice(&(name.len() as u16).to_le_bytes());
            out.extend_from_slice(&0u16.to_le_bytes()); // extra
        };
        out.extend_from_slice(b"PK\x03\x04");
        fields(&mut out);
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(data);
        central.extend_from_slice(b"PK\x01\x02");
        central.extend_from_slice(&20u16.to_le_bytes()); // version made by
        fields(&mut central);
        central.extend_from_slice(&[0; 8]); // comment, disk, internal attributes
        central.extend_from_slice(&0u32.to_le_bytes()); // external attributes
        central.extend_from_slice(&offset.to_le_bytes());
        central.extend_from_slice(name.as_bytes());
    }
    let start = out.len() as u32;
    out.extend_from_slice(&central);
    out.extend_from_slice(b"PK\x05\x06");
    out.extend_from_slice(&[0; 4]);
    out.extend_from_slice(&(members.len() as u16).to_le_bytes());
    out.extend_from_slice(&(members.len() as u16).to_le_bytes());
    out.extend_from_slice(&(central.len() as u32).to_le_bytes());
    out.extend_from_slice(&start.to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    out
}

/// The members of a stored zip (`np.savez`'s): `(name, data)`; empty for anything else.
fn stored_members(zip: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut members = Vec::new();
    let mut at = 0;
    while zip.get(at..at + 4) == Some(b"PK\x03\x04") {
        let u16_at = |k: usize| u16::from_le_bytes([zip[at + k], zip[at + k + 1]]) as usize;
        let Some(head) = zip.get(at..at + 30) else {
            break;
        };
        let size = u32::from_le_bytes([head[18], head[19], head[20], head[21]]) as usize;
        let (name_len, extra) = (u16_at(26), u16_at(28));
        let start = at + 30 + name_len + extra;
        let (Some(name), Some(data)) = (
            zip.get(at + 30..at + 30 + name_len),
            zip.get(start..start + size),
        ) else {
            break;
        };
        if u16_at(8) != 0 {
            break;
        }
        members.push((String::from_utf8_lossy(name).into_owned(), data.to_vec()));
        at = start + size;
    }
    members
}

const NPZ_FIXTURES: &[&[u8]] = &[
    fixture!("poses.npz"),
    fixture!("contact_graspnet.npz"),
    fixture!("contact_graspnet_one_grasp.npz"),
    fixture!("m2t2_equal.npz"),
    fixture!("m2t2_named.npz"),
    fixture!("m2t2_objects.npz"),
    fixture!("bad/mixed_segments.npz"),
    fixture!("bad/scores_mismatch.npz"),
    fixture!("bad/wrong_shape.npz"),
    fixture!("bad/complex.npz"),
    fixture!("bad/complex_segments.npz"),
    fixture!("bad/pickled_f0.npz"),
    fixture!("bad/memo_bomb.npz"),
    fixture!("bad/deep_pickle.npz"),
];

/// Seeds of the `npz` target: the `.npz` fixtures, good and refused.
pub fn npz_seeds() -> Vec<Vec<u8>> {
    NPZ_FIXTURES.iter().map(|b| b.to_vec()).collect()
}

const MEMBER_NAMES: &[&str] = &[
    "pred_grasps_cam",
    "scores",
    "contact_pts",
    "gripper_openings",
    "grasps",
    "grasp_confidence",
    "grasp_contacts",
    "widths",
    "poses",
    "transforms",
];

/// An archive of 1–4 members named as the layouts name them, each a fixture's member (mutated
/// or not) or a generated `.npy`.
fn npz_document(rng: &mut Rng) -> Vec<u8> {
    let fixture_members: Vec<(String, Vec<u8>)> =
        stored_members(NPZ_FIXTURES[rng.below(NPZ_FIXTURES.len())])
            .into_iter()
            .collect();
    let count = 1 + rng.below(4);
    let members: Vec<(String, Vec<u8>)> = (0..count)
        .map(|_| {
            let name = format!("{}.npy", rng.pick(MEMBER_NAMES));
            let data = match (rng.below(3), fixture_members.is_empty()) {
                (0, false) => rng.pick(&fixture_members).1.clone(),
                (1, false) => {
                    let mut data = rng.pick(&fixture_members).1.clone();
                    crate::mutate::mutate_once(rng, &mut data, &[]);
                    data
                }
                _ => npy_document(rng),
            };
            (name, data)
        })
        .collect();
    stored_zip(&members)
}

/// A generated `.npz` (the `npz` target's generator).
pub fn npz_structured(rng: &mut Rng) -> Vec<u8> {
    npz_document(rng)
}

/// The `npz` target: the bytes as `fuzz.npz`, guessed, as Contact-GraspNet and as M2T2.
pub fn run_npz(dir: &Path, bytes: &[u8]) {
    read_as(
        dir,
        "fuzz.npz",
        bytes,
        &[
            None,
            Some(GraspFormat::ContactGraspnet),
            Some(GraspFormat::M2T2),
        ],
    );
}

// ---------------------------------------------------------------------------------------------
// pickle

/// The pickles of the fixtures' object members (Contact-GraspNet's and M2T2's dictionaries and
/// lists, as NumPy writes them).
fn pickle_seeds_raw() -> Vec<Vec<u8>> {
    let mut seeds = Vec::new();
    for zip in NPZ_FIXTURES {
        for (_, member) in stored_members(zip) {
            if member.len() < 10 || !member.starts_with(b"\x93NUMPY") {
                continue;
            }
            let header_len = u16::from_le_bytes([member[8], member[9]]) as usize;
            let header = String::from_utf8_lossy(&member[10..(10 + header_len).min(member.len())]);
            if header.contains("|O") {
                seeds.push(member[(10 + header_len).min(member.len())..].to_vec());
            }
        }
    }
    if seeds.is_empty() {
        seeds.push(b"\x80\x02}q\x00.".to_vec());
    }
    seeds
}

/// Seeds of the `pickle` target: the fixtures' pickles.
pub fn pickle_seeds() -> Vec<Vec<u8>> {
    pickle_seeds_raw()
}

/// Snippets of pickle opcodes, each well formed on its own, stacked at random: containers,
/// memo puts and gets, marks, NumPy's globals, reduce and build with array states.
fn pickle_document(rng: &mut Rng) -> Vec<u8> {
    const SNIPPETS: &[&[u8]] = &[
        b"]",
        b")",
        b"}",
        b"(",
        b"l",
        b"t",
        b"d",
        b"a",
        b"e",
        b"s",
        b"u",
        b"N",
        b"\x88",
        b"K\x03",
        b"J\xff\xff\xff\xff",
        b"M\x00\x01",
        b"G?\xf0\x00\x00\x00\x00\x00\x00",
        b"\x85",
        b"\x86",
        b"\x87",
        b"q\x00",
        b"q\x01",
        b"h\x00",
        b"h\x01",
        b"\x94",
        b"r\x00\x00\x00\x00",
        b"j\x00\x00\x00\x00",
        b"X\x01\x00\x00\x00a",
        b"\x8c\x02f4",
        b"\x8c\x03<f8",
        b"\x8c\x03c16",
        b"\x8c\x00",
        b"\x8c\x02f0",
        b"C\x10\x00\x00\x00\x00\x00\x00\xf0?\x00\x00\x00\x00\x00\x00\xf0?",
        b"B\x80\x00\x00\x00",
        b"cnumpy.core.multiarray\n_reconstruct\n",
        b"cnumpy\nndarray\n",
        b"cnumpy\ndtype\n",
        b"cnumpy.core.multiarray\nscalar\n",
        b"cos\nsystem\n",
        b"R",
        b"b",
        b"\x8a\x01\x05",
        b"\x8a\x09\x00\x00\x00\x00\x00\x00\x00\x00\x01",
        b"\x89\x88\x87R(K\x03X\x01\x00\x00\x00<NNNJ\xff\xff\xff\xffJ\xff\xff\xff\xffK\x00tb",
        b"(K\x01K\x02K\x04K\x04\x87cnumpy\ndtype\nX\x02\x00\x00\x00f8\x89\x88\x87R\x89C\x00tb",
        b"(h\x00h\x00lq\x00",
    ];
    let mut out = b"\x80\x02".to_vec();
    for _ in 0..1 + rng.below(80) {
        out.extend_from_slice(SNIPPETS[rng.below(SNIPPETS.len())]);
    }
    out.push(b'.');
    out
}

/// A generated pickle (the `pickle` target's generator).
pub fn pickle_structured(rng: &mut Rng) -> Vec<u8> {
    pickle_document(rng)
}

/// Feeds a pickle as the object member of a Contact-GraspNet `.npz` and of an M2T2 one.
pub fn run_pickle(dir: &Path, bytes: &[u8]) {
    let npy = npy_image(
        "{'descr': '|O', 'fortran_order': False, 'shape': (), }",
        bytes,
    );
    let scores = npy_image(
        "{'descr': '<f8', 'fortran_order': False, 'shape': (1,), }",
        &1f64.to_le_bytes(),
    );
    for (poses, score) in [
        ("pred_grasps_cam.npy", "scores.npy"),
        ("grasps.npy", "grasp_confidence.npy"),
    ] {
        let zip = stored_zip(&[
            (poses.to_string(), npy.clone()),
            (score.to_string(), scores.clone()),
        ]);
        read_as(dir, "fuzz_pickle.npz", &zip, &[None]);
    }
}

// ---------------------------------------------------------------------------------------------
// HDF5, text layouts

/// Seeds of the `hdf5` target: the ACRONYM fixtures, good and refused.
pub fn hdf5_seeds() -> Vec<Vec<u8>> {
    vec![
        fixture!("acronym.h5").to_vec(),
        fixture!("bad/huge_header.h5").to_vec(),
        fixture!("bad/no_transforms.h5").to_vec(),
        fixture!("bad/transforms_3x3.h5").to_vec(),
    ]
}

/// The `hdf5` target: the bytes as an ACRONYM `fuzz.h5`.
pub fn run_hdf5(dir: &Path, bytes: &[u8]) {
    read_as(dir, "fuzz.h5", bytes, &[Some(GraspFormat::Acronym)]);
}

const ACRONYM_JSON: &str = r#"{"transforms": [[[1,0,0,0.01],[0,1,0,0],[0,0,1,0.02],[0,0,0,1]], [[0,-1,0,0],[1,0,0,0],[0,0,1,0],[0,0,0,1]]], "quality_flex_object_in_gripper": [1, 0]}"#;

/// Seeds of the `grasp_text` target: GraspGen YAML and JSON, ACRONYM JSON.
pub fn grasp_text_seeds() -> Vec<Vec<u8>> {
    vec![
        fixture!("graspgen.yaml").to_vec(),
        fixture!("graspgen_dataset.json").to_vec(),
        fixture!("bad/ragged.json").to_vec(),
        ACRONYM_JSON.as_bytes().to_vec(),
    ]
}

/// Feeds a GraspGen / ACRONYM text file as JSON and as YAML, guessed and forced.
pub fn run_grasp_text(dir: &Path, bytes: &[u8]) {
    let formats = [
        None,
        Some(GraspFormat::GraspGen),
        Some(GraspFormat::Acronym),
    ];
    read_as(dir, "fuzz_grasps.json", bytes, &formats);
    read_as(dir, "fuzz_grasps.yaml", bytes, &formats[..2]);
}

// ---------------------------------------------------------------------------------------------
// MJCF, SRDF

/// Seeds of the `mjcf` target: the repository's MJCF test robots.
pub fn mjcf_seeds() -> Vec<Vec<u8>> {
    vec![
        mjcf_fixture!("panda.xml").to_vec(),
        mjcf_fixture!("ur5.xml").to_vec(),
        mjcf_fixture!("dynamics_arm.xml").to_vec(),
    ]
}

/// `MjcfRobot::from_xml_in`, then its collisions and the chains from the first body to the
/// first twelve (FK and Jacobian at the mid configuration).
pub fn run_mjcf(dir: &Path, bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    let Ok(robot) = MjcfRobot::from_xml_in(&text, "fuzz.xml", dir) else {
        return;
    };
    let _ = robot.skipped_geoms();
    let _ = robot.collisions(&robot.mesh_resolver());
    let bodies: Vec<String> = robot
        .body_names()
        .iter()
        .take(12)
        .map(|s| s.to_string())
        .collect();
    let Some(base) = bodies.first() else { return };
    for tip in &bodies {
        let Ok(chain) = robot.chain(base, tip, None) else {
            continue;
        };
        let q = chain.mid_configuration();
        let mut jacobian = nalgebra::Matrix6xX::zeros(chain.dof());
        let _ = chain.pose_and_jacobian_into(&q, &mut jacobian);
    }
}

const SRDF: &str = r#"<?xml version="1.0"?>
<robot name="panda">
  <group name="arm"><chain base_link="panda_link0" tip_link="panda_link8"/></group>
  <group name="hand"><link name="panda_hand"/><link name="panda_leftfinger"/><joint name="panda_finger_joint1"/></group>
  <group name="both"><group name="arm"/><group name="hand"/></group>
  <group_state name="ready" group="arm"><joint name="panda_joint1" value="0"/></group_state>
  <end_effector name="hand" parent_link="panda_link8" group="hand" parent_group="arm"/>
  <virtual_joint name="fixed_base" type="fixed" parent_frame="world" child_link="panda_link0"/>
  <disable_collisions link1="panda_link0" link2="panda_link1" reason="Adjacent"/>
  <disable_collisions link1="panda_hand" link2="panda_leftfinger" reason="Adjacent"/>
  <!-- a comment --><passive_joint name="panda_finger_joint2"/>
</robot>
"#;

/// Seeds of the `srdf` target: a Panda SRDF with every element read.
pub fn srdf_seeds() -> Vec<Vec<u8>> {
    vec![SRDF.as_bytes().to_vec()]
}

/// `Srdf::parse`, then its links checked against a fixed list.
pub fn run_srdf(_: &Path, bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    if let Ok(srdf) = Srdf::parse(&text, "fuzz.srdf") {
        let links: Vec<String> = [
            "panda_link0",
            "panda_link1",
            "panda_hand",
            "panda_leftfinger",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        let _ = srdf.check_links(&links);
    }
}
