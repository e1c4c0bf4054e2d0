//! FK + geometric Jacobian per call, the tip pose alone and every link frame: Baxter's arm
//! (built in, dynamic and fixed-size, and in batches), the built-in Panda's row-major batch
//! on one and two threads, Panda and UR5 from `../shared/robots` (or
//! `$GRASPATH_SHARED/robots`) when present.
//!
//! `cargo bench -p graspath --bench kinematics`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use graspath::robot::builtin::{baxter, Arm};
use graspath::robot::{load_urdf_chain, Chain, RobotSource};
use nalgebra::{IsometryMatrix3, Matrix6xX};
use std::hint::black_box;
use std::path::PathBuf;

/// Copies of the 64 configurations in the row-major batch benchmark.
const BATCH_GROUPS: usize = 64;

fn configurations(chain: &Chain) -> Vec<Vec<f64>> {
    // A fixed spread of configurations inside the limits (no RNG needed).
    (0..64)
        .map(|k| {
            chain
                .lower()
                .iter()
                .zip(chain.upper())
                .enumerate()
                .map(|(j, (&lo, &hi))| {
                    let (lo, hi) = (lo.max(-3.0), hi.min(3.0));
                    let t = ((k * 7 + j * 13) % 64) as f64 / 63.0;
                    lo + t * (hi - lo)
                })
                .collect()
        })
        .collect()
}

fn bench_dynamic(c: &mut Criterion, name: &str, chain: &Chain) {
    let qs = configurations(chain);
    let mut jacobian = Matrix6xX::zeros(chain.dof());
    let mut k = 0;
    c.bench_function(&format!("fk_jacobian/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % qs.len();
            let pose = chain
                .pose_and_jacobian_into(black_box(&qs[k]), &mut jacobian)
                .expect("valid configuration");
            black_box((pose, &jacobian));
        });
    });
}

/// The tip pose alone and every link frame, on the same configurations: the link-frame pass
/// should stay in the tip pass's speed class.
fn bench_frames(c: &mut Criterion, name: &str, chain: &Chain) {
    let qs = configurations(chain);
    let mut k = 0;
    c.bench_function(&format!("fk_tip/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % qs.len();
            black_box(chain.pose(black_box(&qs[k])).expect("valid configuration"))
        });
    });
    let mut frames = vec![IsometryMatrix3::identity(); chain.link_names().len()];
    c.bench_function(&format!("fk_link_frames/{name}"), |b| {
        b.iter(|| {
            k = (k + 1) % qs.len();
            chain
                .link_frames_into(black_box(&qs[k]), &mut frames)
                .expect("valid configuration");
            black_box(&frames);
        });
    });
}

fn kinematics(c: &mut Criterion) {
    let left = baxter(Arm::Left);
    bench_dynamic(c, "baxter_left", &left);
    bench_frames(c, "baxter_left", &left);
    let fixed = left.fixed::<7>().expect("7 joints");
    let qs: Vec<[f64; 7]> = configurations(&left)
        .into_iter()
        .map(|q| std::array::from_fn(|i| q[i]))
        .collect();
    let mut k = 0;
    c.bench_function("fk_jacobian/baxter_left_fixed7", |b| {
        b.iter(|| {
            k = (k + 1) % qs.len();
            black_box(fixed.pose_and_jacobian(black_box(&qs[k])))
        });
    });
    // A batch of 1024 configurations through `for_each_pose_and_jacobian` (four per vector
    // lane group on AVX2 processors); criterion reports the time per configuration.
    let batch: Vec<f64> = (0..16)
        .flat_map(|_| configurations(&left))
        .flatten()
        .collect();
    let mut group = c.benchmark_group("fk_jacobian_batch");
    group.throughput(Throughput::Elements((batch.len() / left.dof()) as u64));
    group.bench_function("baxter_left_1024", |b| {
        b.iter(|| {
            let mut sum = 0.0;
            left.for_each_pose_and_jacobian(black_box(&batch), |_, pose, jacobian| {
                sum += pose.translation.x + jacobian[3];
            })
            .expect("valid configurations");
            black_box(sum)
        });
    });
    group.finish();
    // The row-major batch into existing buffers (`Chain::batch_into`, what Python's
    // `fk_jacobian(q, out=...)` runs), built-in Panda, 4096 configurations (1.9 MB of results,
    // within the caches), on pools of one and two threads: the kernel and its writes without
    // the cost of memory.
    let panda = RobotSource::builtin("panda")
        .load()
        .and_then(|model| model.named_chain("arm", None))
        .expect("built-in panda");
    let rows: Vec<f64> = (0..BATCH_GROUPS)
        .flat_map(|_| configurations(&panda))
        .flatten()
        .collect();
    let n = rows.len() / panda.dof();
    let (mut poses, mut jacobians) = (vec![0.0; 16 * n], vec![0.0; 6 * panda.dof() * n]);
    let mut group = c.benchmark_group("batch_into");
    group.throughput(Throughput::Elements(n as u64));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        group.bench_function(format!("panda_{n}_threads_{threads}"), |b| {
            b.iter(|| {
                pool.install(|| {
                    panda.batch_into(black_box(&rows), Some(&mut poses), Some(&mut jacobians))
                })
                .expect("valid configurations");
            });
        });
    }
    group.finish();
    let shared = std::env::var_os("GRASPATH_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared"))
        .join("robots");
    for (name, file, base, tip) in [
        ("panda", "panda.urdf", "panda_link0", "panda_hand_tcp"),
        ("ur5", "ur5_robot.urdf", "base_link", "tool0"),
    ] {
        match load_urdf_chain(&shared.join(file), base, tip, None) {
            Ok(chain) => {
                bench_dynamic(c, name, &chain);
                bench_frames(c, name, &chain);
            }
            Err(e) => eprintln!("skipping {name}: {e}"),
        }
    }
}

criterion_group!(benches, kinematics);
criterion_main!(benches);
