//! Findings that are known and being fixed elsewhere. The CI slice tolerates (and prints) a
//! finding only if its target and a fragment of its message match an entry here; everything
//! else fails the test. Remove an entry when its fix is merged.

/// A known, not yet fixed finding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct KnownFinding {
    /// The fuzz target that reaches it.
    pub target: &'static str,
    /// A fragment of the finding's message (signature or text) that identifies it.
    pub fragment: &'static str,
    /// Where it is tracked.
    pub issue: &'static str,
}

const ISSUE_OUTLIERS: &str =
    "issue 13: far-outlier clouds (dense query grid over the cloud's extent)";
const ISSUE_PCD_PAYLOAD: &str =
    "issue 13: PCD binary_compressed payload shorter than the header promises";
const ISSUE_COUNTS: &str = "issue 13: header and option counts trusted for allocation";
const ISSUE_TASK_SIZES: &str = "issue 13: unbounded task sizes";
const NEW: &str = "new (fuzz report): needs an issue";

/// The known findings (see the module documentation).
pub const KNOWN_FINDINGS: &[KnownFinding] = &[
    // Grasp-model query density: a grid over the kernels' extent (outliers, huge widths).
    KnownFinding {
        target: "generate",
        fragment: "graspath::grasp::model::query::QueryDensity",
        issue: ISSUE_OUTLIERS,
    },
    KnownFinding {
        target: "generate",
        fragment: "graspath/src/grasp/model/query.rs",
        issue: ISSUE_OUTLIERS,
    },
    KnownFinding {
        target: "model",
        fragment: "graspath::grasp::model::query::QueryDensity",
        issue: ISSUE_OUTLIERS,
    },
    KnownFinding {
        target: "model",
        fragment: "graspath/src/grasp/model/query.rs",
        issue: ISSUE_OUTLIERS,
    },
    // PCD: compressed payloads inconsistent with POINTS / the announced sizes (in pcd-rs).
    KnownFinding {
        target: "pcd",
        fragment: "pcd-rs-0.13.0/src/reader.rs:177",
        issue: ISSUE_PCD_PAYLOAD,
    },
    KnownFinding {
        target: "generate",
        fragment: "pcd-rs-0.13.0/src/reader.rs:177",
        issue: ISSUE_PCD_PAYLOAD,
    },
    KnownFinding {
        target: "pcd",
        fragment: "pcd_rs::lzf::decompress",
        issue: ISSUE_PCD_PAYLOAD,
    },
    KnownFinding {
        target: "generate",
        fragment: "pcd_rs::lzf::decompress",
        issue: ISSUE_PCD_PAYLOAD,
    },
    KnownFinding {
        target: "pcd",
        fragment: "alloc at pcd_rs::reader::Reader<Record,R>::from_reader",
        issue: ISSUE_PCD_PAYLOAD,
    },
    KnownFinding {
        target: "generate",
        fragment: "alloc at pcd_rs::reader::Reader<Record,R>::from_reader",
        issue: ISSUE_PCD_PAYLOAD,
    },
    // PCD header counts: POINTS and SIZE × COUNT used before they are checked.
    KnownFinding {
        target: "pcd",
        fragment: "alloc at graspath::cloud::pcd::read_pcd_bytes",
        issue: ISSUE_COUNTS,
    },
    KnownFinding {
        target: "generate",
        fragment: "alloc at graspath::cloud::pcd::read_pcd_bytes",
        issue: ISSUE_COUNTS,
    },
    KnownFinding {
        target: "pcd",
        fragment: "raw_vec/mod.rs:28 in graspath::cloud::pcd::read_pcd_bytes",
        issue: ISSUE_COUNTS,
    },
    KnownFinding {
        target: "generate",
        fragment: "raw_vec/mod.rs:28 in graspath::cloud::pcd::read_pcd_bytes",
        issue: ISSUE_COUNTS,
    },
    KnownFinding {
        target: "pcd",
        fragment: "pcd-rs-0.13.0/src/reader.rs:151",
        issue: ISSUE_COUNTS,
    },
    KnownFinding {
        target: "generate",
        fragment: "pcd-rs-0.13.0/src/reader.rs:151",
        issue: ISSUE_COUNTS,
    },
    // PLY: an element count with no payload behind it is looped over.
    KnownFinding {
        target: "ply",
        fragment: "ply_rs_bw::parser::Parser<E>::__read_",
        issue: ISSUE_COUNTS,
    },
    // JSON cloud sources: `points` drives the allocation and the sampling time.
    KnownFinding {
        target: "cloud_json",
        fragment: "graspath::cloud::primitives::sample_primitive",
        issue: ISSUE_COUNTS,
    },
    KnownFinding {
        target: "cloud_json",
        fragment: "graspath::cloud::mesh::TriangleMesh::sample",
        issue: ISSUE_COUNTS,
    },
    KnownFinding {
        target: "demo",
        fragment: "graspath::cloud::primitives::sample_primitive",
        issue: ISSUE_COUNTS,
    },
    KnownFinding {
        target: "demo",
        fragment: "graspath::cloud::mesh::TriangleMesh::sample",
        issue: ISSUE_COUNTS,
    },
    // Task files: samples, spacing and family counts drive allocation and time.
    KnownFinding {
        target: "task_yaml",
        fragment: "graspath::task::path::",
        issue: ISSUE_TASK_SIZES,
    },
    KnownFinding {
        target: "task_json",
        fragment: "graspath::task::path::",
        issue: ISSUE_TASK_SIZES,
    },
    KnownFinding {
        target: "task_yaml",
        fragment: "graspath::grasp::families::",
        issue: ISSUE_TASK_SIZES,
    },
    KnownFinding {
        target: "task_json",
        fragment: "graspath::grasp::families::",
        issue: ISSUE_TASK_SIZES,
    },
    // Found by this fuzzer and not covered by issue 13's list.
    KnownFinding {
        target: "model",
        fragment: "graspath::grasp::model::configuration::ConfigurationModel::new",
        issue: NEW,
    },
    KnownFinding {
        target: "model",
        fragment: "min > max, or either was NaN",
        issue: NEW,
    },
    KnownFinding {
        target: "model",
        fragment: "graspath/src/grasp/hand/mod.rs:151",
        issue: NEW,
    },
    KnownFinding {
        target: "urdf",
        fragment: "Cannot compute the SVD of an empty matrix",
        issue: NEW,
    },
    KnownFinding {
        target: "urdf",
        fragment: "Singular value was NaN",
        issue: NEW,
    },
    KnownFinding {
        target: "urdf",
        fragment: "graspath::manipulability::indices::singular_values",
        issue: NEW,
    },
    KnownFinding {
        target: "urdf",
        fragment: "graspath/src/robot/ik/kernel.rs:430",
        issue: NEW,
    },
    KnownFinding {
        target: "ply",
        fragment: "invariant: normals are unit vectors",
        issue: NEW,
    },
    KnownFinding {
        target: "pcd",
        fragment: "invariant: normals are unit vectors",
        issue: NEW,
    },
    KnownFinding {
        target: "cloud_json",
        fragment: "invariant: a cloud read without error has only finite points",
        issue: NEW,
    },
];

/// The known finding that covers a failure of `target` with this signature and message.
pub fn known(target: &str, signature: &str, message: &str) -> Option<&'static KnownFinding> {
    KNOWN_FINDINGS.iter().find(|k| {
        k.target == target && (signature.contains(k.fragment) || message.contains(k.fragment))
    })
}
