"""Where the lab's global variables are in the worker, and in which C types, for both kinds of
firmware: the watched variables' ``get``/``set``, the expectations' reads, the scenarios' writes,
and the emulated C28x memory the course's MATLAB tools read and write (``crs_board.memory``).

- WebAssembly: a variable lives in the firmware's linear memory, at the address its export holds
  (the build exports every global of the lab file); its types are the C28x's widths, which the lab
  is compiled with (``int`` 16 bits, ``long`` 32, ``double`` 32; crslab/lab/c28x_ir.py). The
  memory's size is fixed, so an address and a size are checked once against it.
- native: a variable is the loaded shared object's symbol; its types are the host's; its size is
  the symbol's, as the dynamic loader knows it.

Everything read is data the firmware wrote; nothing here trusts it beyond its bounds.

"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from cffi import FFI

from crslab.lab.firmware import FRAMEWORK_VARIABLES, SIZES_SYMBOL
from crslab.lab.variables import HOST_TYPES, wasm_element_type
from crslab.os_support import loaded_symbol_size

if TYPE_CHECKING:
    from crslab._bindings import BoardLibrary
    from crslab.lab.build import LabBuild

FRAMEWORK_BYTES = {name: 4 if name == "matlabLock" else 2 for name in FRAMEWORK_VARIABLES}
"""The framework's own variables' bytes in a WebAssembly firmware: Simulink's inputs are ints."""

def native_element_type(ctype: str, pointer: bool = False) -> str | None:
    """The cffi type of one element of a variable of ``ctype`` in a native firmware."""
    if pointer:
        return None
    host = HOST_TYPES.get(ctype, ctype)
    return None if host.endswith("*") else host


class FirmwareMemory(Protocol):
    """The lab's variables in one loaded firmware."""

    def size_of(self, ctype: str) -> int:
        """Bytes of one ``ctype`` (an element type of :meth:`element_type`) in this firmware."""

    def pointer(self, ctype: str, address: int) -> Any:
        """A ``ctype`` (a pointer type) at ``address`` in this process, to read and write through."""

    def element_type(self, ctype: str, pointer: bool = False) -> str | None:
        """The cffi type of one element of ``ctype`` in this firmware (None: not readable)."""

    def address(self, name: str, nbytes: int) -> int | None:
        """The worker's address of the global ``name`` when ``nbytes`` of it lie in the firmware
        (None: not there, or smaller than that)."""


class WasmMemory:
    """A WebAssembly firmware's memory (``crs_fw_wasm_memory``, ``crs_fw_wasm_variable``), for the
    lab ``build`` (what its globals are called in the image, and the size of each)."""

    def __init__(self, board: BoardLibrary, sim: object, build: LabBuild) -> None:
        self._board, self._sim, self._image_name = board, sim, build.image_name
        self.base, self.size = board.wasm_memory(sim)
        # the size the compiler gave each of the lab's globals (the build's table, read once)
        self._sizes: dict[str, int] = {}
        table = self._offset(SIZES_SYMBOL)
        n = len(build.sized)
        if table and table + 4 * (n + 1) <= self.size:
            values = board.unpack(board.pointer("uint32_t *", self.base + table), n + 1)
            self._sizes = dict(zip(build.sized, values[1:]))

    def _offset(self, exported: str) -> int:
        return self._board.wasm_variable(self._sim, exported)

    def size_of(self, ctype: str) -> int:
        return self._board.size_of(ctype)

    def pointer(self, ctype: str, address: int) -> Any:
        return self._board.pointer(ctype, address)

    def element_type(self, ctype: str, pointer: bool = False) -> str | None:
        return wasm_element_type(ctype, pointer)

    def address(self, name: str, nbytes: int) -> int | None:
        offset = self._offset(self._image_name(name))
        if offset == 0 or offset + nbytes > self.size:
            return None
        # never trust the source's parse beyond the object the compiler laid out (the framework's own
        # variables, a 16-bit int or a float each, are not in the lab's table)
        size = self._sizes.get(name, FRAMEWORK_BYTES.get(name, 0))
        return self.base + offset if size >= nbytes else None


class NativeMemory:
    """A native firmware's globals: the loaded shared object's symbols."""

    def __init__(self, shared_object: Path, names: list[str]) -> None:
        self.ffi = FFI()
        declared = [n for n in dict.fromkeys(names) if n.isidentifier()]
        self.ffi.cdef("\n".join(f"extern char {n};" for n in declared))
        self._lib = self.ffi.dlopen(str(shared_object))  # already loaded: found by its path, never opened
        self._names = set(declared)

    def size_of(self, ctype: str) -> int:
        return int(self.ffi.sizeof(ctype))

    def pointer(self, ctype: str, address: int) -> Any:
        return self.ffi.cast(ctype, address)

    def element_type(self, ctype: str, pointer: bool = False) -> str | None:
        return native_element_type(ctype, pointer)

    def address(self, name: str, nbytes: int) -> int | None:
        if name not in self._names:
            return None
        try:
            address = int(self.ffi.cast("uintptr_t", self.ffi.addressof(self._lib, name)))
        except (AttributeError, KeyError, NotImplementedError, self.ffi.error):
            return None
        # never trust the source's parse beyond the object the compiler laid out
        size = loaded_symbol_size(address)
        return address if size is not None and size >= nbytes else None
