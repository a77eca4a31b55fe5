"""How the simulated arm moves against the real one (issue 12), and a full ``crslab identify``.

The real recording's controller (csrc/labs/lab2_square_pid.c) runs in crslab with the arm as it was
before issue 12 (plant_before_issue12.toml: the course's friction table, no drive model) and as it
is now (models/crs_arm/params.toml), each aligned on the recording (start, phase and clock drift
fitted, nothing of the plant). Per joint, real, before and after side by side: RMS and max of
(sim - real), 10-90 % rise time, overshoot, steady-state error and peak speed of the rising and
falling steps, with the issue's targets. Then a full identification (every drive and friction
value) from a start 10-20 % off the shipped values: how long it takes and whether it ends within
the shipped values' stated uncertainty.
"""

from __future__ import annotations

import math
import time

import numpy as np
from real_recording import (
    BEFORE_PLANT,
    REAL_RECORDING,
    TARGET_ERROR_RAD,
    TARGET_PEAK_SPEED_SHARE,
    TARGET_RISE_SHARE,
    TARGET_RMS_RAD,
)

from crslab.identify import metrics
from crslab.identify.fit import Source, compare, fit
from crslab.identify.recording import read_recording
from crslab.identify.runs import lab_offsets
from crslab.plant.params import PARAMS
from crslab.plant.plant_params import PlantParams
from crslab.resources import path as resource_path
from crslab.sim.api import make_config

LAB = resource_path("csrc", "labs", "lab2_square_pid.c")
REFERENCE_COLUMN = 3  # PlotVar4: joint 1's reference, the same square wave as every joint's
# how far from the shipped values the full fit starts (a factor per value)
PERTURBATION = {"stall_nm": 1.15, "backemf": 0.85, "drive_lag_s": 2.0, "coulomb_pos": 1.2,
                "coulomb_neg": 0.8, "viscous": None}
UNCERTAINTY_KEYS = {"stall_nm": "stall_nm", "backemf": "backemf_nm_s_per_rad", "drive_lag_s": "lag_s",
              "coulomb_pos": "Cpos_nm", "coulomb_neg": "Cneg_nm", "viscous": "V_nm_s_per_rad"}


def source() -> Source:
    rec = read_recording(REAL_RECORDING)
    config = make_config(LAB, "hands_off", startup_delay=False)
    return Source(rec, config, lab_offsets(config))


def joint_rows(src: Source, sims: dict[str, np.ndarray], rms: dict[str, np.ndarray],
               mx: dict[str, np.ndarray]) -> list[str]:
    rec = src.recording
    ref = rec.plotvars[:, REFERENCE_COLUMN]
    lines = []
    for k, joint in enumerate(rec.joints):
        found = {"real": metrics.steps(rec.t_s, rec.motor_rad[:, k], ref)}
        for name, sim in sims.items():
            found[name] = metrics.steps(rec.t_s, sim[:, k], ref)
        lines.append(f"joint {joint}                        real     before      after   target (after)")
        ok = _ok(rms["after"][k] <= TARGET_RMS_RAD)
        lines.append(f"  RMS sim - real, rad             -  {rms['before'][k]:9.4f}  {rms['after'][k]:9.4f}"
                     f"   <= {TARGET_RMS_RAD:g}: {ok}")
        lines.append(f"  max |sim - real|, rad           -  {mx['before'][k]:9.4f}  {mx['after'][k]:9.4f}")
        for rising, word in ((True, "up"), (False, "down")):
            s = {n: metrics.summarize(v, rising) for n, v in found.items()}
            real, before, after = s["real"], s["before"], s["after"]
            rise_ok = abs(after.rise_s - real.rise_s) <= TARGET_RISE_SHARE * real.rise_s
            speed_ok = abs(after.peak_speed_rad_s - real.peak_speed_rad_s) <= \
                TARGET_PEAK_SPEED_SHARE * real.peak_speed_rad_s
            error_ok = abs(after.error_rad - real.error_rad) <= TARGET_ERROR_RAD
            lines += [
                f"  rise 10-90 % {word:4s}, s     {real.rise_s:9.4f}  {before.rise_s:9.4f}  "
                f"{after.rise_s:9.4f}   within {TARGET_RISE_SHARE:.0%}: {_ok(rise_ok)}",
                f"  overshoot {word:4s}, %        {real.overshoot_pct:9.2f}  {before.overshoot_pct:9.2f}  "
                f"{after.overshoot_pct:9.2f}",
                f"  error after {word:4s}, rad    {real.error_rad:9.4f}  {before.error_rad:9.4f}  "
                f"{after.error_rad:9.4f}   within {TARGET_ERROR_RAD:g}: {_ok(error_ok)}",
                f"  peak speed {word:4s}, rad/s   {real.peak_speed_rad_s:9.3f}  "
                f"{before.peak_speed_rad_s:9.3f}  {after.peak_speed_rad_s:9.3f}   "
                f"within {TARGET_PEAK_SPEED_SHARE:.0%}: {_ok(speed_ok)}",
            ]
    return lines


def _ok(flag: bool) -> str:
    return "yes" if flag else "NO"


def perturbed_start(shipped: PlantParams) -> PlantParams:
    values = {}
    for name, v in shipped.values().items():
        stem = name.rstrip("0123456789")
        factor = PERTURBATION.get(stem, 1.0)
        if stem in PERTURBATION:
            values[name] = v * factor if factor is not None else 0.3
    return shipped.with_values(values)


def stated_uncertainty(name: str) -> float:
    stem = name.rstrip("0123456789")
    u = PARAMS["identified"]["uncertainty"][UNCERTAINTY_KEYS[stem]]
    return float(u[int(name[len(stem):]) - 1]) if isinstance(u, list) else float(u)


def run() -> list[str]:
    src = source()
    shipped = PlantParams.defaults()
    before = compare([src], PlantParams.load(BEFORE_PLANT), jobs=2)
    after = compare([src], shipped, jobs=2)
    sims = {"before": before.sim_after[0], "after": after.sim_after[0]}
    rms = {"before": before.rms_after[0], "after": after.rms_after[0]}
    mx = {"before": before.max_after[0], "after": after.max_after[0]}
    lines = [f"the real arm's recording ({REAL_RECORDING.name}, 10 s) against crslab running its lab, "
             f"aligned; drift fitted {after.nuisance[1].value * 1e6:.0f} ppm"]
    lines += joint_rows(src, sims, rms, mx)

    start = perturbed_start(shipped)
    t0 = time.perf_counter()
    result = fit([src], start=start, jobs=2)
    wall = time.perf_counter() - t0
    def off(f) -> float:  # how far from the shipped value, in its stated uncertainty
        return abs(f.value - shipped.value(f.name)) / stated_uncertainty(f.name)

    within = [f for f in result.values if off(f) <= 1.0]
    worst = max(result.values, key=off)
    ratio = off(worst)
    rms_after = float(np.sqrt(np.mean(result.rms_after[0] ** 2)))
    lines += [f"full crslab identify (16 values) from 10-20 % off: {result.runs} runs in {wall:.1f} s "
              f"(2 at a time), RMS {rms_after:.4f} rad; {len(within)} of {len(result.values)} values within "
              f"the shipped ones' stated uncertainty (95 %); farthest {worst.name} {worst.value:.4g} vs "
              f"{shipped.value(worst.name):.4g} ({ratio:.2f} of its uncertainty)"]
    if not math.isfinite(rms_after):
        raise RuntimeError("the fit diverged")
    return lines
