"""MuJoCo's C library as crslab's C tick calls it: the address of ``mj_step`` and the library's
global stage timer.

The tick (``csrc/board/tick.c``) calls ``mj_step`` of the very ``libmujoco`` the ``mujoco`` Python
package loaded, through a function pointer. Importing ``mujoco`` sets that library's ``mjcb_time``
callback (the Python bindings fill ``mjData.timer`` for their profiler), and with it set every
``mj_step`` reads the clock at the start and end of each of its stages, about a fifth of a step
for the CRS arm. A run never reads ``mjData.timer``: :func:`stop_stage_timers` clears the
callback, which changes no state, only the timers.

>>> stop_stage_timers()
>>> stage_timers_on()
False
"""

from __future__ import annotations

import ctypes
import functools
from pathlib import Path

from crslab import os_support


@functools.cache
def libmujoco() -> ctypes.CDLL:
    """The ``libmujoco`` the ``mujoco`` package loaded (opened again by path: the same library)."""
    import mujoco

    lib = os_support.mujoco_library(Path(mujoco.__file__).parent)
    if lib is None:
        raise RuntimeError("libmujoco was not found in the mujoco package")
    return ctypes.CDLL(str(lib))


def mj_step_address() -> int:
    """Address of MuJoCo's C ``mj_step`` in the library the mujoco package loaded."""
    address = ctypes.cast(libmujoco().mj_step, ctypes.c_void_p).value
    assert address is not None
    return address


def _timer_callback() -> ctypes.c_void_p:
    return ctypes.c_void_p.in_dll(libmujoco(), "mjcb_time")


def stop_stage_timers() -> None:
    """Clear ``mjcb_time`` in this process: ``mj_step`` stops timing its stages (``mjData.timer``
    stays zero); the physics is the same, bit for bit."""
    _timer_callback().value = None


def stage_timers_on() -> bool:
    """Whether ``mj_step`` times its stages in this process (``mjcb_time`` is set)."""
    return _timer_callback().value is not None
