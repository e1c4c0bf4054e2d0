"""Times coal (Pinocchio's collision library, from the `pin` wheel) on the link/obstacle pairs
written by `cargo bench -p graspath --bench collision` (which runs this script itself when
COAL_PYTHON is set), and checks its distances against graspath's.

    python examples/peers/coal_distance.py target/tmp/collision_pairs.json [--repeat 21]

Pairs file: {"margin": m, "pairs": [{"a": shape, "pose_a": [x, y, z, qx, qy, qz, qw],
"b": shape, "pose_b": ..., "distance": graspath's distance}]}, shapes {"box": [x, y, z]}
(full sizes), {"cylinder": [radius, length]} (along z) or {"sphere": radius}; metres.

Timed, each as the median over --repeat passes over every pair, per pair:
* Python loop calling coal.distance(geometry, transform, geometry, transform, request,
  result) on shapes and transforms built once (Boost.Python call included);
* the same loop calling coal.collide with security_margin = margin (the yes/no decision);
* the bare Python loop over the same tuples (no call), to show how much is the interpreter.
With a C++ compiler and the wheel's headers, the same pairs are also timed from C++
(examples/peers/coal_distance.cpp), which is the kernel's own cost.
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import coal


def geometry(shape):
    if "box" in shape:
        return coal.Box(*shape["box"])
    if "cylinder" in shape:
        radius, length = shape["cylinder"]
        return coal.Cylinder(radius, length)
    if "sphere" in shape:
        return coal.Sphere(shape["sphere"])
    raise ValueError(f"unknown shape {shape}")


def transform(pose):
    x, y, z, qx, qy, qz, qw = pose
    rotation = coal.Quaternion(qw, qx, qy, qz).toRotationMatrix() if hasattr(
        coal, "Quaternion") else quaternion_matrix(qx, qy, qz, qw)
    return coal.Transform3s(np.asarray(rotation), np.array([x, y, z]))


def quaternion_matrix(x, y, z, w):
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def median_per_pair(run, n, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        times.append((time.perf_counter() - start) / n)
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("pairs")
    parser.add_argument("--repeat", type=int, default=21)
    args = parser.parse_args()
    with open(args.pairs) as f:
        data = json.load(f)
    margin = data["margin"]
    cache = {}

    def shape_of(shape):
        key = json.dumps(shape, sort_keys=True)
        if key not in cache:
            cache[key] = geometry(shape)
        return cache[key]

    items = [(shape_of(p["a"]), transform(p["pose_a"]), shape_of(p["b"]),
              transform(p["pose_b"])) for p in data["pairs"]]
    ours = [p["distance"] for p in data["pairs"]]
    n = len(items)

    request, result = coal.DistanceRequest(), coal.DistanceResult()
    theirs = []
    for a, ta, b, tb in items:
        result.clear()
        theirs.append(coal.distance(a, ta, b, tb, request, result))
    # coal reports a negative value (penetration) for overlapping pairs; graspath 0.
    worst = max(abs(max(t, 0.0) - o) for t, o in zip(theirs, ours))

    collision_request = coal.CollisionRequest()
    collision_request.security_margin = margin
    collision_result = coal.CollisionResult()
    close = 0
    for a, ta, b, tb in items:
        collision_result.clear()
        close += coal.collide(a, ta, b, tb, collision_request, collision_result) > 0

    def distance_loop():
        for a, ta, b, tb in items:
            coal.distance(a, ta, b, tb, request, result)

    def collide_loop():
        for a, ta, b, tb in items:
            coal.collide(a, ta, b, tb, collision_request, collision_result)

    def bare_loop():
        for a, ta, b, tb in items:
            pass

    distance_ns = median_per_pair(distance_loop, n, args.repeat) * 1e9
    collide_ns = median_per_pair(collide_loop, n, args.repeat) * 1e9
    bare_ns = median_per_pair(bare_loop, n, args.repeat) * 1e9
    version = getattr(coal, "__version__", "?")
    print(f"coal {version} (Python {sys.version.split()[0]}): {n} pairs; distances differ "
          f"from graspath's by at most {worst:.1e} m; {close} within the {margin} m margin")
    print(f"  coal.distance, Python loop : {distance_ns:8.0f} ns per pair")
    print(f"  coal.collide (margin), loop: {collide_ns:8.0f} ns per pair")
    print(f"  bare Python loop           : {bare_ns:8.0f} ns per pair")
    cpp(args.pairs, data, args.repeat)


def cpp(path, data, repeat):
    """The same pairs timed from C++, when a compiler and the wheel's headers are there."""
    here = os.path.dirname(os.path.abspath(__file__))
    source = os.path.join(here, "coal_distance.cpp")
    compiler = os.environ.get("CXX", "g++")
    try:
        import cmeel
        prefix = cmeel.__path__[0] + ".prefix"
    except ImportError:
        import site
        prefix = os.path.join(site.getsitepackages()[0], "cmeel.prefix")
    if not (shutil.which(compiler) and os.path.isdir(os.path.join(prefix, "include", "coal"))):
        print("  (C++ timing skipped: no compiler or no coal headers under", prefix, ")")
        return
    if not os.path.isfile(os.path.join(prefix, "include", "eigen3", "Eigen", "Core")):
        subprocess.run([sys.executable, "-m", "pip", "install", "-q", "cmeel-eigen"], check=True)
    out = os.path.join(tempfile.gettempdir(), "graspath-coal-distance")
    subprocess.run([compiler, "-O3", "-DNDEBUG", "-std=c++17", "-I" + os.path.join(prefix, "include"),
                    "-I" + os.path.join(prefix, "include", "eigen3"), source, "-o", out,
                    "-L" + os.path.join(prefix, "lib"), "-Wl,-rpath," + os.path.join(prefix, "lib"),
                    "-lcoal"], check=True)
    # Plain text for the C++ reader: kind, three size values, both poses, per pair.
    text = os.path.join(tempfile.gettempdir(), "graspath-coal-pairs.txt")
    with open(text, "w") as f:
        f.write(f"{len(data['pairs'])} {data['margin']!r}\n")
        for p in data["pairs"]:
            for shape, pose in ((p["a"], p["pose_a"]), (p["b"], p["pose_b"])):
                if "box" in shape:
                    f.write("box " + " ".join(repr(v) for v in shape["box"]))
                elif "cylinder" in shape:
                    f.write("cylinder " + " ".join(repr(v) for v in shape["cylinder"]) + " 0")
                else:
                    f.write(f"sphere {shape['sphere']!r} 0 0")
                f.write(" " + " ".join(repr(v) for v in pose) + "\n")
            f.write(repr(p["distance"]) + "\n")
    subprocess.run([out, text, str(repeat)], check=True)


if __name__ == "__main__":
    main()
