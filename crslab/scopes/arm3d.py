"""The arm in 3D for the scopes: its link shapes from the MuJoCo model and its bodies' poses.

Shapes are read from the model's visual geoms (capsules, cylinders, spheres, boxes), each in its
body's frame; poses come from MuJoCo's forward kinematics of the logged DH joint angles (the
model's ``qpos``, see :mod:`crslab.plant.model`). Positions are in metres, quaternions are
``x y z w`` (rerun's order; MuJoCo's is ``w x y z``).

>>> arm = ArmModel()
>>> [b.name for b in arm.bodies], [b.name for b in arm.moving]
(['world', 'waist', 'upper_arm', 'forearm'], ['waist', 'upper_arm', 'forearm'])
>>> pos, quat = arm.poses(np.array([[0.0, 0.0, 0.0]]))      # DH zero: stretched level
>>> np.round(pos[0, arm.body_index("forearm")], 3).tolist()  # the elbow, 10 in out, 10 in up
[0.254, 0.0, 0.254]
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

SHAPE_KINDS = ("capsule", "cylinder", "sphere", "box", "ellipsoid")


@dataclass(frozen=True)
class Shape:
    """One geom in its body's frame: ``kind``, centre ``pos`` (m), ``quat_xyzw``, MuJoCo ``size``."""

    name: str
    kind: str
    pos: tuple[float, float, float]
    quat_xyzw: tuple[float, float, float, float]
    size: tuple[float, float, float]
    rgba: tuple[float, float, float, float]


@dataclass
class Body:
    """A body of the model with the shapes attached to it."""

    name: str
    id: int
    shapes: list[Shape] = field(default_factory=list)


def _wxyz_to_xyzw(q: np.ndarray) -> np.ndarray:
    return np.concatenate([q[..., 1:], q[..., :1]], axis=-1)


class ArmModel:
    """The CRS arm's MuJoCo model, read for drawing (a private MjData: nothing is simulated); with
    a world (:class:`crslab.world.World`), its scene: the peg and the fixtures too (a
    fixture is a body that never moves). Geoms drawn invisible (the arm's collision capsules) are
    left out.

    >>> from crslab.world import load_world
    >>> [b.name for b in ArmModel(load_world("contest")).moving][3:]
    ['peg', 'table', 'hole', 'obstacle', 'groove', 'egg', 'scale', 'stands']
    """

    def __init__(self, world: object | None = None) -> None:
        import mujoco

        from crslab.world import FREE_AIR
        from crslab.world.scene import load_scene

        self._mj = mujoco
        self.model = model = load_scene(world or FREE_AIR)  # type: ignore[arg-type]
        self.data = mujoco.MjData(model)
        kinds = {int(getattr(mujoco.mjtGeom, f"mjGEOM_{k.upper()}")): k for k in SHAPE_KINDS}
        self.bodies = [Body(model.body(b).name or "world", b) for b in range(model.nbody)]
        for g in range(model.ngeom):
            kind = kinds.get(int(model.geom_type[g]))
            if kind is None:  # the floor plane and anything without a primitive shape
                continue
            mat = int(model.geom_matid[g])
            rgba = model.mat_rgba[mat] if mat >= 0 else model.geom_rgba[g]
            if rgba[3] == 0:  # drawn invisible: a collision shape
                continue
            self.bodies[int(model.geom_bodyid[g])].shapes.append(Shape(
                model.geom(g).name or f"geom{g}", kind, tuple(model.geom_pos[g].tolist()),
                tuple(_wxyz_to_xyzw(model.geom_quat[g]).tolist()), tuple(model.geom_size[g].tolist()),
                tuple(float(c) for c in rgba)))
        self.bodies = [b for b in self.bodies if b.shapes]
        self.moving = [b for b in self.bodies if b.id > 0]
        """The bodies whose pose changes (all but the world's)."""

    def body_index(self, name: str) -> int:
        """Position of a moving body in :attr:`moving` (and in the pose arrays)."""
        return [b.name for b in self.moving].index(name)

    def poses(self, qpos_dh_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """World poses of the :attr:`moving` bodies for each row of joint angles: ``(n, nb, 3)``,
        ``(n, nb, 4)``. Vectorized over rows for chains of hinge joints (this arm); MuJoCo's
        ``mj_kinematics`` row by row otherwise."""
        q = np.asarray(qpos_dh_rad, dtype=float).reshape(-1, 3)
        if self.model.nq > 3:  # the peg's wrist, where its equality holds it (crslab.world.scene)
            q = np.concatenate([q, -(q[:, 1:2] + q[:, 2:3])], axis=1)
        if self._hinge_chain():
            pos, quat = self._poses_vectorized(q)
        else:
            pos, quat = self._poses_mujoco(q)
        return pos, _wxyz_to_xyzw(quat)

    def _hinge_chain(self) -> bool:
        m = self.model
        hinge = int(self._mj.mjtJoint.mjJNT_HINGE)
        return all(int(m.body_jntnum[b]) == 0 or (int(m.body_jntnum[b]) == 1
                   and int(m.jnt_type[m.body_jntadr[b]]) == hinge) for b in range(1, m.nbody))

    def _poses_mujoco(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        ids = [b.id for b in self.moving]
        pos = np.empty((len(q), len(ids), 3))
        quat = np.empty((len(q), len(ids), 4))
        data, model, kinematics = self.data, self.model, self._mj.mj_kinematics
        for i, row in enumerate(q):
            data.qpos[:] = row
            kinematics(model, data)
            pos[i] = data.xpos[ids]
            quat[i] = data.xquat[ids]
        return pos, quat

    def _poses_vectorized(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The same as mj_kinematics, for every row at once (quaternions ``w x y z``)."""
        m, n = self.model, len(q)
        xpos = np.zeros((m.nbody, n, 3))
        xquat = np.zeros((m.nbody, n, 4))
        xquat[0, :, 0] = 1.0
        for b in range(1, m.nbody):  # parents come before their children
            p = int(m.body_parentid[b])
            frame = _quat_mul(xquat[p], np.broadcast_to(m.body_quat[b], (n, 4)))
            xpos[b] = xpos[p] + quat_rotate(xquat[p], np.broadcast_to(m.body_pos[b], (n, 3)))
            if int(m.body_jntnum[b]) == 1:
                j = int(m.body_jntadr[b])
                half = 0.5 * q[:, int(m.jnt_qposadr[j])]
                turn = np.concatenate([np.cos(half)[:, None], np.sin(half)[:, None] * m.jnt_axis[j]], axis=1)
                anchor = np.broadcast_to(m.jnt_pos[j], (n, 3))
                xpos[b] += quat_rotate(frame, anchor - quat_rotate(turn, anchor))
                frame = _quat_mul(frame, turn)
            xquat[b] = frame / np.linalg.norm(frame, axis=1, keepdims=True)
        ids = [b.id for b in self.moving]
        return xpos[ids].transpose(1, 0, 2), xquat[ids].transpose(1, 0, 2)


def _quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of quaternions ``w x y z``, row by row."""
    aw, ax, ay, az = a[:, 0], a[:, 1], a[:, 2], a[:, 3]
    bw, bx, by, bz = b[:, 0], b[:, 1], b[:, 2], b[:, 3]
    return np.stack([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw], axis=1)


def quat_rotate(quat_wxyz: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rotate each vector by its quaternion (``w x y z``).

    >>> quarter_turn_about_y = np.array([[np.cos(np.pi / 4), 0.0, np.sin(np.pi / 4), 0.0]])
    >>> np.round(quat_rotate(quarter_turn_about_y, np.array([[0, 0, 1.0]])), 6)
    array([[1., 0., 0.]])
    """
    u, w = quat_wxyz[:, 1:], quat_wxyz[:, :1]
    t = 2 * np.cross(u, v)
    return v + w * t + np.cross(u, t)
