#!/usr/bin/env bash
# The 1000-candidate faces workload end to end: graspath against its Python peer
# (faces_tracik.py: TRAC-IK + Pinocchio + numpy) on the same wrist poses, then the comparison.
# Needs a release build (cargo build --release -p graspath-cli) and a Python environment with
# the peer's wheels (python3 -m venv target/pyenv && target/pyenv/bin/pip install numpy pin
# pytracik; no system package is needed).
#
#   PYTHON=target/pyenv/bin/python SHARED=../shared RUNS=5 examples/peers/run_faces_peer.sh
#
# After one untimed run each, the two sides run RUNS times in turn (graspath, peer, graspath,
# ...); each run's wall time (process start to exit, files written) is taken from bash's
# microsecond clock, and the medians and the median of the pairs' ratios are printed.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
python="${PYTHON:-python3}"
shared="${SHARED:-$root/../shared}"
runs="${RUNS:-5}"
work="${OUT:-${TMPDIR:-/tmp}/graspath-faces-peer}"
graspath="$root/target/release/graspath"
mkdir -p "$work"
# Like with like: the peer tracks one branch up to the joint limits, ranks by the paper's
# mu_l2 and does not time the motions, so graspath runs the workload with the same settings
# (its defaults keep a 0.1 rad margin from the limits, search the self-motion, rank by mu_rms and time every feasible
# motion). WORKLOAD_SETTINGS=defaults times graspath's defaults instead.
task="$work/workload_1000_faces.yaml"
cp "$root/examples/workload_1000_faces.yaml" "$task"
if [ "${WORKLOAD_SETTINGS:-paper}" = paper ]; then
  printf 'ik: { limit_margin: 0, redundancy: first }\nselection: { norm: l2 }\ntiming: false\n' >>"$task"
fi

# The peer's input, written once and not timed: every candidate's wrist poses.
(cd "$root" && cargo run --release -q -p graspath --example export_wrist_paths -- \
  "$task" "$work/wrists.npy")

# Wall time of one command (ms), from bash's clock in microseconds.
wall_ms() {
  local start=$EPOCHREALTIME
  "$@"
  local end=$EPOCHREALTIME
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", (b - a) * 1000 }'
}
run_graspath() {
  "$graspath" select --task "$task" --out "$work/graspath" --force --quiet
}
run_peer() {
  "$python" "$here/faces_tracik.py" --wrists "$work/wrists.npy" \
    --urdf "$shared/robots/baxter.urdf" --out "$work/peer.npz" --quiet
}

run_graspath && run_peer # warm-up, not timed
ours=()
theirs=()
for i in $(seq "$runs"); do
  ours+=("$(wall_ms run_graspath)")
  theirs+=("$(wall_ms run_peer)")
  echo "pair $i: graspath ${ours[-1]} ms, peer ${theirs[-1]} ms"
done
"$python" - "${ours[*]}" "${theirs[*]}" <<'PY'
import statistics, sys
ours = [float(v) for v in sys.argv[1].split()]
theirs = [float(v) for v in sys.argv[2].split()]
ratios = [t / o for o, t in zip(ours, theirs)]
print(f"graspath median {statistics.median(ours):.1f} ms ({min(ours):.1f}-{max(ours):.1f}), "
      f"peer median {statistics.median(theirs):.0f} ms ({min(theirs):.0f}-{max(theirs):.0f}), "
      f"ratio (median of the pairs') {statistics.median(ratios):.0f}x")
PY
"$python" "$here/compare_faces.py" "$work/graspath/candidates.json" "$work/peer.npz" \
  --wrists "$work/wrists.npy" --urdf "$shared/robots/baxter.urdf"
