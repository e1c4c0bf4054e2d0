#!/usr/bin/env bash
# The 1000-candidate faces workload end to end: graspath against its Python peer
# (faces_tracik.py: TRAC-IK + Pinocchio + numpy) on the same wrist poses, then the comparison.
# Needs a release build (cargo build --release -p graspath-cli) and a Python environment with
# the peer's wheels (python3 -m venv target/pyenv && target/pyenv/bin/pip install numpy pin
# pytracik; no system package is needed).
#
#   PYTHON=target/pyenv/bin/python SHARED=../shared RUNS=5 examples/peers/run_faces_peer.sh
#
# Each side runs RUNS times in turn (graspath, peer, graspath, ...); every run's wall time
# (process start to exit, files written) is printed by /usr/bin/time. Quote medians.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
python="${PYTHON:-python3}"
shared="${SHARED:-$root/../shared}"
runs="${RUNS:-5}"
work="${OUT:-${TMPDIR:-/tmp}/graspath-faces-peer}"
task="$root/examples/workload_1000_faces.yaml"
graspath="$root/target/release/graspath"
mkdir -p "$work"

# The peer's input, written once and not timed: every candidate's wrist poses.
(cd "$root" && cargo run --release -q -p graspath --example export_wrist_paths -- \
  "$task" "$work/wrists.npy")

for i in $(seq "$runs"); do
  rm -rf "$work/graspath"
  /usr/bin/time -f "graspath wall %e s" "$graspath" select --task "$task" \
    --out "$work/graspath" --quiet
  /usr/bin/time -f "peer wall %e s" "$python" "$here/faces_tracik.py" --wrists "$work/wrists.npy" \
    --urdf "$shared/robots/baxter.urdf" --out "$work/peer.npz" --quiet
done
"$python" "$here/compare_faces.py" "$work/graspath/candidates.json" "$work/peer.npz" \
  --wrists "$work/wrists.npy" --urdf "$shared/robots/baxter.urdf"
