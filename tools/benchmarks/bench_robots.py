"""Issue 7: Panda kinematics, crslab's C core vs roboticstoolbox-python (the `bench` extra).

1. Batch FK of 100,000 random in-limit configurations: crslab's ``Chain.fk`` vs RTB's
   ``Panda().fkine`` on the same array (both to the flange; the poses are compared first).
   Target: at least 5x RTB's rate.
   Best of ``REPEATS`` calls on each side.
2. Numerical IK of 10,000 reachable flange poses (FK of random in-limit configurations), full
   pose, tolerance 1e-5, limits enforced: crslab's ``chain_ik.ik`` vs RTB's ``ik_LM``, each
   called once per pose from Python and timed per call. RTB's ``tol`` bounds E = |e|^2 / 2, so
   it gets 5e-11 (|e| <= 1e-5). Both are warmed up alike (untimed calls on the first
   ``N_WARM`` poses: first-call costs such as lazy set-up stay out), then each solves every pose
   ``REPEATS`` times, the passes interleaved; each side's pass with the lower mean time is
   reported. Every returned solution of both is re-checked here the same way: residual |e| from
   crslab's FK <= 1e-5 and every joint inside its limits.
   Target: success at least RTB's, mean time per solve no worse.
   crslab's batch call (all poses in one call; RTB has none) is printed for information.
"""

from __future__ import annotations

import time

import numpy as np

from crslab import robots
from crslab.chain_ik import ik
from crslab.workspace import random_configurations

N_FK = 100_000
N_IK = 10_000
N_WARM = 500
REPEATS = 2  # best-of count of every timing, the same on both sides
TOL = 1e-5
FLANGE = "panda_link8"  # RTB's Panda otherwise ends at its gripper's fingertip frame


def residual(chain, q, target):
    """|e| = sqrt(|dp|^2 + angle(R_target R^T)^2), computed with numpy from FK."""
    pose = chain.fk(q)
    dp = target[..., :3, 3] - pose[..., :3, 3]
    rel = target[..., :3, :3] @ np.swapaxes(pose[..., :3, :3], -1, -2)
    skew = np.stack([rel[..., 2, 1] - rel[..., 1, 2], rel[..., 0, 2] - rel[..., 2, 0],
                     rel[..., 1, 0] - rel[..., 0, 1]], -1)
    angle = np.arctan2(np.linalg.norm(skew, axis=-1) / 2, (np.trace(rel, axis1=-2, axis2=-1) - 1) / 2)
    return np.sqrt(np.sum(dp**2, -1) + angle**2)


def verified(chain, q, target, claimed):
    ok = claimed & (residual(chain, q, target) <= TOL * (1 + 1e-9)) & chain.within_limits(q, slack=1e-12)
    return ok


def best_of(fn, repeats=REPEATS):
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def per_call(solve, targets):
    times = np.empty(len(targets))
    results = []
    for i, t in enumerate(targets):
        start = time.perf_counter()
        results.append(solve(t))
        times[i] = time.perf_counter() - start
    return times, results


def run():
    panda = robots.load("panda_mdh")
    flange = panda.chain.with_tool(None)  # the flange, where both solvers are compared
    q_fk = random_configurations(panda, N_FK, seed=0)
    q_ik = random_configurations(panda, N_IK, seed=1)
    targets = flange.fk(q_ik)
    lines = []
    try:
        import roboticstoolbox as rtb

        rtb_panda = rtb.models.Panda()
        rtb_error = None
    except Exception as exc:  # noqa: BLE001 - any import failure is reported, not raised
        rtb_panda, rtb_error = None, f"{type(exc).__name__}: {exc}"

    # --- FK ---------------------------------------------------------------------------------
    t_c, poses = best_of(lambda: flange.fk(q_fk))
    if rtb_panda is not None:
        np.testing.assert_allclose(np.asarray(rtb_panda.qlim), [flange.lower, flange.upper], atol=1e-4)
        t_r, rtb_poses = best_of(lambda: rtb_panda.fkine(q_fk, end=FLANGE))
        diff = np.max(np.abs(rtb_poses.A - poses))
        assert diff < 1e-9, f"crslab and RTB disagree on the Panda flange by {diff:g}"
        lines.append(f"FK  {N_FK} configs in one call, best of {REPEATS}: crslab "
                     f"{N_FK / t_c / 1e6:5.2f} M/s, RTB fkine {N_FK / t_r / 1e6:5.2f} M/s, "
                     f"ratio {t_r / t_c:5.1f}x (target >= 5x, issue 7); poses agree to {diff:.1e}")
    else:
        lines.append(f"roboticstoolbox-python unavailable here ({rtb_error}); crslab's numbers only")
        lines.append(f"FK  {N_FK} configs in one call, best of {REPEATS}: crslab {N_FK / t_c / 1e6:5.2f} M/s")

    # --- IK ---------------------------------------------------------------------------------
    solvers = {"crslab": lambda t: ik(flange, t, tolerance=TOL, seed=7)}
    if rtb_panda is not None:
        solvers["RTB"] = lambda t: rtb_panda.ik_LM(t, end=FLANGE, tol=TOL**2 / 2, joint_limits=True)
    for solve in solvers.values():  # the same warm-up for both
        per_call(solve, targets[:N_WARM])
    passes = {name: [] for name in solvers}
    for _ in range(REPEATS):  # interleaved: both see the same machine load
        for name, solve in solvers.items():
            passes[name].append(per_call(solve, targets))
    best = {name: min(runs, key=lambda run: run[0].mean()) for name, runs in passes.items()}
    times_c, sols = best["crslab"]
    t_batch, batch = best_of(lambda: ik(flange, targets, tolerance=TOL, seed=7))
    q_c = np.array([s.q for s in sols])
    ok_c = verified(flange, q_c, targets, np.array([bool(s.success) for s in sols]))
    how = f"one call per pose after {N_WARM} warm-up calls, faster of {REPEATS} passes"
    lines.append(f"IK  {N_IK} poses, crslab ({how}): success {100 * ok_c.mean():.2f} %, per call mean "
                 f"{1e6 * times_c.mean():.1f} us, median {1e6 * np.median(times_c):.1f} us; "
                 f"iterations mean {np.mean([s.iterations for s in sols]):.1f}, "
                 f"restarts mean {np.mean([s.restarts for s in sols]):.2f}")
    lines.append(f"IK  {N_IK} poses, crslab batch call (all poses in one call, best of {REPEATS}): "
                 f"{1e6 * t_batch / N_IK:.1f} us/pose, success {100 * batch.success.mean():.2f} %")
    if rtb_panda is not None:
        times_r, rsols = best["RTB"]
        q_r = np.array([s.q for s in rsols])
        claimed = np.array([bool(s.success) for s in rsols])
        ok_r = verified(flange, q_r, targets, claimed)
        lines.append(f"IK  {N_IK} poses, RTB ik_LM ({how}): success {100 * ok_r.mean():.2f} % "
                     f"(it claims {100 * claimed.mean():.2f} %), per call mean "
                     f"{1e6 * times_r.mean():.1f} us, median {1e6 * np.median(times_r):.1f} us")
        lines.append(f"IK  ratio per call: mean time RTB / crslab {times_r.mean() / times_c.mean():.1f}x, "
                     f"median {np.median(times_r) / np.median(times_c):.1f}x (target >= 1x, issue 7); "
                     f"success crslab - RTB {100 * (ok_c.mean() - ok_r.mean()):+.2f} points (target >= 0)")
    return lines
