"""cffi declarations of the emulated board (csrc/board/board.h and the headers it includes) for a
native worker: it dlopens its lab's shared object (the board linked with the firmware) with these
declarations and the native port's (firmware_native.h), parsed from the headers (ABI mode), and
calls it through :class:`crslab._bindings.BoardLibrary`, as a WebAssembly worker calls the board
compiled into the C core. Nothing else parses a header at run time (pycparser takes about a tenth
of a second).
"""

from __future__ import annotations

from functools import cache

from cffi import FFI

from crslab import resources
from crslab.cheaders import cdef_from_header

BOARD_HEADERS = ("port/firmware_board.h", "kin/traj_profiles.h", "plant/drive.h", "plant/friction.h",
                 "plant/hand.h", "plant/plant_faults.h", "plant/push.h", "plant/world.h", "board/board.h",
                 "board/board_config.h")
"""board.h, the headers it includes (cffi reads no #include) and the board's configuration (board_config.h),
under csrc/."""


@cache
def native_board_ffi() -> FFI:
    """board.h's declarations, the debugger's (debug.h) and the native firmware port's
    (crs_fw_native_attach): a native lab's shared object holds all of them."""
    ffi = FFI()
    for header in (*BOARD_HEADERS, "board/debug.h", "board/firmware_native.h"):
        ffi.cdef(cdef_from_header(resources.path("csrc", *header.split("/")).read_text()))
    return ffi
