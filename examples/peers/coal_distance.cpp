// coal (Pinocchio's collision library) on the link/obstacle pairs of graspath's collision
// kernel benchmark, from C++: coal::distance and coal::collide (security margin) per pair,
// shapes and transforms built once. Built and run by examples/peers/coal_distance.py, which
// writes the pairs as text:
//
//   N margin
//   then per pair: two lines "kind s0 s1 s2 x y z qx qy qz qw" (box: full sizes; cylinder:
//   radius length 0; sphere: radius 0 0) and one line with graspath's distance.
//
//   coal_distance PAIRS.txt [REPEAT]
//
// Prints the median over REPEAT passes (default 21) of the time per pair.
#include <coal/collision.h>
#include <coal/distance.h>
#include <coal/shape/geometric_shapes.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {

struct Placed {
  std::shared_ptr<coal::ShapeBase> shape;
  coal::Transform3s pose;
};

Placed read(std::istream& in) {
  std::string kind;
  double s0, s1, s2, x, y, z, qx, qy, qz, qw;
  in >> kind >> s0 >> s1 >> s2 >> x >> y >> z >> qx >> qy >> qz >> qw;
  std::shared_ptr<coal::ShapeBase> shape;
  if (kind == "box") {
    shape = std::make_shared<coal::Box>(s0, s1, s2);
  } else if (kind == "cylinder") {
    shape = std::make_shared<coal::Cylinder>(s0, s1);
  } else {
    shape = std::make_shared<coal::Sphere>(s0);
  }
  coal::Quatf q(qw, qx, qy, qz);
  return {shape, coal::Transform3s(q.toRotationMatrix(), coal::Vec3s(x, y, z))};
}

template <class F>
double median_ns_per_pair(F&& pass, std::size_t n, int repeat) {
  std::vector<double> t;
  for (int r = 0; r < repeat; ++r) {
    auto start = std::chrono::steady_clock::now();
    pass();
    auto end = std::chrono::steady_clock::now();
    t.push_back(std::chrono::duration<double, std::nano>(end - start).count() / n);
  }
  std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: coal_distance PAIRS.txt [REPEAT]\n";
    return 2;
  }
  int repeat = argc > 2 ? std::stoi(argv[2]) : 21;
  std::ifstream in(argv[1]);
  std::size_t n;
  double margin;
  in >> n >> margin;
  std::vector<Placed> a(n), b(n);
  std::vector<double> ours(n);
  for (std::size_t i = 0; i < n; ++i) {
    a[i] = read(in);
    b[i] = read(in);
    in >> ours[i];
  }
  if (!in) {
    std::cerr << "cannot read " << argv[1] << "\n";
    return 1;
  }
  coal::DistanceRequest dreq;
  coal::DistanceResult dres;
  coal::CollisionRequest creq;
  creq.security_margin = margin;
  coal::CollisionResult cres;
  double worst = 0.0, sink = 0.0;
  std::size_t close = 0;
  for (std::size_t i = 0; i < n; ++i) {
    dres.clear();
    double d = coal::distance(a[i].shape.get(), a[i].pose, b[i].shape.get(), b[i].pose, dreq, dres);
    worst = std::max(worst, std::abs(std::max(d, 0.0) - ours[i]));
    cres.clear();
    close += coal::collide(a[i].shape.get(), a[i].pose, b[i].shape.get(), b[i].pose, creq, cres) > 0;
  }
  double distance_ns = median_ns_per_pair(
      [&] {
        for (std::size_t i = 0; i < n; ++i) {
          dres.clear();
          sink += coal::distance(a[i].shape.get(), a[i].pose, b[i].shape.get(), b[i].pose, dreq, dres);
        }
      },
      n, repeat);
  double collide_ns = median_ns_per_pair(
      [&] {
        for (std::size_t i = 0; i < n; ++i) {
          cres.clear();
          sink += coal::collide(a[i].shape.get(), a[i].pose, b[i].shape.get(), b[i].pose, creq, cres);
        }
      },
      n, repeat);
  std::printf("coal C++ (g++ -O3): %zu pairs; distances differ from graspath's by at most %.1e m; "
              "%zu within the margin\n", n, worst, close);
  std::printf("  coal::distance, C++       : %8.0f ns per pair\n", distance_ns);
  std::printf("  coal::collide (margin), C++: %8.0f ns per pair\n", collide_ns);
  return sink == 12345.6789 ? 1 : 0;
}
