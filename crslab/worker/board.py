"""One board instance in the worker: one lab's MuJoCo data, its board (``crs_board``: the framework's
state), its firmware and its outputs (its own shared block), stepped in chunks on request. A worker
process holds many (:mod:`crslab.worker.main`). The board's C is called through
:class:`crslab._bindings.BoardLibrary`.

Serial bytes and scope rows never travel through the pipe: the board writes them into the
instance's shared block, where the crslab process reads them even if this process dies.

The lab's firmware is a WebAssembly module by default: the board (the C core's) runs it in a
store of its own, and it can reach nothing of this process (csrc/board/firmware_wasm.c); the
instances of a worker share one wasmtime engine and one compiled module per distinct firmware,
and a trap or a hang ends only the instance whose firmware did it. A native
firmware (crslab debug, --sanitize, --native) is a shared object holding the board too; with
``RunConfig.sandboxed`` the worker builds the plant, then closes itself in the run sandbox
(crslab/sandbox/run_sandbox.py), then loads it: from the lab's first constructor on, it may
compute and print, and nothing else. Everything a native worker sends is read by the crslab
process as untrusted (crslab/worker/worker_messages.py).
"""

from __future__ import annotations

import contextlib
import copy
import errno
import mmap
import os
import re
from collections.abc import Iterable

import numpy as np

from crslab import crs, os_support
from crslab._bindings import BoardLibrary, compiled_board, constants
from crslab.cache import is_sealed
from crslab.lab.firmware import MEMORY_BYTES, NATIVE_STACK_BYTES
from crslab.lab.watched import WatchedError, WatchedVar, watched_var
from crslab.plant.model import apply_friction, apply_plant, motor_to_qpos
from crslab.plant.mujoco_c import mj_step_address, stop_stage_timers
from crslab.plant.plant_params import PlantParams
from crslab.scenario.expect_events import Observation
from crslab.worker import worker_messages
from crslab.worker.board_ffi import native_board_ffi
from crslab.worker.board_settings import board_settings, friction
from crslab.worker.config import RunConfig
from crslab.worker.debug_setup import DebugSetup
from crslab.worker.event_effects import apply_event
from crslab.worker.firmware_memory import FirmwareMemory, NativeMemory, WasmMemory
from crslab.worker.memory_table import fill_memory_table
from crslab.worker.run_stats import CounterRow, RunStats
from crslab.worker.share import Share
from crslab.worker.wasm_runtime import (
    ENGINE_ENVIRONMENT,
    KeptModule,
    WasmImage,
    WasmImageError,
    wasmtime_library,
)
from crslab.world import World
from crslab.world.scene import FIXTURE_SENSORS, PEG_TIP_SITE, load_scene, set_arm_pose
from crslab.world.world_facts import WORLD_ROW_WIDTH, split_world_row


def world_config(c: BoardLibrary, model: object, data: object, world: World) -> tuple[object, list[object]]:
    """The C world's configuration (a ``crs_world_config *`` of ``c``'s; csrc/plant/world.h) for
    ``world``'s compiled scene ``model`` and its ``data``: the sensors' places in
    ``data.sensordata``, the hole, the groove's centre line, the egg's breaking force and geom.
    Returns it and what must stay alive as long as it is used."""
    config = c.new("crs_world_config *")
    keep: list[object] = [model, data, config]

    def ptr(ctype: str, arr: np.ndarray, offset: int = 0) -> object:
        keep.append(arr)
        return c.pointer(ctype, arr.ctypes.data) + offset

    w = config
    w.sensordata = ptr("double *", data.sensordata)  # type: ignore[attr-defined]
    w.peg_tip_adr = -1
    names = [model.sensor(i).name for i in range(model.nsensor)]  # type: ignore[attr-defined]
    if PEG_TIP_SITE in names:
        w.peg_tip_adr = int(model.sensor_adr[names.index(PEG_TIP_SITE)])  # type: ignore[attr-defined]
    for i, fixture in enumerate(FIXTURE_SENSORS):
        found = f"{fixture}_force" in names
        w.sensor_adr[i] = int(model.sensor_adr[names.index(f"{fixture}_force")]) if found else -1  # type: ignore[attr-defined]
    w.timestep_s = float(model.opt.timestep)  # type: ignore[attr-defined]
    if (h := world.hole) is not None:
        w.has_hole = 1
        w.hole_xy_m = list(h.center_xy_m)
        w.hole_top_z_m, w.hole_radius_m = h.top_z_m, h.diameter_m / 2
    if world.groove is not None:
        w.has_groove = 1
        w.groove_xy_m = [v for corner in world.groove.corners_xy_m for v in corner]
    if world.egg is not None:
        w.breaking_force_n = world.egg.breaking_force_n
        egg = model.geom("egg").id  # type: ignore[attr-defined]
        w.egg_contype = ptr("int32_t *", model.geom_contype, egg)  # type: ignore[attr-defined]
        w.egg_conaffinity = ptr("int32_t *", model.geom_conaffinity, egg)  # type: ignore[attr-defined]
        w.egg_size_m = ptr("double *", model.geom_size, 3 * egg)  # type: ignore[attr-defined]
        w.egg_pos_m = ptr("double *", model.geom_pos, 3 * egg)  # type: ignore[attr-defined]
    return config, keep


class ModelRefused(Exception):
    """MuJoCo refuses the model a run's world file makes: the message names the file (``file``)."""

    def __init__(self, file: str, message: str) -> None:
        super().__init__(message)
        self.file = file


def refusal_text(error: str) -> str:
    """MuJoCo's refusal of a model, in one line: what it refused and in which part.

    >>> refusal_text("Error: error 'inertia must have positive eigenvalues' in fullinertia\\n"
    ...              "Element name 'peg', id 5, line 35")
    'inertia must have positive eigenvalues (the peg)'
    """
    what = re.search(r"error '([^']*)'", error)
    part = re.search(r"Element name '([^']*)'", error)
    text = what.group(1) if what else (error.strip().splitlines() or ["no reason given"])[0]
    return f"{text} (the {part.group(1)})" if part and part.group(1) else text


def plant_model(config: RunConfig) -> object:
    """The MuJoCo model of ``config``'s world with its plant parameters applied (loaded from the
    MJCF once). A world MuJoCo refuses (its values each in range, together not a body MuJoCo can
    simulate: a peg 1e-9 m across) raises :class:`ModelRefused` naming the world's file."""
    try:
        model = load_scene(config.world)
    except ValueError as exc:
        source = config.world.source or "the world"
        why = refusal_text(str(exc))
        raise ModelRefused(source, f"{source}: MuJoCo refuses the world it describes: {why}") from None
    apply_plant(model, config.plant, loaded=copy.copy(model))
    return model


class FirmwareStopped(Exception):
    """The firmware could not be loaded, or stopped in a constructor: ``trap`` says how
    (:func:`trap_info`)."""

    def __init__(self, trap: dict) -> None:
        super().__init__(trap.get("text", ""))
        self.trap = trap


def trap_info(c: BoardLibrary, sim: object) -> dict:
    """How the firmware stopped (``crs_board.trap``), as plain data: kind, phase, tick, exit code and
    wasmtime's text (the firmware's frames included)."""
    t = sim.trap  # type: ignore[attr-defined]
    return {"kind": int(t.kind), "phase": int(t.phase), "tick": int(t.tick), "exit_code": int(t.exit_code),
            "line": int(t.line), "text": c.string(t.text)}


_ROWS: dict[tuple[str, ...], CounterRow] = {}


def _counter_row(c: BoardLibrary) -> CounterRow:
    """The :class:`CounterRow` of ``c``'s counters (made once per board build)."""
    names = tuple(c.counter_names)
    if names not in _ROWS:
        _ROWS[names] = CounterRow(list(names))
    return _ROWS[names]


class Board:
    """One board instance: its plant's data, the board and the lab, stepped in chunks.

    ``deadline_s``: a WebAssembly firmware's call running longer is interrupted (None: never).
    ``model``: the MuJoCo model to run on (:class:`crslab.worker.main.Models` shares one among
    instances that never change theirs); None: its own, loaded here. ``image``: the firmware's bytes
    and digest, when the worker already read them (:class:`crslab.worker.main.Images`).
    ``time_lab`` False counts no lab() call's cost (measuring what timing costs:
    :mod:`crslab.run.inprocess`). ``share``: what a WebAssembly firmware may take of a worker it
    shares with other runs (:mod:`crslab.worker.share`; None: the worker is its own)."""

    def __init__(self, config: RunConfig, shared: mmap.mmap, keep_fds: Iterable[int] = (),
                 debug: DebugSetup | None = None, *, deadline_s: float | None = None,
                 model: object | None = None, image: WasmImage | None = None, time_lab: bool = True,
                 share: Share | None = None) -> None:
        import mujoco

        self.config = config
        self.model = model if model is not None else plant_model(config)
        self.plant = config.plant
        """The plant parameters in force (a scenario's friction scale changes them)."""
        self.data = mujoco.MjData(self.model)
        rest = np.asarray(config.rest_motor_rad, dtype=float)
        set_arm_pose(self.model, self.data, motor_to_qpos(rest))
        mujoco.mj_forward(self.model, self.data)
        self.rest_dh = crs.motor_to_dh(rest)
        mj_step = mj_step_address()
        stop_stage_timers()  # nothing reads mjData.timer: mj_step does the physics and only that
        self.watched = {v.name: v for v in config.build.watched}
        self.sandbox = None
        self._keep: list[object] = [shared]
        if config.build.native:
            ffi = native_board_ffi()
            block = ffi.cast("crs_shared *", ffi.from_buffer(shared))
            self.c = BoardLibrary(ffi, self._load_native(config, block, keep_fds, debug))
            sim = self.c.new_board(config.build.generation.id, block)
            if self.c.native_attach(sim) != 0:
                raise FirmwareStopped(trap_info(self.c, sim))
            names = [v.name for v in config.build.variables]
            self.firmware: FirmwareMemory = NativeMemory(config.build.image, names)
        else:
            self.c = compiled_board()
            block = self.c.shared(shared)
            sim = self._load_wasm(config, block, deadline_s, image or WasmImage.read(config.build.image),
                                  share)
            self.firmware = WasmMemory(self.c, sim, config.build)
        self.sim = sim
        c = self.c
        # the lab's globals as the board's MATLAB code sees them (C28x addresses)
        self._keep += fill_memory_table(sim, c, self.firmware, config.build.memory)
        c.attach_plant(sim, {
            "model": c.pointer("void *", self.model._address),
            "data": c.pointer("void *", self.data._address),
            "step": c.pointer("crs_mj_step_fn", mj_step), "qpos": self._ptr("double *", self.data.qpos),
            "qvel": self._ptr("double *", self.data.qvel), "ctrl": self._ptr("double *", self.data.ctrl),
            "qfrc_applied": self._ptr("double *", self.data.qfrc_applied)})
        trap_fp = debug is not None and debug.trap_fp
        c.configure(sim, board_settings(config, trap_fp=trap_fp, time_lab=time_lab))
        self._set_world(config.world)
        self.events = list(config.scenario.events)
        self._row = _counter_row(c)
        self._over_slot = c.counter_names.index("over_budget")
        self.motor_board_events: list[worker_messages.MotorBoardEvent] = []
        self.observations: list[Observation] = []

    def _set_world(self, world: World) -> None:
        """Configure the board's world (csrc/plant/world.h) with the scene's sensors and the egg's
        geom; world ``none`` leaves it off."""
        if world.is_free_air:
            return
        config, keep = world_config(self.c, self.model, self.data, world)
        self._keep += keep
        self.c.attach_world(self.sim, config)

    def board_event(self, fields: dict) -> None:
        """Have the board apply one ``crs_board_event`` (csrc/board/board_config.h) now."""
        if not self.c.apply_event(self.sim, fields):
            raise ValueError(f"the board knows no event of kind {fields.get('kind')}")

    def world_values(self) -> dict[str, float] | None:
        """The world's quantities of the last step, by name (the peg tip's as ``peg_tip_x`` ...;
        every column of :data:`~crslab.world.world_facts.WORLD_COLUMNS`). None in a world without
        fixtures."""
        w = self.sim.world
        if not w.enabled:
            return None
        values = {}
        row = [float(w.state.row[i]) for i in range(WORLD_ROW_WIDTH)]
        for name, value in split_world_row(row).items():
            if len(value) == 3:
                values.update({f"{name}_{a}": float(v) for a, v in zip("xyz", value)})
            else:
                values[name] = float(value[0])
        return values

    def _load_native(self, config: RunConfig, block: object, keep_fds: Iterable[int],
                     debug: DebugSetup | None) -> object:
        """The native firmware's shared object (the board linked with the firmware), loaded in the
        run sandbox when asked."""
        tracer = debug.tracer_pid if debug is not None else None
        for library in (config.build.image, config.build.trap_library):
            # loaded by its path: this user's build sealed it, in a folder only this user writes
            if library is not None and not is_sealed(library):
                raise WasmImageError(errno.EACCES, f"{library.name} is not what crslab built (its seal "
                                                   "does not hold): build it again")
        loading, idle = constants.CRS_PHASE_LOADING, constants.CRS_PHASE_IDLE  # before the sandbox closes
        if config.sandboxed:
            from crslab.sandbox.run_sandbox import enter_run_sandbox

            self.sandbox = enter_run_sandbox(block, config.build.image, keep_fds,
                                             trap_library=config.build.trap_library,
                                             sanitizer=config.build.sanitized, tracer_pid=tracer)
        elif tracer is not None:
            os_support.allow_tracer(tracer)
        block.phase = loading  # type: ignore[attr-defined]
        with self.sandbox.loading() if self.sandbox is not None else contextlib.nullcontext():
            lib = native_board_ffi().dlopen(str(config.build.image))
        block.phase = idle  # type: ignore[attr-defined]
        return lib

    def _load_wasm(self, config: RunConfig, block: object, deadline_s: float | None,
                   image: WasmImage, share: Share | None) -> object:
        """The WebAssembly firmware, loaded into a new board (the C core's): a store of its own, the
        compiled module shared with every instance of the same firmware in this process, with what
        it may take of a worker it shares (``share``; None: a worker of its own); raises
        :class:`FirmwareStopped` when it cannot be loaded or stops in a constructor."""
        c = self.c
        sim = c.new_board(config.build.generation.id, block)
        os.environ.update(ENGINE_ENVIRONMENT)  # (a trap's backtrace names the lab's file and line)
        library, key = c.text(str(wasmtime_library())), c.text(image.digest)
        # the compiled module kept between runs: read (its seal checked on the bytes the board then
        # loads) only when this process does not hold the module already (another instance of the
        # same firmware); compiled anew, the board writes it to a private file crslab then seals
        path = None if c.wasm_module_held(image.digest) else image.compiled_path()
        kept = KeptModule(path) if path is not None else None
        bytes_ = kept.bytes if kept is not None else None
        compiled = c.bytes_view(bytes_) if bytes_ else c.pointer("uint8_t *", 0)
        wasm = c.bytes_view(image.wasm)
        self._keep += [library, wasm, key]
        block.phase = constants.CRS_PHASE_LOADING  # type: ignore[attr-defined]
        code = c.wasm_load(sim, {
            "libwasmtime": library, "wasm": wasm, "wasm_len": len(image.wasm), "memory_bytes": MEMORY_BYTES,
            "stack_bytes": NATIVE_STACK_BYTES, "compiled": compiled, "compiled_len": len(bytes_ or b""),
            "compiled_fd": kept.fd if kept is not None else -1, "module_key": key,
            "deadline_ns": 0 if deadline_s is None else max(1, round(deadline_s * 1e9)),
            **(share.options() if share is not None else {})})
        del compiled  # wasmtime copied what it loaded
        if kept is not None:
            kept.keep()
        if code != 0:
            raise FirmwareStopped(trap_info(c, sim))
        block.phase = constants.CRS_PHASE_IDLE  # type: ignore[attr-defined]
        return sim

    def close(self) -> None:
        """Free the firmware (a WebAssembly one: its store, and its compiled module when no other
        instance runs it; a native one stays loaded with the process)."""
        if not self.config.build.native and self.sim is not None:
            self.c.wasm_unload(self.sim)
            self.sim = None

    @property
    def module_refs(self) -> int:
        """How many instances of this process share this one's compiled firmware module (0: a
        native firmware)."""
        return 0 if self.config.build.native else self.c.wasm_module_refs(self.sim)

    def set_friction(self, plant: PlantParams) -> None:
        """Run on with ``plant``'s friction."""
        self.plant = plant
        apply_friction(self.model, plant)
        self.board_event({"kind": constants.CRS_EVENT_FRICTION,
                          "friction": friction(plant.sliding_units(), plant.friction_transition_rad_s)})

    def _ptr(self, ctype: str, arr: np.ndarray) -> object:
        self._keep.append(arr)
        return self.c.pointer(ctype, arr.ctypes.data)

    # -- watched variables -------------------------------------------------------------------
    def _var(self, name: str, index: int | None, *, whole: bool) -> tuple[WatchedVar, object]:
        """A watched variable, checked with ``index`` (:func:`crslab.lab.watched.watched_var`), and
        its first element (a cffi pointer)."""
        try:
            var = watched_var(self.watched.values(), name, index, self.config.build.source.name, whole=whole)
        except WatchedError as exc:
            raise KeyError(str(exc)) from None
        element = self.firmware.element_type(var.ctype)
        count = var.length if var.length is not None else 1
        address = None
        if element is not None:
            address = self.firmware.address(name, count * self.firmware.size_of(element))
        if address is None:
            raise KeyError(f"{name} cannot be reached in the lab's firmware")
        return var, self.firmware.pointer(f"{element} *", address)

    def get_var(self, name: str) -> float | list[float]:
        """Current value of a watched variable (a list for arrays)."""
        var, pointer = self._var(name, None, whole=True)
        if var.length is not None:
            return [float(pointer[i]) for i in range(var.length)]  # type: ignore[index]
        return float(pointer[0])  # type: ignore[index]

    def set_var(self, name: str, index: int | None, value: float) -> None:
        """Write a watched variable (or one element of a watched array) between ticks."""
        var, pointer = self._var(name, index, whole=False)
        try:
            var.check_value(value, self.config.build.source.name)
        except WatchedError as exc:
            raise KeyError(str(exc)) from None
        pointer[index or 0] = int(round(value)) if var.is_integer else float(value)  # type: ignore[index]

    def observe(self, var: tuple[str, int | None] | None) -> None:
        """Note what an expectation sees now, before this tick runs: the motor board and the
        safety flag as the last tick left them, the arm's motor angles (what this tick's encoders
        read, without offsets or faults), and the watched variable ``var`` (name, index) if any."""
        sim = self.sim
        motor = crs.dh_to_motor(np.asarray(self.data.qpos[:3], dtype=float))
        value = None
        if var is not None:
            got = self.get_var(var[0])
            value = float(got[var[1]] if isinstance(got, list) and var[1] is not None else got)
        self.observations.append(Observation(
            tick=int(sim.tick), motor_board=self.config.motor_board_model,
            motor_board_off=bool(sim.motor_board.off), motor_board_cutouts=int(sim.motor_board.cutouts),
            error=int(sim.safety_flag), motor_rad=(float(motor[0]), float(motor[1]), float(motor[2])),
            var=value, world=self.world_values()))

    def take_observations(self) -> list[Observation]:
        """What the expectations saw since the last call."""
        taken, self.observations = self.observations, []
        return taken

    def run(self, until_tick: int) -> int:
        """Run to ``until_tick`` (events applied on their tick); returns a CRS_RUN_* code: done, or
        why the chunk ended early (the shared block's serial buffer or scope log full: the crslab
        process takes them and asks for the rest; a trap, a NaN in strict mode, an overflow)."""
        c, sim = self.c, self.sim
        while True:
            while self.events and self.events[0].tick <= sim.tick:
                apply_event(self, self.events.pop(0))
            if sim.tick >= until_tick:
                return constants.CRS_RUN_DONE
            stop_at = min(until_tick, self.events[0].tick) if self.events else until_tick
            code = c.run(sim, stop_at)
            if code == constants.CRS_RUN_EVENTS_FULL:
                self._drain_motor_board_events()
            elif code != constants.CRS_RUN_DONE:
                return code

    def _drain_motor_board_events(self) -> None:
        n = self.c.take_motor_board_events(self.sim)
        if n <= 0:
            return  # (nearly every chunk)
        mb = self.sim.motor_board
        self.motor_board_events.extend(
            worker_messages.MotorBoardEvent(int(mb.event_tick[i]), int(mb.event_joint[i]),
                                            bool(mb.event_off[i]))
            for i in range(min(n, len(mb.event_tick))))

    def debug_break(self) -> None:
        """Stop in the debugger before the next tick (it then stops at the next ``lab()`` call)."""
        self.c.debug_break(int(self.sim.tick))

    def stats(self) -> RunStats:
        """The board's counters (read in one call), as :meth:`stats_row` reads them."""
        return RunStats.from_row(self.stats_row())

    def stats_row(self) -> tuple:
        """:meth:`stats` as :meth:`RunStats.row` gives them, made with no :class:`RunStats` (a
        WebAssembly worker's reply for every chunk)."""
        counts = self.c.counter_values(self.sim)
        over = min(constants.CRS_FIRST_OVER_TICKS, counts[self._over_slot])
        first = tuple(int(self.sim.first_over_tick[i]) for i in range(over)) if over > 0 else ()
        return self._row(counts, first_over_tick=first, native=self.config.build.native,
                         motor_board=self.config.motor_board_model)

    def take_motor_board_events(self) -> list[worker_messages.MotorBoardEvent]:
        """The motor board's cut-outs starting or ending since the last call."""
        self._drain_motor_board_events()
        events, self.motor_board_events = self.motor_board_events, []
        return events
