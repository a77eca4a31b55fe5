"""The emulated C28x memory's table, filled in the worker once the firmware is loaded: where each
variable of the lab's layout lives in this process, so the board's MATLAB code reads and writes
the lab's real globals (``crs_board.memory``, csrc/board/c28x_memory.c).

A variable the worker cannot reach (a ``static``, which has no symbol; a pointer, whose value means
nothing on the C28x; one whose object in the firmware is smaller than the source's parse says, so
a host can never read or write past it) keeps its place and reads as zero.
"""

from __future__ import annotations

from crslab._bindings import BoardLibrary, constants
from crslab.lab.c28x_memory import KINDS, MemoryLayout
from crslab.worker.firmware_memory import FirmwareMemory


def fill_memory_table(sim: object, board: BoardLibrary, firmware: FirmwareMemory,
                      mem: MemoryLayout) -> list[object]:
    """Point the board ``sim`` (a ``crs_board *`` of ``board``) at a table of ``mem``'s variables in
    the loaded ``firmware`` (``crs_board_attach_memory``); returns what must stay alive as long as
    the table is used."""
    c = constants
    codes = {kind: getattr(c, f"CRS_MEM_{kind.upper()}") for kind in KINDS}
    table = board.new("crs_mem_var[]", max(1, len(mem.variables)))
    for i, v in enumerate(mem.variables):
        e = table[i]
        e.address, e.count, e.words = v.address, v.count, v.element_words
        e.kind, e.writable = codes[v.kind], int(v.writable)
        e.host_bytes = 1  # host: NULL (as the table was made) until the variable is found
        element = firmware.element_type(v.ctype) if v.is_global and v.kind != "opaque" else None
        if element is None:
            continue
        size = firmware.size_of(element)
        address = firmware.address(v.name, v.count * size)
        if address is not None:
            e.host_bytes = size
            e.host = board.pointer("void *", address)
    board.attach_memory(sim, table, len(mem.variables))
    return [table]
