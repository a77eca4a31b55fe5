"""The worker process: owns the MuJoCo plant and the lab's code, and runs ticks on request.

Messages from the crslab process (tuples): ``("run", until_tick)``, ``("get", name)``,
``("set", name, index, value)``, ``("push", body_forces)``, ``("break",)`` (a debugged run:
call ``crs_debug_break``, where the debugger stops and arms its breakpoint on ``lab()``),
``("stop",)``. Replies:
``("ready", symbols)`` (or ``("failed", message)`` when the sandbox cannot be entered) first,
then ``("ran", code, tick, stats, log)`` where ``log`` is None or a dict of numpy columns and
``stats["motor_board_events"]`` lists the motor board's cut-outs starting or ending since the last
reply as ``(tick, joint, off)`` (joint 1..3, or 0 for a missing command; off 1 starts, 0 ends)
and ``stats["observations"]`` what each expectation reached since the last reply saw (dicts, see
:meth:`Worker.observe`);
``("value", v)`` or ``("error", message)``. Serial bytes never travel through the pipe: the
board writes them into the shared block, where the crslab process reads them even if this
process dies.

With ``SimConfig.sandboxed`` the worker builds the plant, then closes itself in the run
sandbox (crslab/sandbox/run_sandbox.py), then loads the lab: from the lab's first constructor
on, it may compute and print, and nothing else. Everything this process sends is read by the
crslab process as untrusted (crslab/sim/worker_reply.py).
"""

from __future__ import annotations

import contextlib
import mmap
from collections.abc import Iterable
from multiprocessing.connection import Connection

import numpy as np
from cffi import FFI

from crslab import crs, os_support
from crslab.framework_facts import MOTOR_BOARDS
from crslab.host_tools.c28x_memory import SIMULINK_INPUT_NAMES, lab_memory
from crslab.plant.model import apply_friction, apply_plant, load_model, motor_to_qpos
from crslab.plant.mujoco_c import mj_step_address, stop_stage_timers
from crslab.plant.plant_params import PlantParams
from crslab.sim.board_ffi import board_constants, board_ffi
from crslab.sim.config import SimConfig
from crslab.sim.debug_setup import DebugSetup
from crslab.sim.event_effects import apply_event
from crslab.sim.memory_table import fill_memory_table

LOG_ROWS = 2000  # rows per scope-log block

_LOG_COLUMNS = {  # name: (width, dtype)
    "tick": (1, np.int64), "enc_rad": (3, np.float64), "tau_lab": (3, np.float64),
    "tau_applied": (3, np.float64), "plot": (4, np.float64), "safety": (1, np.int32),
    "leds": (1, np.uint32), "motor_board_off": (1, np.int32), "qpos_dh_rad": (3, np.float64),
}
_C_TYPE = {np.int64: "int64_t *", np.float64: "double *", np.int32: "int32_t *", np.uint32: "uint32_t *"}


STAT_FIELDS = (
    "lab_calls", "lab_ns_total", "lab_ns_max", "lab_max_tick", "over_budget", "nan_first_tick",
    "nan_first_joint", "nan_count", "printing_runs", "safety_flag", "leds", "estop_latched",
    "tx_dropped", "tx_first_drop_tick", "overflow_tick", "overflow_chars", "overflow_phase",
)


class Worker:
    """The plant, the board and the lab, stepped in chunks."""

    def __init__(self, config: SimConfig, shared: mmap.mmap, keep_fds: Iterable[int] = (),
                 debug: DebugSetup | None = None) -> None:
        import mujoco

        self.config = config
        self.ffi = ffi = board_ffi()
        self.model = load_model()
        apply_plant(self.model, config.plant, loaded=load_model())
        self.plant = config.plant
        """The plant parameters in force (a scenario's friction scale changes them)."""
        self.data = mujoco.MjData(self.model)
        rest = np.asarray(config.rest_motor_rad, dtype=float)
        self.data.qpos[:3] = motor_to_qpos(rest)
        mujoco.mj_forward(self.model, self.data)
        self.rest_dh = crs.motor_to_dh(rest)
        mj_step = mj_step_address()
        stop_stage_timers()  # nothing reads mjData.timer: mj_step does the physics and only that
        block = ffi.cast("crs_shared *", ffi.from_buffer(shared))
        self.watched = {v.name: v for v in config.build.watched}
        var_ffi = None
        if self.watched:
            var_ffi = FFI()
            var_ffi.cdef("\n".join(v.cdecl for v in self.watched.values()))
        simulink_ffi = FFI()
        simulink_ffi.cdef("\n".join(f"extern int {name};" for name in SIMULINK_INPUT_NAMES))

        so = str(config.build.shared_object)
        self.sandbox = None
        tracer = debug.tracer_pid if debug is not None else None
        if config.sandboxed:
            from crslab.sandbox.run_sandbox import enter_run_sandbox

            self.sandbox = enter_run_sandbox(block, config.build.shared_object, keep_fds,
                                             sanitizer=config.build.sanitized, tracer_pid=tracer)
        elif tracer is not None:
            os_support.allow_tracer(tracer)
        block.phase = board_constants().CRS_PHASE_LOADING  # the lab's constructors run now
        with self.sandbox.loading() if self.sandbox is not None else contextlib.nullcontext():
            self.lib = ffi.dlopen(so)
        block.phase = board_constants().CRS_PHASE_IDLE
        # the same library again: found by its path among those loaded, never opened
        self.var_lib = var_ffi.dlopen(so) if var_ffi is not None else None
        self._simulink = simulink_ffi.dlopen(so)

        sim = self.sim = ffi.new("crs_sim *")
        self.lib.crs_sim_init(sim)
        self._keep = [shared, var_ffi, simulink_ffi]
        sim.shared = block
        # the lab's globals as the board's MATLAB code sees them (C28x addresses)
        self._keep += fill_memory_table(sim, ffi, config.build.shared_object, lab_memory(config.build))
        sim.mj_model = ffi.cast("void *", self.model._address)
        sim.mj_data = ffi.cast("void *", self.data._address)
        sim.mj_step = ffi.cast("crs_mj_step_fn", mj_step)
        sim.qpos = self._ptr("double *", self.data.qpos)
        sim.qvel = self._ptr("double *", self.data.qvel)
        sim.ctrl = self._ptr("double *", self.data.ctrl)
        sim.qfrc_applied = self._ptr("double *", self.data.qfrc_applied)
        sim.generation = config.build.generation
        sim.motor_board.model = MOTOR_BOARDS[config.motor_board_model]
        sim.strict_nan = int(config.strict_nan)
        sim.startup_ticks = config.startup_ticks
        sim.budget_ns = config.budget_ns
        for j in range(3):
            sim.rest_motor_rad[j] = rest[j]
        self._set_drive(config.plant)
        self._set_sliding_friction(config.plant)
        for j in range(3):
            sim.faults.noise_counts[j] = config.plant.encoder_noise_counts
        h = sim.hand
        h.kp_nm_per_rad, h.ki_nm_per_rad_s = config.hand.kp, config.hand.ki
        h.kd_nm_s_per_rad, h.max_nm = config.hand.kd, config.hand.max_nm
        sim.debug.break_when = int(config.build.break_when is not None)
        sim.debug.trap_fp = int(debug is not None and debug.trap_fp)
        self.events = list(config.scenario.events)
        self.motor_board_events: list[tuple[int, int, int]] = []
        self.observations: list[dict] = []
        self.log_blocks: list[dict[str, np.ndarray]] = []
        if config.log_signals:
            self._log_arrays = {k: np.zeros((LOG_ROWS, w), dt) for k, (w, dt) in _LOG_COLUMNS.items()}
            sim.log.capacity = LOG_ROWS
            for k, arr in self._log_arrays.items():
                setattr(sim.log, k, self._ptr(_C_TYPE[_LOG_COLUMNS[k][1]], arr))

    def _set_drive(self, plant: PlantParams) -> None:
        drive = self.sim.drive
        drive.lag_s = plant.drive_lag_s
        for j in range(3):
            # the C drive works in the commands' units: the plant's N.m over the motor gain
            drive.stall_units[j] = plant.stall_nm[j] / plant.motor_gain
            drive.backemf_units_s_per_rad[j] = plant.backemf_nm_s_per_rad[j] / plant.motor_gain

    def _set_sliding_friction(self, plant: PlantParams) -> None:
        friction = self.sim.friction
        friction.transition_rad_s = plant.friction_transition_rad_s
        for field, values in plant.sliding_units().items():
            for j in range(3):
                getattr(friction, field)[j] = values[j]

    def set_friction(self, plant: PlantParams) -> None:
        """Run on with ``plant``'s friction."""
        self.plant = plant
        apply_friction(self.model, plant)
        self._set_sliding_friction(plant)

    def _ptr(self, ctype: str, arr: np.ndarray) -> object:
        self._keep.append(arr)
        return self.ffi.cast(ctype, arr.ctypes.data)

    # -- watched variables -------------------------------------------------------------------
    def _var(self, name: str) -> object:
        if name not in self.watched:
            known = ", ".join(self.watched) or "none"
            raise KeyError(f"{name} is not a watched (#pragma DATA_SECTION) variable (watched: {known})")
        return self.watched[name]

    def get_var(self, name: str) -> float | list[float]:
        """Current value of a watched variable (a list for arrays)."""
        var = self._var(name)
        value = getattr(self.var_lib, name)
        if var.length is not None:
            return [float(value[i]) for i in range(var.length)]
        return float(value)

    def set_var(self, name: str, index: int | None, value: float) -> None:
        """Write a watched variable (or one element of a watched array) between ticks."""
        var = self._var(name)
        v = int(round(value)) if var.is_integer else float(value)
        if var.length is None:
            if index is not None:
                raise KeyError(f"{name} is not an array")
            setattr(self.var_lib, name, v)
            return
        if index is None or not 0 <= index < var.length:
            raise KeyError(f"{name} has {var.length} elements: give an index 0..{var.length - 1}")
        getattr(self.var_lib, name)[index] = v

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
        self.observations.append({
            "tick": int(sim.tick), "motor_board": self.config.motor_board_model,
            "motor_board_off": int(sim.motor_board.off), "motor_board_cutouts": int(sim.motor_board.cutouts),
            "error": int(sim.safety_flag), "motor_rad": [float(v) for v in motor], "var": value,
        })

    def take_observations(self) -> list[dict]:
        """What the expectations saw since the last call."""
        taken, self.observations = self.observations, []
        return taken

    def set_simulink_input(self, number: int, value: int) -> None:
        """What Simulink sent on input ``number`` (1..7), as the lab sees it from the next tick."""
        setattr(self._simulink, SIMULINK_INPUT_NAMES[number - 1], int(value))

    def _drain_log(self) -> None:
        log = self.sim.log
        n = int(log.count)
        if n:
            self.log_blocks.append({k: a[:n].copy() for k, a in self._log_arrays.items()})
            log.count = 0

    def run(self, until_tick: int) -> int:
        """Run to ``until_tick`` (events applied on their tick); returns a CRS_RUN_* code."""
        lib, sim = self.lib, self.sim
        while True:
            while self.events and self.events[0].tick <= sim.tick:
                apply_event(self, self.events.pop(0))
            if sim.tick >= until_tick:
                return lib.CRS_RUN_DONE
            stop_at = min(until_tick, self.events[0].tick) if self.events else until_tick
            code = lib.crs_sim_run(sim, stop_at)
            if code == lib.CRS_RUN_LOG_FULL or (self.config.log_signals and code != lib.CRS_RUN_DONE):
                self._drain_log()
            if code == lib.CRS_RUN_EVENTS_FULL:
                self._drain_motor_board_events()
            if code not in (lib.CRS_RUN_DONE, lib.CRS_RUN_LOG_FULL, lib.CRS_RUN_EVENTS_FULL):
                return code

    def _drain_motor_board_events(self) -> None:
        mb = self.sim.motor_board
        self.motor_board_events.extend((int(mb.event_tick[i]), int(mb.event_joint[i]), int(mb.event_off[i]))
                                       for i in range(int(mb.event_count)))
        mb.event_count = 0

    def debug_break(self) -> None:
        """Stop in the debugger before the next tick (it then stops at the next ``lab()`` call)."""
        self.lib.crs_tick = self.sim.tick
        self.lib.crs_debug_break(self.sim.tick)

    def stats(self) -> dict[str, int]:
        """The board's counters, as plain ints."""
        s = self.sim
        out = {name: int(getattr(s, name)) for name in STAT_FIELDS}
        out["tick"] = int(s.tick)
        out["first_over_tick"] = [int(s.first_over_tick[i]) for i in range(min(8, int(s.over_budget)))]
        out["motor_board"] = self.config.motor_board_model
        out["motor_board_cutouts"] = int(s.motor_board.cutouts)
        return out

    def take_motor_board_events(self) -> list[tuple[int, int, int]]:
        """The motor board's cut-outs starting or ending since the last call: (tick, joint, off)."""
        self._drain_motor_board_events()
        events, self.motor_board_events = self.motor_board_events, []
        return events

    def take_log(self) -> dict[str, np.ndarray] | None:
        """The scope rows gathered since the last call (None when logging is off)."""
        if not self.config.log_signals:
            return None
        self._drain_log()
        blocks, self.log_blocks = self.log_blocks, []
        if not blocks:
            return {k: np.zeros((0, w), dt) for k, (w, dt) in _LOG_COLUMNS.items()}
        return {k: np.concatenate([b[k] for b in blocks]) for k in _LOG_COLUMNS}


def serve(conn: Connection, config: SimConfig, shared_path: str, debug: DebugSetup | None = None) -> None:
    """Worker entry point: answer ``run`` requests until ``stop`` or the pipe closes."""
    from crslab.sandbox.run_sandbox import SandboxError

    with open(shared_path, "r+b") as f:
        shared = mmap.mmap(f.fileno(), 0)
    try:
        worker = Worker(config, shared, keep_fds=[conn.fileno()], debug=debug)
    except SandboxError as exc:
        conn.send(("failed", str(exc)))
        return
    conn.send(("ready", worker.lib.crs_lab_symbols()))
    while True:
        try:
            msg = conn.recv()
        except EOFError:
            return
        if msg[0] == "run":
            code = worker.run(int(msg[1]))
            stats = worker.stats()
            stats["motor_board_events"] = worker.take_motor_board_events()
            stats["observations"] = worker.take_observations()
            conn.send(("ran", code, int(worker.sim.tick), stats, worker.take_log()))
        elif msg[0] == "get":
            try:
                conn.send(("value", worker.get_var(msg[1])))
            except KeyError as exc:
                conn.send(("error", str(exc.args[0])))
        elif msg[0] == "set":
            try:
                worker.set_var(msg[1], msg[2], msg[3])
                conn.send(("value", None))
            except (KeyError, OverflowError) as exc:
                conn.send(("error", str(exc.args[0])))
        elif msg[0] == "push":
            push = worker.data.xfrc_applied  # MuJoCo's viewer: the mouse's force on each body
            push[:] = np.asarray(msg[1], dtype=float).reshape(push.shape)
            conn.send(("value", None))
        elif msg[0] == "break":
            worker.debug_break()
            conn.send(("value", None))
        elif msg[0] == "stop":
            conn.send(("stopped", worker.stats(), worker.take_log()))
            return
