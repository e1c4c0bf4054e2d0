//! Writes the T-shape cloud of `examples/grasp/t_shape.json` (5 000 points with normals) as
//! PLY, alone and with 200 outliers at 10 m, 1 km and 1e20 m from the object (random
//! directions, seeded; normals pointing back at the object), for measuring `graspath
//! generate` on scans with far outliers (BENCHMARKS.md).
//!
//! ```text
//! cargo run --release -p graspath --example outlier_clouds -- DIR
//! ```
//!
//! writes `DIR/t_shape.ply`, `DIR/t_shape_10m.ply`, `DIR/t_shape_1km.ply`,
//! `DIR/t_shape_1e20m.ply`. The `generate` criterion bench builds the same clouds in memory,
//! from the same code (`examples/shared/t_shape_outliers.rs`).

use graspath::cloud::write_cloud;
use std::path::PathBuf;

#[path = "shared/t_shape_outliers.rs"]
mod shared;

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    for (name, cloud) in shared::t_shape_outlier_clouds() {
        if name == "none" {
            write_cloud(&dir.join("t_shape.ply"), &cloud).expect("write");
            continue;
        }
        let path = dir.join(format!("t_shape_{name}.ply"));
        write_cloud(&path, &cloud).expect("write");
        println!("wrote {} ({} points)", path.display(), cloud.len());
    }
}
