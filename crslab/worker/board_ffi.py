"""cffi declarations of the emulated board (csrc/board/board.h), for the native worker and the reader,
and its constants (phases, run codes, lab-symbol bits, trap kinds), so Python never writes them
again.

A native worker dlopens its lab's shared object (the board linked with the firmware) with these
declarations and the native port's (firmware_native.h), parsed from the headers (ABI mode). The
crslab process reads the shared-memory block and the constants through crslab._core, which holds
the board itself compiled from the same headers (API mode): no lab code is loaded, and no header is
parsed at run time (pycparser took about a tenth of a second of every command's start). A
WebAssembly worker runs the board in crslab._core.
"""

from __future__ import annotations

from functools import cache
from typing import Any

from cffi import FFI

from crslab import resources
from crslab.cheaders import cdef_from_header

BOARD_HEADERS = ("port/firmware_board.h", "kin/traj_profiles.h", "plant/drive.h", "plant/friction.h",
                 "plant/hand.h", "plant/plant_faults.h", "plant/push.h", "plant/world.h", "board/board.h",
                 "board/board_config.h")
"""board.h, the headers it includes (cffi reads no #include) and the board's configuration
(board_config.h), under csrc/."""


def board_ffi() -> Any:
    """The FFI holding every declaration of board.h (crslab._core's, compiled from :data:`BOARD_HEADERS`
    and the core's other headers)."""
    from crslab._core import ffi

    return ffi


@cache
def native_board_ffi() -> FFI:
    """board.h's declarations, the debugger's (debug.h) and the native firmware port's
    (crs_fw_native_attach): a native lab's shared object holds all of them."""
    ffi = FFI()
    for header in (*BOARD_HEADERS, "board/debug.h", "board/firmware_native.h"):
        ffi.cdef(cdef_from_header(resources.path("csrc", *header.split("/")).read_text()))
    return ffi


def shared_size() -> int:
    """Bytes of the shared block (``crs_shared``)."""
    return board_ffi().sizeof("crs_shared")


@cache
def board_constants() -> Any:
    """board.h's constants as attributes (``CRS_PHASE_LAB``, ``CRS_RUN_NAN_STRICT``,
    ``CRS_LAB_HAS_LAB``...), without loading any lab code.

    >>> board_constants().CRS_PHASE_PRINTING
    2
    """
    from crslab._core import lib

    return lib
