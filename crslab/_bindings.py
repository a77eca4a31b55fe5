"""The one way into crslab's compiled C core (``crslab._core``: ``ffi`` and ``lib``, built by
csrc/cffi_build.py from csrc/kin, csrc/port, csrc/plant and csrc/board). Every other module calls
the functions here, numpy arrays in and out, and imports nothing of the core, as PyNaCl's
``nacl.bindings`` and argon2-cffi's ``argon2.low_level`` stand between their packages and their
``ffi, lib`` (tests/test_one_seam_to_c.py fails when a second module imports the core).

- :data:`constants`: every named constant of the core's headers (``CRS_TICKS_PER_S``,
  ``CRS_RUN_DONE``, ``ROT_OK``...), read once.
- The kinematics (csrc/kin): the CRS arm's (``arm_*``), a DH chain's (``chain_*``), the closed-form
  IK (``rrr_ik``, ``planar3r_ik``), rotations (``rotation_*``), trajectory profiles (``traj_*``):
  each fills the numpy arrays it is given, C-contiguous float64 (int32 for statuses and flags),
  for ``n`` rows at once.
- The world's facts (csrc/plant/world.h, world_facts.h): its row's columns, fixtures, the egg, the
  peg's depth, the groove's nearest point (``world_*``, ``egg_*``, ``peg_depths``, ``groove_nearest``).
- The framework's generations (:func:`generation_rows`) and wasmtime's library loaded ahead of forks
  (:func:`preload_wasmtime`).
- The board (csrc/board): :class:`BoardLibrary`, over the core (:func:`compiled_board`) or a native
  lab's shared object, which holds the same board (crslab/worker/board_ffi.py reads its
  declarations); the shared block's view (:func:`shared_view`) and its scope log's columns
  (:func:`scope_log_columns`); bytes in C memory (:func:`read_bytes`, :func:`write_bytes`).

>>> import numpy as np
>>> out = np.empty(3)
>>> arm_fk_dh(np.zeros(3), out, 1); out
array([20.,  0., 10.])
>>> constants.CRS_TICKS_PER_S
1000
"""

from __future__ import annotations

from typing import Any

import numpy as np

from crslab._core import ffi, lib


class _Constants:
    """The core's named constants as attributes (enums, ``#define`` numbers, ``static const``:
    names that begin with a capital), each read from the core when first asked for."""

    def __getattr__(self, name: str) -> int | float:
        try:
            value = getattr(lib, name) if name[:1].isupper() else None
        except AttributeError:
            value = None
        if not isinstance(value, (int, float)):
            raise AttributeError(f"the C core has no constant {name}")
        setattr(self, name, value)
        return value


constants: Any = _Constants()
"""Every named constant of the core (``constants.CRS_TICKS_PER_S``)."""


def _d(arr: np.ndarray | None) -> Any:
    """A ``double *`` onto a C-contiguous float64 array (no copy); NULL for None."""
    return ffi.NULL if arr is None else ffi.cast("double *", ffi.from_buffer(arr))


def _i(arr: np.ndarray | None) -> Any:
    """An ``int *`` onto a C-contiguous int32 array (no copy); NULL for None."""
    return ffi.NULL if arr is None else ffi.cast("int *", ffi.from_buffer(arr))


def _i32(arr: np.ndarray) -> Any:
    """An ``int32_t *`` onto a C-contiguous int32 array (no copy)."""
    return ffi.cast("int32_t *", ffi.from_buffer(arr))


# -- the CRS arm (csrc/kin/crs_arm.h): n rows of 3 ------------------------------------------------
def arm_motor_to_dh(motor_rad: np.ndarray, dh_rad: np.ndarray, n: int) -> None:
    """DH angles from motor angles (rad)."""
    lib.crs_motor_to_dh_batch(_d(motor_rad), _d(dh_rad), n)


def arm_dh_to_motor(dh_rad: np.ndarray, motor_rad: np.ndarray, n: int) -> None:
    """Motor angles from DH angles (rad)."""
    lib.crs_dh_to_motor_batch(_d(dh_rad), _d(motor_rad), n)


def arm_fk_motor(motor_rad: np.ndarray, xyz_in: np.ndarray, n: int) -> None:
    """The end effector's position (in) from motor angles (rad)."""
    lib.crs_fk_motor_batch(_d(motor_rad), _d(xyz_in), n)


def arm_fk_dh(dh_rad: np.ndarray, xyz_in: np.ndarray, n: int) -> None:
    """The end effector's position (in) from DH angles (rad)."""
    lib.crs_fk_dh_batch(_d(dh_rad), _d(xyz_in), n)


def arm_fk_pose_dh(dh_rad: np.ndarray, pose_in: np.ndarray) -> None:
    """One 4x4 pose (16 values, translation in in) of DH frame 3 from one row of DH angles."""
    lib.crs_fk_pose_dh(_d(dh_rad), _d(pose_in))


def arm_ik_motor(xyz_in: np.ndarray, elbow_up: bool, motor_rad: np.ndarray, status: np.ndarray,
                 n: int) -> None:
    """Motor angles (rad) for targets (in), a ``CRS_IK_*`` status per row."""
    lib.crs_ik_motor_batch(_d(xyz_in), int(elbow_up), _d(motor_rad), _i(status), n)


def arm_ik_dh(xyz_in: np.ndarray, elbow_up: bool, dh_rad: np.ndarray, status: np.ndarray, n: int) -> None:
    """DH angles (rad) for targets (in), a ``CRS_IK_*`` status per row."""
    lib.crs_ik_dh_batch(_d(xyz_in), int(elbow_up), _d(dh_rad), _i(status), n)


def arm_outside_envelope(motor_rad: np.ndarray, outside: np.ndarray, n: int) -> None:
    """1 per row of motor angles (rad) outside the framework's safety envelope, else 0."""
    lib.crs_outside_envelope_motor_batch(_d(motor_rad), _i(outside), n)


def arm_jacobian_motor(motor_rad: np.ndarray, jac_in_per_rad: np.ndarray, n: int) -> None:
    """d(xyz, in)/d(motor angles, rad), 9 values per row."""
    lib.crs_jacobian_motor_batch(_d(motor_rad), _d(jac_in_per_rad), n)


# -- a DH chain (csrc/kin/chain.h, chain_ik.h) ---------------------------------------------------------
def chain_new(convention: int, a: np.ndarray, alpha_rad: np.ndarray, d: np.ndarray, theta_rad: np.ndarray,
              joint_types: np.ndarray, base: np.ndarray | None, tool: np.ndarray | None) -> tuple[Any, int]:
    """A ``dh_chain`` over the arrays given (kept alive by the caller, with the chain) and its
    ``CHAIN_*`` status (``chain_check``)."""
    c = ffi.new("dh_chain *")
    c.n_rows, c.convention = len(a), convention
    c.a, c.alpha_rad, c.d, c.theta_rad = _d(a), _d(alpha_rad), _d(d), _d(theta_rad)
    c.joint_type, c.base, c.tool = _i(joint_types), _d(base), _d(tool)
    return c, int(lib.chain_check(c))


def chain_fk(chain: Any, q_rad: np.ndarray, pose: np.ndarray, n: int) -> None:
    """The end effector's 4x4 pose for each of ``n`` configurations."""
    lib.chain_fk_batch(chain, _d(q_rad), _d(pose), n)


def chain_frames(chain: Any, q_rad: np.ndarray, frames: np.ndarray, n: int) -> None:
    """Every DH frame's 4x4 pose, then the end effector's, for each of ``n`` configurations."""
    lib.chain_frames_batch(chain, _d(q_rad), _d(frames), n)


def chain_points(chain: Any, q_rad: np.ndarray, local_point: np.ndarray, points: np.ndarray, n: int) -> None:
    """Point i (``local_point[i]`` in frame i + 1) in the world, for each of ``n`` configurations."""
    lib.chain_points_batch(chain, _d(q_rad), _d(local_point), _d(points), n)


def chain_jacobian(chain: Any, q_rad: np.ndarray, jac: np.ndarray, n: int) -> None:
    """The geometric Jacobian (6 x joints) for each of ``n`` configurations."""
    lib.chain_jacobian_batch(chain, _d(q_rad), _d(jac), ffi.NULL, n)


def chain_ik(chain: Any, lower: np.ndarray | None, upper: np.ndarray | None, options: dict[str, Any],
             poses: np.ndarray, start: np.ndarray | None, q: np.ndarray, success: np.ndarray,
             iterations: np.ndarray, restarts: np.ndarray, residual: np.ndarray, n: int) -> None:
    """Numerical IK (``chain_ik_options`` by field name) for ``n`` target poses."""
    lib.chain_ik_batch(chain, _d(lower), _d(upper), ffi.new("chain_ik_options *", options), _d(poses),
                       _d(start), _d(q), _i(success), _i(iterations), _i(restarts), _d(residual), n)


# -- the closed-form IK (csrc/kin/closed_ik.h) ---------------------------------------------------------
def rrr_ik(dims: np.ndarray, lower: np.ndarray | None, upper: np.ndarray | None, xyz: np.ndarray,
           q: np.ndarray, status: np.ndarray, singular: np.ndarray, n: int) -> None:
    """Every IK solution of the spatial RRR arm ``dims`` (d1, a1, a2, a3) for ``n`` targets."""
    lib.rrr_ik_batch(_d(dims), _d(lower), _d(upper), _d(xyz), _d(q), _i(status), _i(singular), n)


def planar3r_ik(links: np.ndarray, lower: np.ndarray | None, upper: np.ndarray | None, target: np.ndarray,
                q: np.ndarray, status: np.ndarray, singular: np.ndarray, n: int) -> None:
    """Both IK solutions of the planar 3R arm ``links`` for ``n`` targets (x, y, phi)."""
    lib.planar3r_ik_batch(_d(links), _d(lower), _d(upper), _d(target), _d(q), _i(status), _i(singular), n)


# -- rotations (csrc/kin/rotation.h): n 3x3 matrices -------------------------------------------------
def rotation_check(matrices: np.ndarray, tol: float, status: np.ndarray, deviation: np.ndarray,
                   n: int) -> None:
    """A ``ROT_*`` status and ``max |R R^T - I|`` per matrix."""
    lib.rot_check_batch(_d(matrices), float(tol), _i(status), _d(deviation), n)


def rotation_from_euler_zyx(angles_rad: np.ndarray, matrices: np.ndarray, n: int) -> None:
    """Rotation matrices from ZYX Euler angles (rad)."""
    lib.rot_euler_zyx_to_matrix_batch(_d(angles_rad), _d(matrices), n)


def rotation_to_euler_zyx(matrices: np.ndarray, angles_rad: np.ndarray, singular: np.ndarray, n: int) -> None:
    """ZYX Euler angles (rad) of rotation matrices, a gimbal-lock flag per matrix."""
    lib.rot_matrix_to_euler_zyx_batch(_d(matrices), _d(angles_rad), _i(singular), n)


def rotation_from_axis_angle(axis: np.ndarray, angle_rad: np.ndarray, matrices: np.ndarray,
                             status: np.ndarray, n: int) -> None:
    """Rotation matrices from axes and angles (rad), a ``ROT_*`` status per row."""
    lib.rot_axis_angle_to_matrix_batch(_d(axis), _d(angle_rad), _d(matrices), _i(status), n)


def rotation_to_axis_angle(matrices: np.ndarray, axis: np.ndarray, angle_rad: np.ndarray, n: int) -> None:
    """The axis and angle (rad) of rotation matrices."""
    lib.rot_matrix_to_axis_angle_batch(_d(matrices), _d(axis), _d(angle_rad), n)


# -- trajectory profiles (csrc/kin/traj_profiles.h) ----------------------------------------------------
def traj_min_duration(kind: int, q0_rad: float, qf_rad: float, vmax_rad_s: float,
                      amax_rad_s2: float) -> tuple[int, float]:
    """The shortest duration (s) of a rest-to-rest move within the limits, and its ``TRAJ_*`` status."""
    t = ffi.new("double *")
    status = lib.traj_min_duration(kind, q0_rad, qf_rad, vmax_rad_s, amax_rad_s2, t)
    return int(status), float(t[0])


def traj_segments(n: int) -> Any:
    """Room for ``n`` planned profiles (``traj_profile[n]``): segment i's joint j at ``i * joints + j``;
    each has ``duration_s``, ``q0_rad``, ``qf_rad``..."""
    return ffi.new("traj_profile[]", n)


def traj_plan_synchronized(segments: Any, offset: int, n_joints: int, kind: int, q0_rad: np.ndarray,
                           qf_rad: np.ndarray, duration_s: float, vmax: np.ndarray,
                           amax: np.ndarray) -> tuple[int, int]:
    """Plan one segment (every joint starting and stopping together) into ``segments[offset:]``:
    its ``TRAJ_*`` status and the joint that failed (``n_joints`` for the duration)."""
    failed = ffi.new("size_t *")
    status = lib.traj_plan_synchronized(segments + offset, n_joints, kind, _d(q0_rad), _d(qf_rad), duration_s,
                                        _d(vmax), _d(amax), failed)
    return int(status), int(failed[0])


def traj_plan_status(kind: int, q0_rad: float, qf_rad: float, duration_s: float, vmax: float,
                     amax: float) -> int:
    """Whether one joint's move can take exactly ``duration_s`` within its limits (``TRAJ_*``)."""
    return int(lib.traj_plan(ffi.new("traj_profile *"), kind, q0_rad, qf_rad, duration_s, vmax, amax))


def traj_evaluate(segments: Any, start_s: np.ndarray, n_joints: int, t_s: np.ndarray, q: np.ndarray,
                  qd: np.ndarray, qdd: np.ndarray, qddd: np.ndarray) -> None:
    """Position, velocity, acceleration and jerk of a planned path at each time of ``t_s``."""
    lib.traj_path_eval_many(segments, _d(start_s), start_s.size, n_joints, _d(t_s), t_s.size,
                            _d(q), _d(qd), _d(qdd), _d(qddd))


# -- the framework's generations (csrc/port/generations.c) and wasmtime ---------------------------------
def generation_rows() -> list[dict[str, Any]]:
    """Every row of generations.c, its fields by name (texts decoded)."""
    names = [name for name, _ in ffi.typeof("crs_generation").fields]
    rows = []
    for i in range(lib.crs_generation_count()):
        r = lib.crs_generation_at(i)
        values = [getattr(r, name) for name in names]
        rows.append({name: ffi.string(v).decode() if isinstance(v, ffi.CData) else int(v)
                     for name, v in zip(names, values)})
    return rows


def preload_wasmtime(library: str) -> bool:
    """Load wasmtime's C library (its path) into this process now; False when it cannot be."""
    return lib.crs_fw_wasm_preload(library.encode()) == 0


# -- the world's facts (csrc/plant/world.h, world_facts.h) ------------------------------------------
def world_columns() -> list[tuple[str, str, str, int, int]]:
    """The world row's quantities (``crs_world_columns``), in order: each one's name, unit, what it
    is, offset and width."""
    count = ffi.new("int32_t *")
    table = lib.crs_world_columns(count)
    return [(text_of(c.name), text_of(c.unit), text_of(c.what), int(c.offset), int(c.width))
            for c in (table[i] for i in range(count[0]))]


def world_fixture_names() -> tuple[str, ...]:
    """The fixtures with a force sensor, in C's order (``crs_world_fixture_name``)."""
    return tuple(text_of(lib.crs_world_fixture_name(i)) for i in range(lib.CRS_FIXTURES))


def egg_broken_by_name(code: int) -> str:
    """What broke the egg, for the row's ``egg_broken_by`` code (``crs_egg_broken_by_name``)."""
    return text_of(lib.crs_egg_broken_by_name(code))


def egg_flatten(size_m: np.ndarray, pos_m: np.ndarray) -> None:
    """Lay an egg geom flat in place (``crs_egg_flatten``): its half sizes and centre, 3 values each."""
    lib.crs_egg_flatten(_d(size_m), _d(pos_m))


def peg_depths(hole_xy_m: np.ndarray, top_z_m: float, radius_m: float, tips_m: np.ndarray,
               depth_m: np.ndarray, n: int) -> None:
    """How deep each of ``n`` tips (rows of x, y, z) is in the hole (``crs_peg_depths``)."""
    lib.crs_peg_depths(_d(hole_xy_m), top_z_m, radius_m, _d(tips_m), n, _d(depth_m))


def groove_nearest(corners_xy_m: np.ndarray, points_m: np.ndarray, n: int, stride: int,
                   segment: np.ndarray, offset_m: np.ndarray, along_m: np.ndarray) -> None:
    """The groove's nearest segment, distance and length along for each of ``n`` points (rows of
    ``stride`` values, x and y first): ``crs_groove_nearest_many``."""
    lib.crs_groove_nearest_many(_d(corners_xy_m), _d(points_m), n, stride, _i32(segment), _d(offset_m),
                                _d(along_m))


# -- bytes in C memory ---------------------------------------------------------------------------------
def read_bytes(cdata: Any, n: int) -> bytes:
    """The first ``n`` bytes at ``cdata`` (an array or pointer of the core's)."""
    return bytes(ffi.buffer(cdata, n))


def read_ints(cdata: Any, n: int) -> list[int]:
    """The first ``n`` integers of ``cdata`` (an integer array of the core's), in one call."""
    return ffi.unpack(cdata, n) if n > 0 else []


def write_bytes(cdata: Any, data: bytes) -> None:
    """Copy ``data`` to ``cdata`` (an array or pointer of the core's, with room for it)."""
    ffi.memmove(cdata, data, len(data))


def size_of(cdata_or_type: Any) -> int:
    """Bytes of a C value or type of the core's (``size_of("crs_shared")``)."""
    return int(ffi.sizeof(cdata_or_type))


def text_of(cdata: Any) -> str:
    """A NUL-terminated char array or pointer as text (untrusted bytes decoded, never raising)."""
    return ffi.string(cdata).decode("utf-8", "replace")


_NUMPY_TYPES = {"int64_t": "<i8", "int32_t": "<i4", "uint32_t": "<u4", "double": "<f8"}


def scope_log_columns() -> list[tuple[str, int, str, int]]:
    """The scope log's columns as the board writes them into the shared block (``crs_scope_log``,
    csrc/board/board.h): each one's name, the offset of its first value in ``crs_shared`` (bytes),
    its numpy type and its values per row, in the struct's order.

    >>> [(name, kind, width) for name, _, kind, width in scope_log_columns()][:2]
    [('tick', '<i8', 1), ('enc_rad', '<f8', 3)]
    """
    base, rows = ffi.offsetof("crs_shared", "log"), lib.CRS_LOG_CAPACITY
    return [(name, base + field.offset, _NUMPY_TYPES[field.type.item.cname], field.type.length // rows)
            for name, field in ffi.typeof("crs_scope_log").fields if field.type.kind == "array"]


class PageRows:
    """The page's packed rows of a chunk straight from a shared block's scope log
    (``crs_page_rows``, csrc/page/page_rows.h): one per run (it keeps the frame of the last frame
    sent, and a buffer it reuses). ``world``: where the egg's force, the scale's grams and the egg
    broken start in a world row (a world with fixtures), or None."""

    def __init__(self, every: int, world: tuple[int, int, int] | None) -> None:
        self.every = every
        self.world = ffi.new("crs_page_world *", world) if world is not None else ffi.NULL
        self.state = ffi.new("crs_page_state *", {"frame": -1})
        self._out: Any = None
        self._capacity = 0
        self._rows = -1
        """The most rows :attr:`_out` holds the fields of (its ``_capacity`` bytes)."""
        self._shared: Any = None
        self._log: Any = None

    def take(self, shared: Any) -> bytes:
        """The chunk message's ``frames`` and ``scope`` fields (``, "frames": ..., "scope": ...``)
        of the rows ``shared`` (a ``crs_shared *``) holds, which are taken off it (its count back to
        0); b"" when none is of a tick divisible by ``every``."""
        if shared is not self._shared:
            self._shared, self._log = shared, ffi.addressof(shared.log)
        log = self._log
        n = min(max(0, int(log.count)), lib.CRS_LOG_CAPACITY)
        if n > self._rows:  # (grown once or twice in a run: its chunks are alike)
            self._capacity = lib.crs_page_rows_capacity(n)
            self._out, self._rows = ffi.new("char[]", self._capacity), n
        size = lib.crs_page_rows(log, n, self.every, self.world, self.state, self._out, self._capacity)
        log.count = 0
        return ffi.buffer(self._out, size)[:] if size > 0 else b""

    @property
    def qpos_dh_rad(self) -> np.ndarray:
        """The last row's DH angles (of the last :meth:`take` that had rows)."""
        return np.array(ffi.unpack(self.state.qpos_dh_rad, 3))

    @property
    def egg_broken(self) -> bool:
        """Whether the last row's egg was broken."""
        return bool(self.state.egg_broken)


def shared_view(memory: Any) -> Any:
    """The ``crs_shared *`` (csrc/board/board.h) over ``memory`` (a writable buffer of
    ``size_of("crs_shared")`` bytes: the shared block's mapping)."""
    return ffi.cast("crs_shared *", ffi.from_buffer(memory))


# -- the board ----------------------------------------------------------------------------------------
class BoardLibrary:
    """The board's functions (csrc/board/board.h, board_config.h, the firmware ports) in one build
    of it: the core's (:func:`compiled_board`, running WebAssembly firmware) or a native lab's
    shared object (the board linked with the firmware: ``BoardLibrary(ffi, lib)`` with
    crslab/worker/board_ffi.py's declarations). A board (``crs_board *``), its settings and events
    are C values of the library's own; a board's fields are read as attributes."""

    def __init__(self, board_ffi: Any, board_lib: Any) -> None:
        self._ffi, self._lib = board_ffi, board_lib
        elements = board_ffi.typeof("crs_counter").elements  # value: name (csrc/board/board_config.h)
        self._counters = [elements[i].removeprefix("CRS_COUNTER_").lower() for i in sorted(elements)
                          if elements[i] != "CRS_COUNTERS"]
        self._counts = board_ffi.new("int64_t[]", len(self._counters))

    # -- C values of this library --------------------------------------------------------------
    def new(self, ctype: str, init: Any = None) -> Any:
        """A new, zeroed C value (``"crs_world *"``, ``"crs_mem_var[]"``), filled from ``init``."""
        return self._ffi.new(ctype, init)

    def pointer(self, ctype: str, address: int) -> Any:
        """A ``ctype`` (a pointer type) at ``address`` (a numpy array's ``.ctypes.data``, say)."""
        return self._ffi.cast(ctype, address)

    def address_of(self, pointer: Any) -> int:
        """The address a pointer holds."""
        return int(self._ffi.cast("uintptr_t", pointer))

    def text(self, value: str) -> Any:
        """``value`` as a NUL-terminated ``char[]`` (kept alive by the caller while C holds it)."""
        return self._ffi.new("char[]", value.encode())

    def bytes_view(self, data: bytes) -> Any:
        """A ``uint8_t[]`` onto ``data`` (no copy; kept alive by the caller)."""
        return self._ffi.from_buffer("uint8_t[]", data)

    def string(self, cdata: Any) -> str:
        """A NUL-terminated char array as text (untrusted bytes decoded, never raising)."""
        return self._ffi.string(cdata).decode("utf-8", "replace")

    def unpack(self, pointer: Any, n: int) -> list:
        """The first ``n`` values at ``pointer``."""
        return self._ffi.unpack(pointer, n)

    def size_of(self, ctype: str) -> int:
        """Bytes of a C type of this library."""
        return int(self._ffi.sizeof(ctype))

    def shared(self, memory: Any) -> Any:
        """The ``crs_shared *`` over ``memory`` (the shared block's mapping)."""
        return self._ffi.cast("crs_shared *", self._ffi.from_buffer(memory))

    # -- one board ------------------------------------------------------------------------------
    def new_board(self, generation: int, shared: Any) -> Any:
        """A new board of framework generation ``generation`` writing into ``shared``."""
        board = self._ffi.new("crs_board *")
        self._lib.crs_board_init(board, generation, shared)
        return board

    def configure(self, board: Any, settings: dict[str, Any]) -> None:
        """Give ``board`` a run's settings (``crs_board_settings`` by field name)."""
        self._lib.crs_board_configure(board, self._ffi.new("crs_board_settings *", settings))

    def attach_plant(self, board: Any, plant: dict[str, Any]) -> None:
        """Have ``board`` step MuJoCo's model and data (``crs_board_plant`` by field name)."""
        self._lib.crs_board_attach_plant(board, self._ffi.new("crs_board_plant *", plant))

    def attach_world(self, board: Any, config: Any) -> None:
        """Give ``board`` the world's fixtures (a filled ``crs_world_config *``: one assignment)."""
        self._lib.crs_board_attach_world(board, config)

    def attach_memory(self, board: Any, table: Any, count: int) -> None:
        """The lab's variables in C28x memory: ``count`` entries of ``table`` (``crs_mem_var[]``)."""
        self._lib.crs_board_attach_memory(board, table, count)

    def apply_event(self, board: Any, fields: dict[str, Any]) -> bool:
        """Carry out a scenario's event now (``crs_board_event`` by field name); False for a kind
        the board does not know."""
        return self._lib.crs_board_apply_event(board, self._ffi.new("crs_board_event *", fields)) == 0

    def run(self, board: Any, until_tick: int) -> int:
        """Run ``board`` to ``until_tick`` or an early stop: a ``CRS_RUN_*`` code."""
        return int(self._lib.crs_board_run(board, until_tick))

    def counters(self, board: Any) -> dict[str, int]:
        """The board's counters (``crs_counter``'s, by their names in lower case), in one call."""
        return dict(zip(self._counters, self.counter_values(board)))

    @property
    def counter_names(self) -> list[str]:
        """The counters' names (``crs_counter``'s, in lower case), in the order
        :meth:`counter_values` gives them."""
        return self._counters

    def counter_values(self, board: Any) -> list[int]:
        """The board's counters, in :attr:`counter_names`' order, in one call."""
        self._lib.crs_board_counters(board, self._counts)
        return self._ffi.unpack(self._counts, len(self._counters))

    def take_motor_board_events(self, board: Any) -> int:
        """How many motor-board events ``board`` noted since the last call (the reader took them)."""
        return int(self._lib.crs_board_take_motor_board_events(board))

    # -- the firmware's ports -----------------------------------------------------------------
    def native_attach(self, board: Any) -> int:
        """Start the native firmware linked with this board: 0, or ``CRS_RUN_TRAPPED``."""
        return int(self._lib.crs_fw_native_attach(board))

    def debug_break(self, tick: int) -> None:
        """Call ``crs_debug_break`` (a native board's), where a debugger stops, at ``tick``."""
        self._lib.crs_tick = tick
        self._lib.crs_debug_break(tick)

    def wasm_load(self, board: Any, options: dict[str, Any]) -> int:
        """Load a WebAssembly firmware into ``board`` (``crs_wasm_options`` by field name): 0, or
        ``CRS_RUN_TRAPPED`` with ``board.trap`` saying why."""
        return int(self._lib.crs_fw_wasm_load(board, self._ffi.new("crs_wasm_options *", options)))

    def wasm_compile(self, options: dict[str, Any]) -> str:
        """Compile a WebAssembly firmware with the boards' engine settings and write it to
        ``compiled_fd`` (``crs_wasm_options`` by field name; no board): empty, or why it could not."""
        error = self._ffi.new("char[]", 512)
        settings = self._ffi.new("crs_wasm_options *", options)
        if self._lib.crs_fw_wasm_compile(settings, error, len(error)) != 0:
            return self.string(error) or "wasmtime could not compile it"
        return ""

    def wasm_unload(self, board: Any) -> None:
        """Free ``board``'s firmware store (and its compiled module when no other board uses it)."""
        self._lib.crs_fw_wasm_unload(board)

    def wasm_module_held(self, key: str) -> bool:
        """Whether this process holds the compiled module of ``key`` (a load of it reads no file)."""
        return bool(self._lib.crs_fw_wasm_module_held(key.encode()))

    def wasm_module_refs(self, board: Any) -> int:
        """How many boards share ``board``'s compiled module."""
        return int(self._lib.crs_fw_wasm_module_refs(board))

    def wasm_memory(self, board: Any) -> tuple[int, int]:
        """The address and the size (bytes) of ``board``'s firmware memory."""
        size = self._ffi.new("uint64_t *")
        base = self._lib.crs_fw_wasm_memory(board, size)
        return int(self._ffi.cast("uintptr_t", base)), int(size[0])

    def wasm_variable(self, board: Any, name: str) -> int:
        """The firmware-memory address of the variable the module exports as ``name`` (0: none)."""
        return int(self._lib.crs_fw_wasm_variable(board, name.encode()))


def compiled_board() -> BoardLibrary:
    """The board compiled into the core (it runs WebAssembly firmware)."""
    global _COMPILED
    if _COMPILED is None:
        _COMPILED = BoardLibrary(ffi, lib)
    return _COMPILED


_COMPILED: BoardLibrary | None = None
