"""Where the real arm's joints held still and where they slid slowly in the real recording, and
the torque on each then: the evidence for what a real joint does inside its static-friction band
(models/crs_arm/README.md, "Friction at rest").

The recording (``real_recording.REAL_RECORDING``) holds the motor angles a real arm reached under a
known lab (``csrc/labs/lab2_square_pid.c``; the recording's README says what it does). The lab's
command at every sample follows from those angles alone: its PID, the integral windows and all,
recomputed here from the README (a second implementation of the C lab, at the recording's 5 ms).
Gravity's push on each motor comes from the course's p vector [framework.md §11]. So after each
step, whenever a joint's reading did not change for 50 ms (it held still, under 2e-3 rad/s to the
recording's 1e-4 rad) the torque friction balanced is known: the static friction that way is at
least that; and whenever it slid slowly (0.004-0.06 rad/s), about what friction takes there.

The reconstruction is good to about 0.1 N.m: the angles are quantized to 1e-4 rad (the integral of
the error by 0.05 N.m over a hold), speeds come from 5 ms samples, the real arm's gravity is the
course's model's to a few percent, and a slide that is slowing down has the arm's inertia in it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from real_recording import REAL_RECORDING

from crslab.identify.recording import read_recording

NM_PER_UNIT = 6.0                       # [framework.md §11]
KP, KD = 30.0, 1.75                     # the lab's gains, every joint (units/rad, units s/rad)
KI = (200.0, 300.0, 300.0)              # units/(rad s), joints 1..3
WINDOW_RAD = (0.017, 0.013, 0.013)      # an |error| above this resets the joint's integral
P4, P5, GRAV = 0.0753, 0.0298, 9.81     # the course's gravity parameters (units), m/s^2
REFERENCE_COLUMN = 3                    # PlotVar4: the square wave every joint follows
SETTLE_S = 0.25                         # after each toggle: the step itself, not looked at
HOLD_SAMPLES = 10                       # a hold: this many samples (50 ms) with one reading
SLIDE_RAD_S = (0.004, 0.06)             # a slow slide: speeds in this range, rad/s ...
SLIDE_ACCEL = 1.0                       # ... changing by less than this, rad/s^2
RESOLUTION_NM = 0.1                     # what the reconstruction's torques are good to (above)


@dataclass(frozen=True)
class Stretch:
    """One joint, after one step: held still, or sliding slowly."""

    joint: int            # 1..3
    t_s: float            # where it begins, the recording's time
    pose_rad: float       # the motor angle
    held: bool
    torque_nm: float      # the torque friction balanced (the lab's and gravity's, N.m, signed:
                          # positive pushes the motor angle up); held: the largest in size; slid:
                          # the median
    speed_rad_s: float    # slid: the median speed, signed; held: 0


@dataclass(frozen=True)
class Level:
    """What the recording says about one joint's static friction one way, at one pose."""

    joint: int
    direction: int        # +1: pushed positive (a bound on Spos), -1: pushed negative (on Sneg)
    pose_rad: float       # to 0.1 rad
    held_nm: float        # the largest torque it held still against (a size, N.m)
    holds: int
    slid_nm: float        # the median torque it slid slowly under (a size, N.m; nan: never)
    slides: int


def net_torque_nm(angle_rad: np.ndarray, reference_rad: float, joint: int, dt_s: float) -> np.ndarray:
    """The lab's command plus gravity's push (N.m about the motor angle) at every sample of one step
    of ``joint`` (1..3), from its recorded angles (rad) and the step's reference (rad).

    >>> a = np.full(20, 0.5)          # held at 0.5 rad, reference 0.51: inside joint 1's window
    >>> t = net_torque_nm(a, 0.51, 1, 0.005)
    >>> round(float(t[0]), 3)         # 6 N.m/unit x 30 e; no gravity on joint 1
    1.8
    >>> round(float(t[-1]), 3)        # + 6 x 200 x (0.01 rad x 19 x 5 ms) of integral
    2.94
    """
    k = joint - 1
    error = reference_rad - angle_rad
    integral, acc = np.zeros_like(error), 0.0
    for i in range(1, len(error)):
        acc = 0.0 if abs(error[i]) > WINDOW_RAD[k] else acc + (error[i] + error[i - 1]) / 2 * dt_s
        integral[i] = acc
    speed = np.gradient(angle_rad, dt_s) if len(angle_rad) > 1 else np.zeros_like(angle_rad)
    units = KP * error - KD * speed + KI[k] * integral
    gravity = (0.0 * angle_rad, P4 * GRAV * np.sin(angle_rad), P5 * GRAV * np.cos(angle_rad))[k]
    return (units + gravity) * NM_PER_UNIT


def stretches() -> list[Stretch]:
    """Every hold and slow slide of every joint after every step of the recording."""
    rec = read_recording(REAL_RECORDING)
    t, dt = rec.t_s, rec.period_s
    reference = rec.plotvars[:, REFERENCE_COLUMN]
    toggles = np.flatnonzero(np.diff(reference)) + 1
    found: list[Stretch] = []
    for a, b in zip(toggles[:-1], toggles[1:]):
        start = a + int(round(SETTLE_S / dt))
        for joint in (1, 2, 3):
            angle = rec.motor_rad[a:b, joint - 1]
            net = net_torque_nm(angle, float(reference[a]), joint, dt)[start - a:]
            angle = angle[start - a:]
            speed = np.gradient(angle, dt)
            found += _holds(joint, t[start:b], angle, net)
            found += _slides(joint, t[start:b], angle, net, speed, np.gradient(speed, dt))
    return found


def levels(found: list[Stretch] | None = None) -> list[Level]:
    """Per joint, direction and pose (0.1 rad): the largest torque held, the median slid under."""
    found = stretches() if found is None else found

    def key(s: Stretch) -> tuple[int, int, float]:
        return s.joint, int(np.sign(s.torque_nm)), round(s.pose_rad, 1) + 0.0

    out = []
    for joint, direction, pose in sorted({key(s) for s in found if s.torque_nm}):
        mine = [s for s in found if key(s) == (joint, direction, pose)]
        held = [abs(s.torque_nm) for s in mine if s.held]
        slid = [abs(s.torque_nm) for s in mine if not s.held]
        if held:
            out.append(Level(joint, direction, pose, max(held), len(held),
                             float(np.median(slid)) if slid else float("nan"), len(slid)))
    return out


def _runs(mask: np.ndarray, least: int) -> list[tuple[int, int]]:
    """[start, end) of every run of True at least ``least`` long."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(int), [0]))))
    return [(int(s), int(e)) for s, e in zip(edges[::2], edges[1::2]) if e - s >= least]


def _holds(joint: int, t: np.ndarray, angle: np.ndarray, net: np.ndarray) -> list[Stretch]:
    unchanged = np.concatenate((np.diff(angle) == 0, [False]))  # sample i equals sample i + 1
    out = []
    for s, e in _runs(unchanged, HOLD_SAMPLES):
        i = s + int(np.argmax(np.abs(net[s:e + 1])))
        out.append(Stretch(joint, float(t[s]), float(angle[s]), True, float(net[i]), 0.0))
    return out


def _slides(joint: int, t: np.ndarray, angle: np.ndarray, net: np.ndarray, speed: np.ndarray,
            accel: np.ndarray) -> list[Stretch]:
    size = np.abs(speed)
    slow = (size >= SLIDE_RAD_S[0]) & (size <= SLIDE_RAD_S[1]) & (np.abs(accel) < SLIDE_ACCEL)
    slow &= np.sign(net) == np.sign(speed)  # pushed the way it slides: friction balances the push
    return [Stretch(joint, float(t[s]), float(np.median(angle[s:e])), False, float(np.median(net[s:e])),
                    float(np.median(speed[s:e]))) for s, e in _runs(slow, 4)]
