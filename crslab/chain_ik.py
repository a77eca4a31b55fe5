"""Numerical inverse kinematics of any :class:`~crslab.chain.Chain`, over the C core
(``csrc/kin/chain_ik.h``): damped least squares with a Levenberg-Marquardt damping schedule,
joint limits kept by projection, and seeded random restarts.

The residual of a solution is the Euclidean norm of the error vector (position in the chain's
length unit, then the rotation vector of ``R_target R^T`` in rad, for a full-pose target), so
``tolerance=1e-5`` on the Panda means about 10 micrometres and 10 microradians.

>>> import numpy as np
>>> from crslab.chain import Chain
>>> arm = Chain(a=[1.0, 1.0], alpha_rad=[0, 0], d=[0, 0])
>>> sol = ik(arm, [1.0, 1.0, 0.0])              # a position: matched alone
>>> bool(sol.success), np.round(arm.fk(sol.q)[:3, 3], 5) + 0.0
(True, array([1., 1., 0.]))
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from crslab import _bindings
from crslab.chain import Chain


@dataclass(frozen=True)
class IKResult:
    """What :func:`ik` found, per target (arrays share the targets' leading shape).

    ``q`` holds the solution, or the best configuration found where ``success`` is False.
    """

    q: np.ndarray
    success: np.ndarray
    iterations: np.ndarray
    restarts: np.ndarray
    residual: np.ndarray


def ik(
    chain: Chain,
    target: object,
    q0: object = None,
    *,
    position_only: bool | None = None,
    tolerance: float = 1e-6,
    max_iterations: int = 60,
    max_restarts: int = 50,
    limits: bool = True,
    seed: int = 0,
) -> IKResult:
    """Joint angles (rad) that put the chain's end effector on ``target``.

    ``target`` is ``(..., 4, 4)`` (poses) or ``(..., 3)`` (positions, which implies
    ``position_only``); ``position_only=True`` with poses matches only their translation. ``q0``
    (``(..., joints)`` or one configuration for all) is the first start; without it every start
    is random inside the limits. ``limits=False`` ignores the chain's limits.

    >>> import numpy as np
    >>> from crslab.chain import Chain
    >>> arm = Chain(a=[1.0, 1.0], alpha_rad=[0, 0], d=[0, 0], upper=[np.pi, 0.0])
    >>> sol = ik(arm, arm.fk([0.3, -0.8]))     # upper limit 0 on joint 2: one elbow allowed
    >>> sol.q.round(9) + 0.0, int(sol.restarts) >= 0
    (array([ 0.3, -0.8]), True)
    """
    t = np.ascontiguousarray(target, dtype=np.float64)
    if t.ndim >= 1 and t.shape[-1] == 3 and not (t.ndim >= 2 and t.shape[-2:] == (4, 4)):
        lead = t.shape[:-1]
        poses = np.zeros(lead + (4, 4))
        poses[...] = np.eye(4)
        poses[..., :3, 3] = t
        if position_only is False:
            raise ValueError("a position target (..., 3) cannot be matched as a full pose")
        position_only = True
    elif t.ndim >= 2 and t.shape[-2:] == (4, 4):
        lead = t.shape[:-2]
        poses = t
    else:
        raise ValueError(f"target must have shape (..., 4, 4) or (..., 3), got {t.shape}")
    if not tolerance > 0:
        raise ValueError(f"tolerance must be positive, got {tolerance}")
    if max_iterations < 1 or max_restarts < 0:
        raise ValueError("max_iterations must be >= 1 and max_restarts >= 0")
    nj = chain.n_joints
    n = int(np.prod(lead, dtype=np.int64))
    start = None
    if q0 is not None:
        start = np.ascontiguousarray(np.broadcast_to(np.asarray(q0, dtype=np.float64), lead + (nj,)))
    options = {"max_iterations": int(max_iterations), "max_restarts": int(max_restarts),
               "tolerance": float(tolerance), "position_only": 1 if position_only else 0,
               "seed": int(seed) & 0xFFFFFFFFFFFFFFFF}
    q = np.empty(lead + (nj,))
    success = np.empty(lead, dtype=np.int32)
    iterations = np.empty(lead, dtype=np.int32)
    restarts = np.empty(lead, dtype=np.int32)
    residual = np.empty(lead)
    lower, upper = (chain.lower, chain.upper) if limits else (None, None)
    poses = np.ascontiguousarray(poses, dtype=np.float64)
    _bindings.chain_ik(chain.c_chain, lower, upper, options, poses, start, q, success, iterations, restarts,
                       residual, n)
    return IKResult(q, success.astype(bool), iterations, restarts, residual)
