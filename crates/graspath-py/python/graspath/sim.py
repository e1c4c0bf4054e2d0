"""Execute grasps and their tasks in MuJoCo, and measure whether they succeed.

``graspath.sim`` builds the task's world once (:func:`graspath.world_mjcf`: the arms with
their inertias and torque motors, a force-limited parallel gripper at each tool, the object as
a free body, the table and the obstacles), then runs each candidate's timed motion
(:func:`graspath.candidate_motions`) under computed-torque control: the arm starts at rest at
the pre-grasp pose, approaches, stops while the gripper closes, carries the object along the
task, stops while the gripper opens at the place, retreats, and waits for the object to settle.

Two grasp modes are measured apart and never mixed: ``friction`` (the fingers hold the object
by friction alone, so it may slip or drop) and ``weld`` (the object is welded to the tool when
the gripper has closed: this isolates the arm — tracking, torque limits, collisions — from the
grip).

Measured per run (see ``docs/simulation.md`` for the definitions and the success rule):
the object's pose error against the task's goal at the place (``delivery``) and after release
and settling (``final``, with a table), the object's slip in the hand during the carry, a drop,
the joints' tracking error, torque saturation, and contacts of the arm or hand with the table,
the obstacles or the object that the task does not intend.

Run an experiment from the command line::

    python -m graspath.sim TASK.yaml --out sim.json [-k 5] [-n 10] [--seed 0]

It simulates the top ``k`` grasps by the task's index, the classical index's choice (the
largest Yoshikawa manipulability at the grasp), the likelihood's choice and ``n`` random
feasible grasps, in both modes, at the planned speed and slowed down, and writes every run's
measurements and a summary to ``sim.json``. Needs the optional extra ``graspath[sim]``
(``mujoco``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from dataclasses import asdict, dataclass
from typing import Any, Dict, List, Optional, Sequence

import numpy as np

import graspath

#: The success rule's tolerances: the object within this distance (m) and angle (rad) of the
#: task's goal, and no drop.
POSITION_TOLERANCE = 0.02
ANGLE_TOLERANCE = math.radians(10.0)
#: The object is dropped when it has moved this far (m) in the hand during the carry.
DROP_DISTANCE = 0.05


@dataclass(frozen=True)
class SimOptions:
    """How a run is set up. Times in seconds, gains in 1/s² and 1/s."""

    #: ``friction`` (the fingers hold the object) or ``weld`` (the object welded to the tool).
    mode: str = "friction"
    #: Durations multiplied by this (2: half the planned speed).
    slowdown: float = 1.0
    timestep: float = 0.002
    #: Sliding friction of the fingers and the object.
    friction: float = 1.0
    #: Largest force of each finger (N).
    grip_force: float = 40.0
    #: The object's density when the task gives no mass (kg/m³).
    object_density: float = 500.0
    #: Object mass override (kg); ``None``: the task's (or the density's).
    object_mass: Optional[float] = None
    #: How long the arm stops while the gripper closes, and while it opens.
    close_time: float = 0.5
    open_time: float = 0.3
    #: How long the object is left to settle after the retreat.
    settle_time: float = 0.5
    #: Carry the arm's and hand's own weight outside the motors (MuJoCo ``gravcomp``), so
    #: that the motors' limits apply to the motion and the object only: the model of a
    #: gravity-assist spring or counterbalance (Baxter's shoulder ``s1`` has one, which its
    #: published 50 N·m limit leaves out). Off by default: the motors carry everything.
    arm_gravity_compensation: bool = False
    #: Feedback gains of the computed-torque controller: ``q̈ = q̈_ref + kp e + kd ė``
    #: (natural frequency 20 rad/s, critically damped).
    kp: float = 400.0
    kd: float = 40.0

    def check(self) -> None:
        if self.mode not in ("friction", "weld"):
            raise ValueError(f"mode: {self.mode!r} is neither 'friction' nor 'weld'")
        for name, lo, hi in (
            ("slowdown", 0.05, 100.0),
            ("close_time", 0.0, 10.0),
            ("open_time", 0.0, 10.0),
            ("settle_time", 0.0, 60.0),
            ("kp", 0.0, 1e6),
            ("kd", 0.0, 1e4),
        ):
            value = getattr(self, name)
            if not (lo <= value <= hi):
                raise ValueError(f"{name}: {value} is not within {lo} to {hi}")
        if self.object_mass is not None and not (0.0 < self.object_mass <= 1000.0):
            raise ValueError(f"object_mass: {self.object_mass} is not within 0 to 1000 kg")


def _import_mujoco():
    try:
        import mujoco  # noqa: F401
    except ImportError as error:  # pragma: no cover - the extra is missing
        raise ImportError(
            "graspath.sim needs MuJoCo: pip install 'graspath[sim]' (or pip install mujoco)"
        ) from error
    return mujoco


def _rotation_angle(r: np.ndarray) -> float:
    """The angle (rad) of the rotation matrix ``r``."""
    return float(math.acos(max(-1.0, min(1.0, (np.trace(r) - 1.0) / 2.0))))


#: Which contacts are unintended, by the two geoms' classes (0 the static world, 1 the object,
#: 2 an arm link, 3 the hand): an arm link touching anything, the hand touching the world.
UNINTENDED = np.zeros((4, 4), dtype=bool)
UNINTENDED[2, :] = UNINTENDED[:, 2] = True
UNINTENDED[0, 3] = UNINTENDED[3, 0] = True


def _as_slice(indices: np.ndarray):
    """A slice for consecutive indices (views instead of copies), else the indices."""
    indices = np.asarray(indices, dtype=int)
    if indices.size and np.array_equal(indices, np.arange(indices[0], indices[0] + indices.size)):
        return slice(int(indices[0]), int(indices[0]) + indices.size)
    return indices


def _pose(data, body: int):
    return data.xpos[body].copy(), data.xmat[body].reshape(3, 3).copy()


class World:
    """A task's world compiled once for MuJoCo; :meth:`run` executes candidates in it.

    The model is the one :func:`graspath.world_mjcf` writes for ``task`` with ``options``'
    world settings (time step, friction, grip force, density); runs differ in their mode,
    slowdown and candidates only.
    """

    def __init__(self, task: "graspath.Task", options: SimOptions = SimOptions()):
        options.check()
        mujoco = _import_mujoco()
        self.mujoco = mujoco
        self.task = task
        self.options = options
        self.world = graspath.world_mjcf(
            task,
            timestep=options.timestep,
            friction=options.friction,
            grip_force=options.grip_force,
            object_density=options.object_density,
            arm_gravity_compensation=options.arm_gravity_compensation,
        )
        model = mujoco.MjModel.from_xml_string(self.world["xml"])
        self.model = model
        self.data = mujoco.MjData(model)
        self.object_body = model.body(self.world["object"]).id
        if options.object_mass is not None:
            scale = options.object_mass / model.body_mass[self.object_body]
            model.body_mass[self.object_body] *= scale
            model.body_inertia[self.object_body] *= scale
        self.object_mass = float(model.body_mass[self.object_body])
        self.object_qpos = model.joint(self.world["object"]).qposadr[0]
        self.object_dof = model.joint(self.world["object"]).dofadr[0]
        self.arms = []
        for names in self.world["arms"]:
            joints = [model.joint(j) for j in names["joints"]]
            fingers = [model.joint(f) for f in names["fingers"]]
            self.arms.append(
                {
                    "names": names,
                    "qpos": np.array([j.qposadr[0] for j in joints]),
                    "dof": np.array([j.dofadr[0] for j in joints]),
                    "motors": np.array([model.actuator(j).id for j in names["joints"]]),
                    "effort": np.array(names["effort"], dtype=float),
                    "fingers": np.array([model.actuator(f).id for f in names["fingers"]]),
                    "finger_qpos": np.array([f.qposadr[0] for f in fingers], dtype=int),
                    "tool": model.body(names["tool"]).id,
                    "weld": model.equality(names["grasp_weld"]).id,
                }
            )
            arm = self.arms[-1]
            arm["qslice"] = _as_slice(arm["qpos"])
            arm["dslice"] = _as_slice(arm["dof"])
            arm["mslice"] = _as_slice(arm["motors"])
            arm["fslice"] = _as_slice(arm["fingers"])
            arm["lower_effort"] = -arm["effort"]
        # Geom classes for the contact report: 0 static world, 1 object, 2 arm link, 3 hand.
        cls = np.zeros(model.ngeom, dtype=np.int8)
        arm_bodies = set()
        for arm in self.arms:
            arm_bodies |= self._subtree(self.model.body(arm["names"]["arm"] + "/base").id)
        hand_bodies = set()
        for arm in self.arms:
            hand_bodies |= self._subtree(arm["tool"])
        for g in range(model.ngeom):
            body = model.geom_bodyid[g]
            if body == self.object_body:
                cls[g] = 1
            elif body in hand_bodies:
                cls[g] = 3
            elif body in arm_bodies:
                cls[g] = 2
        self.geom_class = cls
        poses = task.object_poses
        self.goal = np.asarray(poses[-1])
        self.start = np.asarray(poses[0])
        self.last_wall_time = 0.0

    def _subtree(self, root: int) -> set:
        out = {root}
        for b in range(self.model.nbody):
            parent = b
            while parent != 0:
                if parent == root:
                    out.add(b)
                    break
                parent = self.model.body_parentid[parent]
        return out

    def _reference(self, motion: Dict[str, Any], k: float):
        """The reference at every simulation step, with the two stops inserted: (q, q̇, q̈),
        and the step indices where the grasp closes, the carry starts, the place opens and
        the retreat starts."""
        o = self.options
        dt = o.timestep
        q, qd, qdd = motion["positions"], motion["velocities"] / k, motion["accelerations"] / k**2
        period = dt / k
        n = q.shape[0]
        i_grasp = min(n - 1, int(round(motion["grasp_time"] / period)))
        i_place = min(n - 1, int(round(motion["place_time"] / period)))
        close = int(round(o.close_time / dt))
        open_ = int(round(o.open_time / dt))
        settle = int(round(o.settle_time / dt))

        def hold(i: int, count: int):
            return (
                np.repeat(q[i : i + 1], count, axis=0),
                np.zeros((count, q.shape[1])),
                np.zeros((count, q.shape[1])),
            )

        parts = [
            (q[: i_grasp + 1], qd[: i_grasp + 1], qdd[: i_grasp + 1]),
            hold(i_grasp, close),
            (q[i_grasp + 1 : i_place + 1], qd[i_grasp + 1 : i_place + 1], qdd[i_grasp + 1 : i_place + 1]),
            hold(i_place, open_),
            (q[i_place + 1 :], qd[i_place + 1 :], qdd[i_place + 1 :]),
            hold(n - 1, settle),
        ]
        ref = tuple(np.concatenate([p[j] for p in parts]) for j in range(3))
        closed = i_grasp + 1 + close
        placed = closed + (i_place - i_grasp)
        opened = placed + open_
        return ref, closed, placed, opened

    def run(
        self,
        candidates: Sequence[int],
        *,
        mode: Optional[str] = None,
        slowdown: Optional[float] = None,
    ) -> Dict[str, Any]:
        """Executes the candidates at positions ``candidates`` (one per arm) and returns the
        run's measurements (a dict; ``status`` ``"infeasible"`` when graspath finds no
        feasible timed motion for them). The wall-clock time of the run is left in
        :attr:`last_wall_time`, not in the result (which the same inputs reproduce exactly)."""
        mujoco, model, data, o = self.mujoco, self.model, self.data, self.options
        mode = mode or o.mode
        k = float(slowdown if slowdown is not None else o.slowdown)
        SimOptions(mode=mode, slowdown=k).check()
        started = time.perf_counter()
        motions = graspath.candidate_motions(self.task, list(candidates), period=o.timestep / k)
        if motions is None:
            return {"candidates": [int(c) for c in candidates], "mode": mode, "slowdown": k, "status": "infeasible"}
        refs = [self._reference(motion, k) for motion in motions]
        steps = max(r[0][0].shape[0] for r in refs)
        closed = max(r[1] for r in refs)
        placed = max(r[2] for r in refs)
        opened = max(r[3] for r in refs)
        close_start = closed - int(round(o.close_time / o.timestep))
        # Every arm's reference padded to the longest: an arm that is done holds still where
        # it ended (its last position, no velocity, no acceleration).
        padded = []
        for (q, qd, qdd), *_rest in refs:
            extra = steps - q.shape[0]
            still = np.zeros((extra, q.shape[1]))
            padded.append(
                (
                    np.concatenate([q, np.repeat(q[-1:], extra, axis=0)]),
                    np.concatenate([qd, still]),
                    np.concatenate([qdd, still]),
                )
            )

        mujoco.mj_resetData(model, data)
        for arm, ref in zip(self.arms, padded):
            data.qpos[arm["qpos"]] = ref[0][0]
        # Without a table nothing supports the object: it is held where it starts until the
        # gripper has closed on it.
        supported = self.world["has_table"]
        object_q = slice(self.object_qpos, self.object_qpos + 7)
        object_v = slice(self.object_dof, self.object_dof + 6)
        object_start = data.qpos[object_q].copy()
        for arm in self.arms:
            data.eq_active[arm["weld"]] = 0
        mujoco.mj_forward(model, data)

        qpos, qvel, ctrl = data.qpos, data.qvel, data.ctrl
        bias, gravcomp = data.qfrc_bias, data.qfrc_gravcomp
        weight = self.object_mass * model.opt.gravity / len(self.arms)
        vec = np.zeros(model.nv)
        res = np.zeros(model.nv)
        jacp = np.zeros((3, model.nv))
        kp, kd = o.kp, o.kd
        n_arms = len(self.arms)
        q_history = [np.empty((steps, len(a["dof"]))) for a in self.arms]
        tau_history = [np.empty((steps, len(a["dof"]))) for a in self.arms]
        tool_body = self.arms[0]["tool"]
        object_body = self.object_body
        in_hand_p = np.full((steps, 3), np.nan)
        in_hand_r = np.full((steps, 3, 3), np.nan)
        xpos, xmat = data.xpos, data.xmat
        contacts: Dict[str, int] = {}
        first_contact: Optional[float] = None
        geom_class = self.geom_class
        delivery = None
        carrying = False
        for i in range(steps):
            if i < closed and not supported:
                qpos[object_q] = object_start
                qvel[object_v] = 0.0
            if i == closed:
                if mode == "weld":
                    for arm in self.arms:
                        tp, tr = _pose(data, arm["tool"])
                        op, orot = _pose(data, object_body)
                        rel = np.eye(4)
                        rel[:3, :3] = tr.T @ orot
                        rel[:3, 3] = tr.T @ (op - tp)
                        self._set_weld(arm["weld"], rel)
                        data.eq_active[arm["weld"]] = 1
                carrying = True
            elif i == placed:
                delivery = self._object_error()
                carrying = False
            elif i == opened and mode == "weld":
                for arm in self.arms:
                    data.eq_active[arm["weld"]] = 0
            finger_target = close_start <= i < placed
            # The arms' feedback accelerations, then one product with M (the arms' blocks do
            # not couple: each hangs from the world on its own).
            for a in range(n_arms):
                arm = self.arms[a]
                qr, qdr, qddr = padded[a]
                ds = arm["dslice"]
                q = qpos[arm["qslice"]]
                q_history[a][i] = q
                vec[ds] = qddr[i] + kp * (qr[i] - q) + kd * (qdr[i] - qvel[ds])
            mujoco.mj_mulM(model, data, res, vec)
            for a in range(n_arms):
                arm = self.arms[a]
                ds = arm["dslice"]
                tau = res[ds] + bias[ds] - gravcomp[ds]
                if carrying:
                    # The carried object's weight, shared by the arms, through each tool.
                    mujoco.mj_jac(model, data, jacp, None, data.xipos[object_body], arm["tool"])
                    tau -= jacp[:, ds].T @ weight
                tau_history[a][i] = tau
                np.minimum(tau, arm["effort"], out=tau)
                np.maximum(tau, arm["lower_effort"], out=tau)
                ctrl[arm["mslice"]] = tau
                ctrl[arm["fslice"]] = arm["names"]["finger_travel"] if finger_target else 0.0
            mujoco.mj_step(model, data)
            if carrying:
                rotation = xmat[tool_body].reshape(3, 3)
                in_hand_p[i] = rotation.T @ (xpos[object_body] - xpos[tool_body])
                in_hand_r[i] = rotation.T @ xmat[object_body].reshape(3, 3)
            if data.ncon:
                geoms = data.contact.geom[: data.ncon]
                unintended = UNINTENDED[geom_class[geoms[:, 0]], geom_class[geoms[:, 1]]]
                if unintended.any():
                    for g1, g2 in geoms[unintended]:
                        key = " / ".join(sorted((self._body_name(g1), self._body_name(g2))))
                        contacts[key] = contacts.get(key, 0) + 1
                    if first_contact is None:
                        first_contact = i * o.timestep
        # MuJoCo resets a simulation whose accelerations blow up (e.g. a load far beyond the
        # motors): such a run is reported as unstable, never as a success.
        unstable = bool(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0)
        final = self._object_error()
        if delivery is None:
            delivery = final
        # In-hand slip: the object's pose in the (first) tool frame against the carry's first.
        held = np.flatnonzero(~np.isnan(in_hand_p[:, 0]))
        slip_distance = slip_angle = 0.0
        if held.size:
            p0, r0 = in_hand_p[held[0]], in_hand_r[held[0]]
            slip_distance = float(np.max(np.linalg.norm(in_hand_p[held] - p0, axis=1)))
            relative = np.einsum("ji,njk->nik", r0, in_hand_r[held])
            cosine = (np.trace(relative, axis1=1, axis2=2) - 1.0) / 2.0
            slip_angle = float(np.max(np.arccos(np.clip(cosine, -1.0, 1.0))))
        tracking_max, tracking_rms = [], []
        saturated = np.zeros(steps, dtype=bool)
        peak_effort_ratio = 0.0
        for a, arm in enumerate(self.arms):
            error = np.abs(padded[a][0] - q_history[a])
            tracking_max.append(float(error.max()))
            tracking_rms.append(float(np.sqrt(np.mean(error**2, axis=0)).max()))
            limit = arm["effort"]
            finite = np.isfinite(limit)
            if finite.any():
                ratio = np.abs(tau_history[a][:, finite]) / limit[finite]
                saturated |= (ratio > 1.0).any(axis=1)
                peak_effort_ratio = max(peak_effort_ratio, float(ratio.max()))
        dropped = slip_distance > DROP_DISTANCE
        judged = final if supported else delivery
        success = (
            not dropped
            and not unstable
            and judged["position"] <= POSITION_TOLERANCE
            and judged["angle"] <= ANGLE_TOLERANCE
            and not contacts
        )
        self.last_wall_time = time.perf_counter() - started
        return {
            "candidates": [int(c) for c in candidates],
            "mode": mode,
            "slowdown": k,
            "status": "simulated",
            "success": bool(success),
            "duration": steps * o.timestep,
            "delivery_position_error": delivery["position"],
            "delivery_angle_error": delivery["angle"],
            "final_position_error": final["position"],
            "final_angle_error": final["angle"],
            "judged_at": "final" if supported else "delivery",
            "position_error": judged["position"],
            "angle_error": judged["angle"],
            "slip_distance": slip_distance,
            "slip_angle": slip_angle,
            "dropped": bool(dropped),
            "unstable": unstable,
            "tracking_error_max": tracking_max,
            "tracking_error_rms": tracking_rms,
            "saturated_fraction": float(saturated.mean()),
            "peak_effort_ratio": peak_effort_ratio,
            "unintended_contacts": dict(sorted(contacts.items())),
            "first_contact_time": first_contact,
        }

    def _set_weld(self, eq: int, body2_in_body1: np.ndarray) -> None:
        """Sets weld ``eq``'s relative pose: body2's pose in body1's frame."""
        quat = np.zeros(4)
        self.mujoco.mju_mat2Quat(quat, body2_in_body1[:3, :3].reshape(9).copy())
        self.model.eq_data[eq, 0:3] = 0.0
        self.model.eq_data[eq, 3:6] = body2_in_body1[:3, 3]
        self.model.eq_data[eq, 6:10] = quat
        self.model.eq_data[eq, 10] = 1.0

    def _body_name(self, geom: int) -> str:
        return self.model.body(self.model.geom_bodyid[geom]).name or "world"

    def _object_error(self) -> Dict[str, float]:
        p, r = _pose(self.data, self.object_body)
        return {
            "position": float(np.linalg.norm(p - self.goal[:3, 3])),
            "angle": _rotation_angle(self.goal[:3, :3].T @ r),
        }


def simulate(
    task: "graspath.Task", candidates: Sequence[int], options: SimOptions = SimOptions()
) -> Dict[str, Any]:
    """Executes the candidates at positions ``candidates`` of ``task`` (one per arm) once
    with ``options`` and returns the run's measurements (:meth:`World.run`)."""
    return World(task, options).run(candidates)


def _choices(task, selection, k: int, n_random: int, seed: int) -> List[Dict[str, Any]]:
    """The grasps an experiment runs: the top ``k`` by the task's index, the classical
    index's choice, the likelihood's choice and ``n_random`` random feasible ones (for two
    arms: among the pairs the selection lists)."""
    rng = np.random.default_rng(seed)
    arms = selection.arms
    out: List[Dict[str, Any]] = []
    if len(arms) == 1:
        a = selection.arrays(arms[0])
        feasible = np.flatnonzero(a["feasible"])
        if feasible.size == 0:
            return []
        rank = a["rank"]

        def entry(group: str, i: int, order: int) -> Dict[str, Any]:
            return {
                "group": group,
                "order": order,
                "candidates": [int(i)],
                "ids": [int(a["id"][i])],
                "labels": [str(a["label"][i])],
                "rank": None if math.isnan(rank[i]) else int(rank[i]),
                "score": _finite(a["score"][i]),
                "yoshikawa_at_grasp": _finite(a["yoshikawa_at_grasp"][i]),
                "log_likelihood": _finite(a["log_likelihood"][i]),
            }

        ranked = sorted((int(i) for i in feasible if not math.isnan(rank[i])), key=lambda i: rank[i])
        for order, i in enumerate(ranked[:k]):
            out.append(entry("index", i, order + 1))
        yoshikawa = np.where(np.isnan(a["yoshikawa_at_grasp"][feasible]), -np.inf, a["yoshikawa_at_grasp"][feasible])
        out.append(entry("classical", int(feasible[int(np.argmax(yoshikawa))]), 1))
        out.append(entry("likelihood", int(feasible[int(np.argmax(a["log_likelihood"][feasible]))]), 1))
        picks = rng.choice(feasible, size=min(n_random, feasible.size), replace=False)
        for order, i in enumerate(sorted(int(p) for p in picks)):
            out.append(entry("random", i, order + 1))
        return out
    pairs = selection.pairs
    if not pairs:
        return []
    records = {arm: selection.arrays(arm) for arm in arms}
    position = {arm: {int(v): i for i, v in enumerate(records[arm]["id"])} for arm in arms}

    def pair_entry(group: str, p: Dict[str, Any], order: int) -> Dict[str, Any]:
        ids = [int(p[arm]) for arm in arms]
        positions = [position[arm][i] for arm, i in zip(arms, ids)]
        return {
            "group": group,
            "order": order,
            "candidates": positions,
            "ids": ids,
            "labels": [str(records[arm]["label"][i]) for arm, i in zip(arms, positions)],
            "rank": int(p["rank"]),
            "score": _finite(p["score"]),
            "yoshikawa_at_grasp": _finite(
                sum(records[arm]["yoshikawa_at_grasp"][i] for arm, i in zip(arms, positions))
            ),
            "log_likelihood": _finite(
                sum(records[arm]["log_likelihood"][i] for arm, i in zip(arms, positions))
            ),
        }

    for order, p in enumerate(pairs[:k]):
        out.append(pair_entry("index", p, order + 1))
    listed = [pair_entry("listed", p, 0) for p in pairs]
    best_classical = max(range(len(listed)), key=lambda i: listed[i]["yoshikawa_at_grasp"] or -math.inf)
    best_likelihood = max(range(len(listed)), key=lambda i: listed[i]["log_likelihood"] or -math.inf)
    out.append(pair_entry("classical", pairs[best_classical], 1))
    out.append(pair_entry("likelihood", pairs[best_likelihood], 1))
    picks = rng.choice(len(pairs), size=min(n_random, len(pairs)), replace=False)
    for order, i in enumerate(sorted(int(p) for p in picks)):
        out.append(pair_entry("random", pairs[i], order + 1))
    return out


def _finite(value) -> Optional[float]:
    value = float(value)
    return value if math.isfinite(value) else None


def experiment(
    task: "graspath.Task",
    *,
    k: int = 5,
    n_random: int = 10,
    seed: int = 0,
    modes: Sequence[str] = ("friction", "weld"),
    slowdowns: Sequence[float] = (1.0, 2.0),
    options: SimOptions = SimOptions(),
    progress=None,
) -> Dict[str, Any]:
    """The physics experiment for one task: selects (:func:`graspath.select`), then executes
    the top ``k`` grasps by the task's index, the classical index's choice, the likelihood's
    choice and ``n_random`` random feasible grasps (seeded) in every mode and at every
    slowdown. Returns the document ``sim.json`` holds: ``task``, ``options``, ``world``
    (object mass, table, notes), ``choices``, ``runs`` and ``summary`` (per group, mode and
    slowdown: runs, successes, success rate, drops, saturated and colliding runs, the median
    position error the success rule judges). The same inputs give the same document."""
    for mode in modes:
        SimOptions(mode=mode).check()
    for slowdown in slowdowns:
        SimOptions(slowdown=slowdown).check()
    world = World(task, options)
    selection = graspath.select(task)
    choices = _choices(task, selection, k, n_random, seed)
    runs: List[Dict[str, Any]] = []
    cache: Dict[Any, Dict[str, Any]] = {}
    for c, choice in enumerate(choices):
        for mode in modes:
            for slowdown in slowdowns:
                key = (tuple(choice["candidates"]), mode, slowdown)
                if key not in cache:
                    cache[key] = world.run(choice["candidates"], mode=mode, slowdown=slowdown)
                    if progress is not None:
                        progress(choice, cache[key], world.last_wall_time)
                runs.append({"choice": c, **cache[key]})
    summary = []
    groups = []
    for choice in choices:
        if choice["group"] not in groups:
            groups.append(choice["group"])
    for group in groups:
        for mode in modes:
            for slowdown in slowdowns:
                chosen = [
                    r
                    for r in runs
                    if choices[r["choice"]]["group"] == group
                    and r["mode"] == mode
                    and r["slowdown"] == slowdown
                    and r["status"] == "simulated"
                ]
                if not chosen:
                    continue
                successes = sum(r["success"] for r in chosen)
                summary.append(
                    {
                        "group": group,
                        "mode": mode,
                        "slowdown": slowdown,
                        "runs": len(chosen),
                        "successes": successes,
                        "success_rate": successes / len(chosen),
                        "drops": sum(r["dropped"] for r in chosen),
                        "saturated_runs": sum(r["saturated_fraction"] > 0 for r in chosen),
                        "colliding_runs": sum(bool(r["unintended_contacts"]) for r in chosen),
                        "median_position_error": float(
                            np.median([r["position_error"] for r in chosen])
                        ),
                        "median_slip_distance": float(np.median([r["slip_distance"] for r in chosen])),
                    }
                )
    return {
        "task": task.name,
        "options": asdict(options),
        "modes": list(modes),
        "slowdowns": [float(s) for s in slowdowns],
        "seed": seed,
        "success_rule": {
            "position_tolerance": POSITION_TOLERANCE,
            "angle_tolerance": ANGLE_TOLERANCE,
            "drop_distance": DROP_DISTANCE,
        },
        "world": {
            "object_mass": world.object_mass,
            "has_table": world.world["has_table"],
            "notes": world.world["notes"],
        },
        "choices": choices,
        "runs": runs,
        "summary": summary,
    }


def summary_table(document: Dict[str, Any]) -> str:
    """The summary of a ``sim.json`` document as an aligned text table."""
    header = ("group", "mode", "slowdown", "success", "drops", "saturated", "colliding", "error (mm)")
    rows = [header]
    for s in document["summary"]:
        rows.append(
            (
                s["group"],
                s["mode"],
                f"{s['slowdown']:g}x",
                f"{s['successes']}/{s['runs']}",
                str(s["drops"]),
                str(s["saturated_runs"]),
                str(s["colliding_runs"]),
                f"{1000 * s['median_position_error']:.1f}",
            )
        )
    widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows)


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m graspath.sim",
        description="Execute a task's grasps in MuJoCo and measure whether they succeed.",
    )
    parser.add_argument("task", help="the task file (YAML or JSON)")
    parser.add_argument("--out", default="sim.json", help="where to write sim.json")
    parser.add_argument("-k", type=int, default=5, help="top grasps by the task's index")
    parser.add_argument("-n", type=int, default=10, help="random feasible grasps")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--modes", default="friction,weld")
    parser.add_argument("--slowdowns", default="1,2", help="factors on the durations")
    parser.add_argument("--friction", type=float, default=SimOptions.friction)
    parser.add_argument("--grip-force", type=float, default=SimOptions.grip_force)
    parser.add_argument("--object-mass", type=float, default=None)
    parser.add_argument("--timestep", type=float, default=SimOptions.timestep)
    parser.add_argument(
        "--arm-gravity-compensation",
        action="store_true",
        help="carry the arm's own weight outside the motors (a gravity-assist spring, as on "
        "Baxter's shoulder)",
    )
    args = parser.parse_args(argv)
    try:
        options = SimOptions(
            friction=args.friction,
            grip_force=args.grip_force,
            object_mass=args.object_mass,
            timestep=args.timestep,
            arm_gravity_compensation=args.arm_gravity_compensation,
        )
        options.check()
        task = graspath.Task.load(args.task)

        def progress(choice, run, wall):
            if run["status"] != "simulated":
                print(f"{choice['group']} {choice['labels']}: {run['status']}", file=sys.stderr)
                return
            print(
                f"{choice['group']:10} {'/'.join(choice['labels']):24} {run['mode']:8} "
                f"{run['slowdown']:g}x  {'ok  ' if run['success'] else 'FAIL'} "
                f"error {1000 * run['position_error']:.1f} mm  slip {1000 * run['slip_distance']:.1f} mm  "
                f"({run['duration'] / wall:.0f}x real time)",
                file=sys.stderr,
            )

        document = experiment(
            task,
            k=args.k,
            n_random=args.n,
            seed=args.seed,
            modes=[m for m in args.modes.split(",") if m],
            slowdowns=[float(s) for s in args.slowdowns.split(",") if s],
            options=options,
            progress=progress,
        )
    except (ValueError, graspath.GraspathError, OSError) as error:
        print(f"graspath.sim: error: {error}", file=sys.stderr)
        return 2
    text = json.dumps(document, indent=2, sort_keys=True) + "\n"
    tmp = args.out + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, args.out)
    print(summary_table(document))
    return 0


if __name__ == "__main__":
    sys.exit(main())
