// Gravity torques, RNEA and CRBA per call in Pinocchio (C++), for comparison with graspath's
// `cargo bench -p graspath --bench dynamics`: the same chains, the same 64 configurations
// inside the limits and the same velocity and acceleration patterns, cycled; the median over
// repeated timing batches.
//
// Build and run: examples/peers/run_pinocchio_dynamics_bench.sh (needs `pip install pin`).
// Arguments: URDF, the chain's joint names (every other joint is locked at zero, so the model
// is exactly the chain from the URDF's root, with the off-chain bodies attached rigidly).

#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/parsers/urdf.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <set>
#include <string>
#include <vector>

static double median_ns(const std::function<void(int)>& call) {
  for (int i = 0; i < 200000; ++i) call(i % 64);  // warm-up
  const int batches = 51, per_batch = 100000;
  std::vector<double> ns;
  for (int b = 0; b < batches; ++b) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < per_batch; ++i) call(i % 64);
    const auto stop = std::chrono::steady_clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(stop - start).count() / per_batch);
  }
  std::sort(ns.begin(), ns.end());
  return ns[batches / 2];
}

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s URDF JOINT...\n", argv[0]);
    return 2;
  }
  pinocchio::Model full;
  pinocchio::urdf::buildModel(argv[1], full);
  std::set<std::string> keep(argv + 2, argv + argc);
  std::vector<pinocchio::JointIndex> lock;
  for (pinocchio::JointIndex j = 1; j < full.joints.size(); ++j) {
    if (!keep.count(full.names[j])) lock.push_back(j);
  }
  const pinocchio::Model model =
      pinocchio::buildReducedModel(full, lock, pinocchio::neutral(full));
  pinocchio::Data data(model);

  // The configurations and rates of benches/dynamics.rs.
  std::vector<Eigen::VectorXd> qs, qds, qdds;
  auto rate = [](int n, int k, double scale) {
    Eigen::VectorXd v(n);
    for (int j = 0; j < n; ++j) v[j] = scale * (double((k * 5 + j * 11) % 21) / 10.0 - 1.0);
    return v;
  };
  for (int k = 0; k < 64; ++k) {
    Eigen::VectorXd q(model.nq);
    for (int j = 0; j < model.nq; ++j) {
      const double lo = std::max(model.lowerPositionLimit[j], -3.0);
      const double hi = std::min(model.upperPositionLimit[j], 3.0);
      const double t = double((k * 7 + j * 13) % 64) / 63.0;
      q[j] = lo + t * (hi - lo);
    }
    qs.push_back(q);
    qds.push_back(rate(model.nv, k, 1.0));
    qdds.push_back(rate(model.nv, k + 3, 2.0));
  }
  double sink = 0.0;
  const double gravity = median_ns([&](int k) {
    sink += pinocchio::computeGeneralizedGravity(model, data, qs[k])[0];
  });
  const double rnea = median_ns([&](int k) {
    sink += pinocchio::rnea(model, data, qs[k], qds[k], qdds[k])[0];
  });
  const double crba = median_ns([&](int k) {
    sink += pinocchio::crba(model, data, qs[k])(0, 0);
  });
  std::printf("%s (%d joints): median ns per call: gravity %.1f, rnea %.1f, crba %.1f%s\n",
              argv[1], model.nv, gravity, rnea, crba, sink == 12345.678 ? "!" : "");
  return 0;
}
