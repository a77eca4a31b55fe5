"""Issue 30: the simulator in the contest world, contacts included, against a bare C loop on the
same scene.

crslab's default lab (Lab 1) runs in the ``contest`` world while a scenario's hand presses the
peg onto the hole block's top beside the hole, then down into the groove onto its floor, so that
the peg is in contact for most of the run (the share is printed). The bare C loop
(``bare_mj_step.c``, as in bench_sim.py) loads the very MJCF crslab generated for that world
(``crslab.world.scene.scene_xml``: the arm, the peg on its wrist, every fixture and its force
sensors) and replays the ``ctrl`` and ``qfrc_applied`` recorded from the same run tick by tick;
it must end in that run's state bit for bit, so both sides did the same physics, contacts and
sensors included. crslab's side is ``BoardRun.run`` at ``--fast`` in a process of its own
(``sim_rates.py``), which also works out the world's quantities after every step
(csrc/plant/world.c). Target (issue 30): crslab >= 0.9 of the bare loop.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np
from baselines import build_bare_loop, record_run, run_bare_loop, same_physics

from crslab import crs
from crslab.run.api import make_config, simulate
from crslab.world import load_world
from crslab.world.scene import scene_xml

REPEATS = 3


def pressing_scenario(path: Path) -> Path:
    """A hand pressing the peg onto the hole block's top, then into the groove onto its floor."""
    w = load_world("contest")
    h, g = w.hole, w.groove

    def xyz_in(x: float, y: float, z: float) -> str:
        return ", ".join(f"{v / crs.M_PER_IN:.5f}" for v in (x, y, z))

    block = (h.center_xy_m[0] + 0.025, h.center_xy_m[1])
    entrance = g.corners_xy_m[0]
    floor = g.top_z_m - g.depth_m
    moves = [
        (0.2, (*block, h.top_z_m + 0.02), 1.5),
        (2.0, (*block, h.top_z_m - 0.002), 1.0),
        (7.0, (*block, h.top_z_m + 0.05), 1.0),
        (8.5, (*entrance, g.top_z_m + 0.03), 1.5),
        (10.5, (*entrance, floor - 0.002), 1.0),
    ]
    text = "end = 16.0\n" + "".join(
        f'[[event]]\nat = {at}\nkind = "hand"\nxyz_in = [{xyz_in(*target)}]\nduration = {duration}\n'
        for at, target, duration in moves
    )
    path.write_text(text)
    return path


def rates_in_a_new_process(scenario: Path) -> dict[str, tuple[float, float | None]]:
    r = subprocess.run(
        [sys.executable, str(Path(__file__).with_name("sim_rates.py")), "contest", str(scenario)],
        capture_output=True,
        text=True,
    )
    if r.returncode != 0:
        raise RuntimeError(f"sim_rates.py failed: {r.stderr.strip()}")
    return {k: tuple(v) for k, v in json.loads(r.stdout.splitlines()[-1]).items()}


def run() -> list[str]:
    with tempfile.TemporaryDirectory(prefix="crslab-bench-contest-") as tmp:
        tmp = Path(tmp)
        scenario = pressing_scenario(tmp / "press.toml")
        scene = tmp / "contest_scene.xml"
        scene.write_text(scene_xml(load_world("contest")))
        native = make_config(None, str(scenario), world="contest", native=True)
        ticks = native.scenario.end_tick
        rec = record_run(native, ticks)
        logged = simulate(None, str(scenario), world="contest", log=True).log
        touching = (logged["hole_force"][:, 0] > 0) | (logged["groove_force"][:, 0] > 0)
        exe = build_bare_loop(tmp)
        controls = rec.save(tmp / "controls.bin")
        no_contacts = tmp / "contest_scene_no_contacts.xml"
        no_contacts.write_text(without_collisions(scene_xml(load_world("contest"))))
        model = mujoco.MjModel.from_xml_path(str(scene))
        contacts = contacts_per_step(model, rec)
        sims, sims_cpu, bare, bare_cpu, free_cpu = [], [], [], [], []
        for _ in range(REPEATS):  # interleaved: both sides see the same machine load
            for _ in range(2):
                wall, cpu = rates_in_a_new_process(scenario)["wasm"]
                sims.append(wall)
                if cpu is not None:
                    sims_cpu.append(cpu)
            loop = run_bare_loop(exe, controls, passes=2, model_xml=scene)
            same_physics(rec, loop.qpos_end, loop.qvel_end, "the bare C loop on the contest scene")
            bare += [ticks / s for s in loop.pass_s]
            bare_cpu += [ticks / s for s in loop.cpu_s]
            no_cd = run_bare_loop(exe, controls, passes=2, model_xml=no_contacts)
            free_cpu += [ticks / s for s in no_cd.cpu_s]
    sim, c_loop = max(sims), max(bare)
    lines = [
        f"same physics on both sides: Lab 1 in the contest world, {ticks} ticks, a hand pressing the peg "
        f"on the hole block and into the groove (in contact {touching.mean():.0%} of the ticks, up to "
        f"{max(logged['hole_force'].max(), logged['groove_force'].max()):.0f} N); the bare loop's replay "
        f"ends in the run's state bit for bit",
        f"crslab BoardRun.run --fast in the contest world (WebAssembly lab, world quantities every "
        f"tick), best of {2 * REPEATS}: {sim:,.0f} ticks/s",
        f"bare C loop on the same generated scene (contacts and sensors included), best of {2 * REPEATS} "
        f"passes: {c_loop:,.0f} steps/s",
        f"  ratio crslab / bare C loop, wall time: {sim / c_loop:.2f} (target >= 0.9, issue 30)",
    ]
    if sims_cpu:
        lines.append(
            f"  by CPU time: crslab's worker {max(sims_cpu):,.0f} ticks/s, the bare loop "
            f"{max(bare_cpu):,.0f} steps/s: ratio {max(sims_cpu) / max(bare_cpu):.2f}"
        )
    lines.append(
        f"what contacts cost: the scene has {model.ngeom} geoms; {contacts[0]:.1f} contacts a step on "
        f"average, {contacts[1]} at most; the bare loop by CPU time with collision detection off "
        f"{max(free_cpu):,.0f} steps/s: contacts and their constraints take "
        f"{1 - max(bare_cpu) / max(free_cpu):.0%} of a step in this run"
    )
    return lines


def without_collisions(xml: str) -> str:
    """The scene with MuJoCo's collision detection off (its option's flag ``contact``)."""
    root = ET.fromstring(xml)
    option = root.find("option")
    assert option is not None
    flag = option.find("flag")
    if flag is None:
        flag = ET.SubElement(option, "flag")
    flag.set("contact", "disable")
    return ET.tostring(root, encoding="unicode")


def contacts_per_step(model: object, rec: object) -> tuple[float, int]:
    """The mean and the largest number of contacts per step, replaying the recorded controls."""
    data = mujoco.MjData(model)
    data.qpos[:] = rec.qpos0
    counts = []
    for ctrl, qfrc in zip(rec.ctrl, rec.qfrc_applied):
        data.ctrl[:] = ctrl
        data.qfrc_applied[:] = qfrc
        mujoco.mj_step(model, data)
        counts.append(data.ncon)
    return float(np.mean(counts)), int(max(counts))
