#!/usr/bin/env bash
# Builds and runs the Pinocchio (C++) dynamics peer benchmark (gravity, RNEA, CRBA) on the
# chains of `cargo bench -p graspath --bench dynamics`: example-robot-data's Panda and Baxter
# URDFs, which the built-in Panda and Baxter equal (tests/robot_data.rs). Needs a Python
# environment with `pin` and `example-robot-data`; the C++ headers Pinocchio's wheel does not
# carry (Eigen, urdfdom) are installed from PyPI into the same environment.
#
#   PYTHON=target/pyenv/bin/python examples/peers/run_pinocchio_dynamics_bench.sh
#
# Compiled for baseline x86-64 like the wheel's own libraries (see run_pinocchio_bench.sh).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
python="${PYTHON:-python3}"
out="${OUT:-${TMPDIR:-/tmp}/graspath-pinocchio-dynamics-bench}"

prefix="$("$python" -c 'import cmeel, sys; sys.stdout.write(cmeel.__path__[0] + ".prefix")' 2>/dev/null ||
  "$python" -c 'import site, sys; sys.stdout.write(site.getsitepackages()[0] + "/cmeel.prefix")')"
if [ ! -d "$prefix/include/pinocchio" ]; then
  echo "no Pinocchio headers under $prefix: pip install pin" >&2
  exit 1
fi
[ -f "$prefix/include/eigen3/Eigen/Core" ] || "$python" -m pip install -q cmeel-eigen
[ -f "$prefix/include/urdfdom_headers/urdf_model/model.h" ] || "$python" -m pip install -q cmeel-urdfdom-headers

defs=(-DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30
  -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12
  -DPINOCCHIO_WITH_URDFDOM -DPINOCCHIO_URDFDOM_HEADERS_MAJOR_VERSION=3
  -DPINOCCHIO_URDFDOM_HEADERS_MINOR_VERSION=0 -DPINOCCHIO_URDFDOM_HEADERS_PATCH_VERSION=0)
"${CXX:-g++}" -O3 -DNDEBUG -std=c++17 "${defs[@]}" \
  -I"$prefix/include" -I"$prefix/include/eigen3" -I"$prefix/include/urdfdom_headers" \
  -I"$prefix/include/urdfdom" "$here/pinocchio_dynamics.cpp" -o "$out" \
  -L"$prefix/lib" -Wl,-rpath,"$prefix/lib" \
  -lpinocchio_default -lpinocchio_parsers -lboost_filesystem -lboost_serialization

robots="$prefix/share/example-robot-data/robots"
"$out" "$robots/panda_description/urdf/panda.urdf" \
  panda_joint1 panda_joint2 panda_joint3 panda_joint4 panda_joint5 panda_joint6 panda_joint7
"$out" "$robots/baxter_description/urdf/baxter.urdf" \
  left_s0 left_s1 left_e0 left_e1 left_w0 left_w1 left_w2
