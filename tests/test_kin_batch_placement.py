"""The C core's batch IK gives the same bits wherever its arrays lie in memory.

Its loop calls atan2 through glibc's vector math where gcc vectorizes it; the vector atan2 and the
scalar one differ in their last bits. Were the loop to fall back to scalar code when its input and
output lie close together (gcc's run-time overlap check, which ``restrict`` in csrc/kin/crs_arm.c
rules out), the same targets would get other angles by where numpy happened to put the arrays:
a waypoint plan, and the report of how well a run tracked it, would change from call to call.
"""

import numpy as np

from crslab import _bindings, crs

N = 64  # targets; the batches below take the first 1 to 16 of them


def targets() -> np.ndarray:
    """Reachable targets (in): FK of motor angles spread over the envelope."""
    rng = np.random.default_rng(7)
    motor = np.column_stack([rng.uniform(-1.2, 1.2, N), rng.uniform(-0.3, 0.9, N), rng.uniform(-1.4, 0.2, N)])
    return crs.fk(motor)


def ik_in(buffer: np.ndarray, xyz: np.ndarray, gap: int) -> np.ndarray:
    """Motor angles (rad) for the rows of ``xyz`` with the input at the start of ``buffer`` and
    the output ``gap`` doubles after its end."""
    n = len(xyz)
    src = buffer[: 3 * n]
    src[:] = xyz.ravel()
    out = buffer[3 * n + gap: 3 * n + gap + 3 * n]
    status = np.empty(n, dtype=np.int32)
    _bindings.arm_ik_motor(src, True, out, status, n)
    assert (status == crs.IK_OK).all()
    return out.reshape(n, 3).copy()


def test_batch_ik_gives_the_same_bits_with_its_arrays_close_together_or_far_apart():
    # a vector of 8 points strided by 3 spans 192 bytes: a batch of a few points whose output
    # lies within that of its input is where the overlap check would choose the scalar loop
    every = targets()
    for n in range(1, 17):
        xyz = every[:n]
        far = ik_in(np.zeros(3 * n + 10_000 + 3 * n), xyz, 10_000)
        for gap in range(0, 49):
            close = ik_in(np.zeros(6 * n + 48), xyz, gap)
            assert close.tobytes() == far.tobytes(), f"{n} points, the output {gap} doubles after the input"
        # and the answers are the targets' angles: FK of them lands on the targets
        np.testing.assert_allclose(crs.fk(far), xyz, atol=1e-9)


def test_a_waypoint_plan_s_angles_do_not_depend_on_the_call():
    xyz = targets()
    first = crs.ik_with_status(xyz, "up")[0]
    kept = [np.empty(k) for k in range(1, 60, 7)]  # other arrays allocated in between
    again = [crs.ik_with_status(np.array(xyz), "up")[0] for _ in kept]
    assert all(a.tobytes() == first.tobytes() for a in again)


def test_the_batch_loops_call_glibc_s_vector_math_on_x86_64_linux():
    # what makes the batch IK several times numpy's speed (make bench, issue 2): each file that calls
    # atan2 declares it as libmvec has it (csrc/kin/vector_math.h). The core is linked with
    # link-time optimization, which merges every file's declaration: one file without it left the
    # IK loop scalar (0.95x numpy's speed instead of 6.6x) and no result told
    import platform
    import sys
    from pathlib import Path

    import pytest

    from crslab import _core

    if platform.machine() != "x86_64" or not sys.platform.startswith("linux"):
        pytest.skip("glibc's vector math (libmvec) is used on x86-64 Linux only")
    core = Path(_core.__file__).read_bytes()
    for name in (b"_ZGVdN4vv_atan2", b"_ZGVdN4v_sin", b"_ZGVdN4v_cos"):
        assert name in core, f"the C core does not call libmvec's {name.decode()}"
