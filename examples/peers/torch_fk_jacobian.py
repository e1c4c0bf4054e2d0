"""A plain batched PyTorch forward kinematics + geometric Jacobian of the Franka Emika Panda
(``panda_link0`` → ``panda_hand_tcp``), the peer of ``graspath.Robot.builtin("panda").fk_jacobian``.

The chain is written out here from ``franka_description``'s joint origins (xyz in metres, rpy in
radians, every joint turning about its own ``z``), independently of graspath: joint ``i``'s
frame is its parent's frame times the fixed origin ``(R_i, t_i)`` times ``Rz(q_i)``; after the
seventh joint come the flange (0.107 m along ``z``), the hand (−π/4 about ``z``) and the tool
centre point (0.1034 m along ``z``).

Results, for a batch ``q`` of shape ``(n, 7)`` (rad):

* ``poses`` ``(n, 4, 4)``: ``base_from_tcp`` (homogeneous, metres);
* ``jacobians`` ``(n, 6, 7)``: the geometric Jacobian in the base frame, rows ``[v; ω]``
  (``v`` the linear velocity of the TCP origin), column ``i`` = ``[z_i × (p_tcp − p_i); z_i]``.

Batched over the configurations, one group of element-wise tensor operations per joint
(nothing fused, no ``torch.compile``). It runs on the CPU, or on a GPU with ``--device cuda``.

``python examples/peers/torch_fk_jacobian.py --check`` compares it with graspath (float64,
1e-12) when graspath is installed; ``examples/python/bench_batch.py`` times both in one run.
"""

import argparse
import math
import time

import torch

# Joint origins in the parent link (xyz m, rpy rad): joints 1–7, flange, hand, TCP.
ORIGINS = [
    ((0.0, 0.0, 0.333), (0.0, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (-math.pi / 2, 0.0, 0.0)),
    ((0.0, -0.316, 0.0), (math.pi / 2, 0.0, 0.0)),
    ((0.0825, 0.0, 0.0), (math.pi / 2, 0.0, 0.0)),
    ((-0.0825, 0.384, 0.0), (-math.pi / 2, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (math.pi / 2, 0.0, 0.0)),
    ((0.088, 0.0, 0.0), (math.pi / 2, 0.0, 0.0)),
    ((0.0, 0.0, 0.107), (0.0, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (0.0, 0.0, -math.pi / 4)),
    ((0.0, 0.0, 0.1034), (0.0, 0.0, 0.0)),
]
DOF = 7


def rpy_matrix(roll, pitch, yaw):
    """URDF's ``Rz(yaw) · Ry(pitch) · Rx(roll)`` as nested lists."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]


class PandaKinematics:
    """The Panda's fixed joint origins as tensors on one device and dtype."""

    def __init__(self, device="cpu", dtype=torch.float64):
        self.device, self.dtype = device, dtype
        self.rotations = [torch.tensor(rpy_matrix(*rpy), device=device, dtype=dtype) for _, rpy in ORIGINS]
        self.translations = [torch.tensor(xyz, device=device, dtype=dtype) for xyz, _ in ORIGINS]
        # The three fixed transforms after joint 7, composed once: link7_from_tcp.
        rotation = torch.eye(3, device=device, dtype=dtype)
        translation = torch.zeros(3, device=device, dtype=dtype)
        for r, t in zip(self.rotations[DOF:], self.translations[DOF:]):
            translation = translation + rotation @ t
            rotation = rotation @ r
        self.tail_rotation, self.tail_translation = rotation, translation
        # The constants as Python floats: they multiply whole tensors.
        self.rotations_list = [r.tolist() for r in self.rotations]
        self.translations_list = [t.tolist() for t in self.translations]
        self.tail_rotation_list = rotation.tolist()
        self.tail_translation_list = translation.tolist()

    def fk_jacobian(self, q):
        """Poses ``(n, 4, 4)`` and Jacobians ``(n, 6, 7)`` of the configurations ``q`` ``(n, 7)``.

        The frame is kept as its three rotation columns ``x, y, z`` and its origin ``p``, each
        an ``(n, 3)`` tensor; a fixed origin combines the columns with the constants of its
        rotation, a joint turns ``x`` and ``y`` by its angle."""
        n = q.shape[0]
        ones = torch.ones(n, 1, device=self.device, dtype=self.dtype)
        x = ones * torch.tensor([1.0, 0.0, 0.0], device=self.device, dtype=self.dtype)
        y = ones * torch.tensor([0.0, 1.0, 0.0], device=self.device, dtype=self.dtype)
        z = ones * torch.tensor([0.0, 0.0, 1.0], device=self.device, dtype=self.dtype)
        p = torch.zeros(n, 3, device=self.device, dtype=self.dtype)
        cos, sin = torch.cos(q), torch.sin(q)
        axes, origins = [], []

        def place(x, y, z, p, r, t):
            """The frame (x, y, z, p) followed by the fixed transform (r, t)."""
            p = p + x * t[0] + y * t[1] + z * t[2]
            columns = [x * r[0][k] + y * r[1][k] + z * r[2][k] for k in range(3)]
            return (*columns, p)

        for i in range(DOF):
            x, y, z, p = place(x, y, z, p, self.rotations_list[i], self.translations_list[i])
            axes.append(z)
            origins.append(p)
            c, s = cos[:, i : i + 1], sin[:, i : i + 1]
            x, y = x * c + y * s, y * c - x * s
        x, y, z, tip = place(x, y, z, p, self.tail_rotation_list, self.tail_translation_list)
        poses = torch.zeros(n, 4, 4, device=self.device, dtype=self.dtype)
        poses[:, :3, 0], poses[:, :3, 1], poses[:, :3, 2], poses[:, :3, 3] = x, y, z, tip
        poses[:, 3, 3] = 1.0
        jacobians = torch.empty(n, 6, DOF, device=self.device, dtype=self.dtype)
        for i, (a, o) in enumerate(zip(axes, origins)):
            jacobians[:, :3, i] = torch.linalg.cross(a, tip - o, dim=1)
            jacobians[:, 3:, i] = a
        return poses, jacobians


def check_against_graspath(n=1000, seed=0, tolerance=1e-12):
    """The largest difference to graspath's poses and Jacobians on ``n`` random configurations
    (float64, CPU); raises when it exceeds ``tolerance``."""
    import numpy as np

    import graspath

    robot = graspath.Robot.builtin("panda")
    rng = np.random.default_rng(seed)
    q = robot.lower + (robot.upper - robot.lower) * rng.random((n, robot.dof))
    poses, jacobians = robot.fk_jacobian(q)
    torch_poses, torch_jacobians = PandaKinematics().fk_jacobian(torch.from_numpy(q))
    error = max(
        float(np.abs(torch_poses.numpy() - poses).max()),
        float(np.abs(torch_jacobians.numpy() - jacobians).max()),
    )
    if not error <= tolerance:
        raise AssertionError(f"PyTorch and graspath differ by {error:.3e} (> {tolerance:g})")
    return error


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=int, default=1_000_000)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--dtype", choices=("float64", "float32"), default="float64")
    parser.add_argument("--threads", type=int, default=None, help="torch.set_num_threads (CPU)")
    parser.add_argument("--check", action="store_true", help="compare with graspath first")
    args = parser.parse_args()
    if args.threads:
        torch.set_num_threads(args.threads)
    if args.check:
        print(f"largest difference to graspath: {check_against_graspath():.3e}")
    dtype = getattr(torch, args.dtype)
    kinematics = PandaKinematics(args.device, dtype)
    generator = torch.Generator().manual_seed(0)
    q = (torch.rand(args.n, DOF, generator=generator, dtype=torch.float64) * 5.0 - 2.5).to(args.device, dtype)
    times = []
    for _ in range(args.repeat):
        if args.device != "cpu":
            torch.cuda.synchronize()
        start = time.perf_counter()
        kinematics.fk_jacobian(q)
        if args.device != "cpu":
            torch.cuda.synchronize()
        times.append(time.perf_counter() - start)
    median = sorted(times)[len(times) // 2]
    print(
        f"torch {torch.__version__} {args.device} {args.dtype} threads={torch.get_num_threads()}: "
        f"{args.n} configurations, median {median * 1e3:.1f} ms, {args.n / median / 1e6:.2f} M configs/s"
    )


if __name__ == "__main__":
    main()
