"""Serial chains from a Denavit-Hartenberg table, over the C core (``csrc/kin/chain.h``).

A :class:`Chain` holds one DH table (standard or modified convention), its joint limits and
optional base and tool poses. Its methods take joint angles of shape ``(..., joints)`` in
radians and return numpy arrays with the same leading shape; the C core loops over the rows.
Lengths keep the table's unit (m for the Panda, in for the CRS arm).

>>> import numpy as np
>>> two_link = Chain(a=[1.0, 0.5], alpha_rad=[0, 0], d=[0, 0])
>>> two_link.fk([np.pi / 2, 0.0])[:3, 3].round(12) + 0.0
array([0. , 1.5, 0. ])
>>> two_link.jacobian([0.0, 0.0])[:, 0]       # joint 1 at the stretched pose: vy and wz
array([0. , 1.5, 0. , 0. , 0. , 1. ])
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from crslab import _bindings
from crslab._bindings import constants
from crslab.arrays import as_rows

STANDARD = "standard"
MODIFIED = "modified"
CONVENTIONS = {STANDARD: constants.CHAIN_STANDARD, MODIFIED: constants.CHAIN_MODIFIED}
REVOLUTE = "revolute"
FIXED = "fixed"
JOINT_TYPES = {REVOLUTE: constants.CHAIN_REVOLUTE, FIXED: constants.CHAIN_FIXED}
MAX_ROWS: int = constants.CHAIN_MAX_ROWS

_STATUS_TEXT = {
    constants.CHAIN_BAD_ROW_COUNT: f"a DH table needs 1 to {constants.CHAIN_MAX_ROWS} rows",
    constants.CHAIN_BAD_CONVENTION: "unknown DH convention",
    constants.CHAIN_BAD_JOINT_TYPE: "unknown joint type",
    constants.CHAIN_NOT_FINITE: "a DH entry, the base or the tool is not a finite number",
    constants.CHAIN_NULL_TABLE: "a DH column is missing",
}


def _pose(value: object, name: str) -> np.ndarray | None:
    if value is None:
        return None
    arr = np.ascontiguousarray(value, dtype=np.float64)
    if arr.shape != (4, 4):
        raise ValueError(f"{name} must be a 4x4 pose, got shape {arr.shape}")
    return arr


class Chain:
    """One DH table with its limits and its base and tool poses.

    ``a``, ``d`` are in the chain's length unit, ``alpha_rad`` and ``theta_rad`` (the constant
    added to each joint variable; the whole angle of a fixed row) in radians. ``joint_types``
    holds ``"revolute"`` or ``"fixed"`` per row (default: all revolute); only revolute rows take
    a joint variable. ``lower``/``upper`` are per-joint limits in radians (default: none).
    ``base`` is the pose of DH frame 0 in the world, ``tool`` the end effector in the last frame.
    """

    def __init__(
        self,
        a: Sequence[float],
        alpha_rad: Sequence[float],
        d: Sequence[float],
        theta_rad: Sequence[float] | None = None,
        joint_types: Sequence[str] | None = None,
        convention: str = STANDARD,
        base: object = None,
        tool: object = None,
        lower: Sequence[float] | None = None,
        upper: Sequence[float] | None = None,
    ) -> None:
        self.a = np.ascontiguousarray(a, dtype=np.float64)
        n = self.a.size
        self.alpha_rad = np.ascontiguousarray(alpha_rad, dtype=np.float64)
        self.d = np.ascontiguousarray(d, dtype=np.float64)
        theta = np.zeros(n) if theta_rad is None else theta_rad
        self.theta_rad = np.ascontiguousarray(theta, dtype=np.float64)
        types = [REVOLUTE] * n if joint_types is None else list(joint_types)
        for name, col in (("alpha_rad", self.alpha_rad), ("d", self.d), ("theta_rad", self.theta_rad),
                          ("joint_types", types)):
            if len(col) != n or self.a.ndim != 1:
                raise ValueError(f"DH columns must be 1-D and equally long: a has {n} rows, "
                                 f"{name} {len(col)}")
        bad = [t for t in types if t not in JOINT_TYPES]
        if bad:
            raise ValueError(f"joint type {bad[0]!r} is not one of {', '.join(JOINT_TYPES)}")
        if convention not in CONVENTIONS:
            raise ValueError(f"convention {convention!r} is not one of {', '.join(CONVENTIONS)}")
        self.convention = convention
        self.joint_types = tuple(types)
        self._types = np.ascontiguousarray([JOINT_TYPES[t] for t in types], dtype=np.int32)
        self.base = _pose(base, "base")
        self.tool = _pose(tool, "tool")
        self.n_rows = n
        self.n_joints = sum(t == REVOLUTE for t in types)
        self.lower = self._limit(lower, -np.inf, "lower")
        self.upper = self._limit(upper, np.inf, "upper")
        if np.any(self.lower > self.upper):
            j = int(np.flatnonzero(self.lower > self.upper)[0])
            raise ValueError(f"joint {j + 1}: lower limit {self.lower[j]:g} is above upper {self.upper[j]:g}")
        self._c, status = _bindings.chain_new(CONVENTIONS[convention], self.a, self.alpha_rad, self.d,
                                              self.theta_rad, self._types, self.base, self.tool)
        if status != constants.CHAIN_OK:
            raise ValueError(_STATUS_TEXT[status])

    def _limit(self, values: Sequence[float] | None, default: float, name: str) -> np.ndarray:
        if values is None:
            return np.full(self.n_joints, default)
        arr = np.ascontiguousarray(values, dtype=np.float64)
        if arr.shape != (self.n_joints,):
            raise ValueError(f"{name} limits need one value per joint ({self.n_joints}), "
                             f"got shape {arr.shape}")
        return arr

    @property
    def c_chain(self) -> object:
        """The chain as the C core holds it (crslab/_bindings.py; valid while this object lives)."""
        return self._c

    def with_tool(self, tool: object) -> Chain:
        """The same chain with another tool pose (``None`` for the bare last DH frame)."""
        return Chain(self.a, self.alpha_rad, self.d, self.theta_rad, self.joint_types, self.convention,
                     self.base, tool, self.lower, self.upper)

    def within_limits(self, q_rad: object, slack: float = 0.0) -> np.ndarray:
        """True per configuration when every joint is inside its limits (widened by ``slack``)."""
        q = as_rows(q_rad, self.n_joints, "q_rad")
        return np.all((q >= self.lower - slack) & (q <= self.upper + slack), axis=-1)

    def _q(self, q_rad: object) -> np.ndarray:
        return as_rows(q_rad, self.n_joints, "q_rad")

    def fk(self, q_rad: object) -> np.ndarray:
        """End-effector pose (tool applied), shape ``(..., 4, 4)``."""
        q = self._q(q_rad)
        out = np.empty(q.shape[:-1] + (4, 4))
        _bindings.chain_fk(self._c, q, out, q.size // max(self.n_joints, 1))
        return out

    def frames(self, q_rad: object) -> np.ndarray:
        """World poses of DH frames 0 (base) to n, then the end effector: ``(..., n + 2, 4, 4)``."""
        q = self._q(q_rad)
        out = np.empty(q.shape[:-1] + (self.n_rows + 2, 4, 4))
        _bindings.chain_frames(self._c, q, out, q.size // max(self.n_joints, 1))
        return out

    def points(self, q_rad: object, local_point: object) -> np.ndarray:
        """Points fixed in the frames, ``(..., n, 3)``: point i is ``local_point[i]`` in frame i + 1.

        Seed 002 places the Panda's joint centres this way (its Table 2).
        """
        q = self._q(q_rad)
        local = np.ascontiguousarray(local_point, dtype=np.float64)
        if local.shape != (self.n_rows, 3):
            raise ValueError(f"local_point must have shape ({self.n_rows}, 3), got {local.shape}")
        out = np.empty(q.shape[:-1] + (self.n_rows, 3))
        _bindings.chain_points(self._c, q, local, out, q.size // max(self.n_joints, 1))
        return out

    def jacobian(self, q_rad: object) -> np.ndarray:
        """Geometric Jacobian of the end effector in world axes, ``(..., 6, joints)``.

        Rows 0-2 give the linear velocity (length unit per rad), rows 3-5 the angular velocity.
        """
        q = self._q(q_rad)
        out = np.empty(q.shape[:-1] + (6, self.n_joints))
        _bindings.chain_jacobian(self._c, q, out, q.size // max(self.n_joints, 1))
        return out
