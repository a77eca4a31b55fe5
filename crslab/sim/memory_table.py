"""The emulated C28x memory's table, filled in the worker once the lab is loaded: where each
variable of the lab's layout lives in this process, so the board's MATLAB code reads and writes
the lab's real globals (``crs_sim.memory``, csrc/sim/c28x_memory.c).

A variable the worker cannot reach (a ``static``, which has no dynamic symbol; a pointer, whose
host value means nothing on the C28x; one whose loaded object is smaller than the source's parse
says, so a host can never read or write past it) keeps its place and reads as zero.
"""

from __future__ import annotations

from pathlib import Path

from cffi import FFI

from crslab.host_tools.c28x_memory import KINDS, MemoryLayout, PlacedVariable
from crslab.os_support import loaded_symbol_size
from crslab.sim.board_ffi import board_constants


def _declaration(v: PlacedVariable) -> str:
    return f"extern {v.host_ctype} {v.name}{f'[{v.count}]' if v.is_array else ''};"


def _declared(variables: list[PlacedVariable]) -> FFI:
    """An FFI declaring ``variables`` (those cffi cannot declare are left out)."""
    ffi = FFI()
    try:
        ffi.cdef("\n".join(map(_declaration, variables)))
        return ffi
    except Exception:  # noqa: BLE001 - some declaration cffi refuses: declare them one by one
        ffi = FFI()
        for v in variables:
            one = FFI()
            try:
                one.cdef(_declaration(v))
            except Exception:  # noqa: BLE001 - that one stays unreachable
                continue
            ffi.cdef(_declaration(v))
        return ffi


def fill_memory_table(sim: object, board: FFI, shared_object: Path, mem: MemoryLayout) -> list[object]:
    """Point ``sim.memory`` (a ``crs_sim *``) at a table of ``mem``'s variables in the loaded
    ``shared_object``; returns what must stay alive as long as the table is used."""
    c = board_constants()
    codes = {kind: getattr(c, f"CRS_MEM_{kind.upper()}") for kind in KINDS}
    reachable = [v for v in mem.variables if v.is_global and v.kind != "opaque"]
    names = {v.name for v in reachable}
    ffi = _declared(reachable)
    lib = ffi.dlopen(str(shared_object))  # already loaded: found by its path, never opened
    table = board.new("crs_mem_var[]", max(1, len(mem.variables)))
    for i, v in enumerate(mem.variables):
        e = table[i]
        e.address, e.count, e.words = v.address, v.count, v.element_words
        e.kind, e.writable = codes[v.kind], int(v.writable)
        e.host_bytes, e.host = 1, board.NULL
        if v.name in names:
            try:
                address = int(ffi.cast("uintptr_t", ffi.addressof(lib, v.name)))
                e.host_bytes = ffi.sizeof(v.host_ctype)
                # never trust the source's parse beyond the object the compiler laid out
                size = loaded_symbol_size(address)
                if size is not None and size >= v.count * e.host_bytes:
                    e.host = board.cast("void *", address)
            except (AttributeError, KeyError, NotImplementedError, ffi.error):
                e.host = board.NULL  # not in the library after all: reads 0
    sim.memory.vars = table  # type: ignore[attr-defined]
    sim.memory.count = len(mem.variables)  # type: ignore[attr-defined]
    return [ffi, lib, table]
