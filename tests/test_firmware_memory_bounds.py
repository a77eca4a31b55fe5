"""A watched variable is read or written only where all of it lies inside the firmware's memory:
one that starts inside and ends past it is refused, even when the firmware's own table of sizes
(memory the lab can write) says it is that large."""

from types import SimpleNamespace

from cffi import FFI

from crslab.lab.firmware import SIZES_SYMBOL
from crslab.worker.firmware_memory import WasmMemory

MEMORY_BYTES = 64
TABLE_AT, VARIABLE_AT = 8, 48
"""The size table (a count, then one size per sized global) and the variable, by offset."""


class FakeBoard:
    """The board's firmware memory (``BoardLibrary.wasm_memory``, ``wasm_variable``) over a 64-byte
    memory of our own."""

    def __init__(self, claimed_size: int) -> None:
        self.ffi = FFI()
        self.memory = self.ffi.new(f"uint8_t[{MEMORY_BYTES}]")
        table = self.ffi.cast("uint32_t *", self.memory + TABLE_AT)
        table[0], table[1] = 1, claimed_size
        self.offsets = {SIZES_SYMBOL: TABLE_AT, "big": VARIABLE_AT}

    def wasm_memory(self, sim: object) -> tuple[int, int]:
        return int(self.ffi.cast("uintptr_t", self.memory)), MEMORY_BYTES

    def wasm_variable(self, sim: object, name: str) -> int:
        return self.offsets.get(name, 0)

    def pointer(self, ctype: str, address: int) -> object:
        return self.ffi.cast(ctype, address)

    def unpack(self, pointer: object, n: int) -> list:
        return self.ffi.unpack(pointer, n)  # type: ignore[arg-type]


def memory(claimed_size: int) -> WasmMemory:
    build = SimpleNamespace(image_name=lambda name: name, sized=["big"])
    return WasmMemory(FakeBoard(claimed_size), object(), build)  # type: ignore[arg-type]


def test_a_variable_that_ends_past_the_memory_is_refused_whatever_its_table_says():
    m = memory(claimed_size=1000)  # the table (the lab's to overwrite) claims 1000 bytes
    assert m.address("big", 16) == m.base + VARIABLE_AT  # bytes 48..63: the last byte is inside
    assert m.address("big", 17) is None  # 48..64: one byte past the end
    assert m.address("big", 32) is None


def test_a_variable_larger_than_its_compiled_size_is_refused():
    m = memory(claimed_size=8)
    assert m.address("big", 8) == m.base + VARIABLE_AT
    assert m.address("big", 12) is None  # inside the memory, but past the object
    assert m.address("missing", 4) is None
