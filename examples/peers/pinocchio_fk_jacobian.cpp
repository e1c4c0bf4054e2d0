// FK + frame Jacobian per call in Pinocchio (C++), for comparison with graspath's
// `cargo bench -p graspath --bench kinematics`: the same chains, 64 configurations inside the
// limits cycled, the median over repeated timing batches.
//
// Build and run: examples/peers/run_pinocchio_bench.sh (needs `pip install pin`).
// Arguments: URDF, tip frame, the chain's joint names (every other joint is locked at zero, so
// the model is exactly the chain from the URDF's root).

#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/parsers/urdf.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s URDF TIP JOINT...\n", argv[0]);
    return 2;
  }
  pinocchio::Model full;
  pinocchio::urdf::buildModel(argv[1], full);
  const std::string tip = argv[2];
  std::set<std::string> keep(argv + 3, argv + argc);
  std::vector<pinocchio::JointIndex> lock;
  for (pinocchio::JointIndex j = 1; j < full.joints.size(); ++j) {
    if (!keep.count(full.names[j])) lock.push_back(j);
  }
  const pinocchio::Model model =
      pinocchio::buildReducedModel(full, lock, pinocchio::neutral(full));
  pinocchio::Data data(model);
  const auto frame = model.getFrameId(tip);
  if (frame >= model.frames.size()) {
    std::fprintf(stderr, "no frame '%s'\n", tip.c_str());
    return 1;
  }

  // 64 configurations spread inside the limits (clamped to ±3 rad), as in the Rust bench.
  std::vector<Eigen::VectorXd> qs;
  for (int k = 0; k < 64; ++k) {
    Eigen::VectorXd q(model.nq);
    for (int j = 0; j < model.nq; ++j) {
      const double lo = std::max(model.lowerPositionLimit[j], -3.0);
      const double hi = std::min(model.upperPositionLimit[j], 3.0);
      const double t = double((k * 7 + j * 13) % 64) / 63.0;
      q[j] = lo + t * (hi - lo);
    }
    qs.push_back(q);
  }

  pinocchio::Data::Matrix6x jacobian(6, model.nv);
  double sink = 0.0;
  auto call = [&](const Eigen::VectorXd& q) {
    jacobian.setZero();
    pinocchio::computeFrameJacobian(model, data, q, frame, pinocchio::LOCAL_WORLD_ALIGNED,
                                    jacobian);
    pinocchio::updateFramePlacement(model, data, frame);
    sink += data.oMf[frame].translation()[0] + jacobian(0, 0);
  };
  for (int i = 0; i < 200000; ++i) call(qs[i % 64]);  // warm-up

  const int batches = 101, per_batch = 100000;
  std::vector<double> ns;
  for (int b = 0; b < batches; ++b) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < per_batch; ++i) call(qs[i % 64]);
    const auto stop = std::chrono::steady_clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(stop - start).count() / per_batch);
  }
  std::sort(ns.begin(), ns.end());
  std::printf("%s -> %s (%d joints): median %.1f ns per FK + Jacobian (min %.1f, max %.1f)%s\n",
              argv[1], tip.c_str(), model.nv, ns[batches / 2], ns.front(), ns.back(),
              sink == 12345.678 ? "!" : "");
  return 0;
}
