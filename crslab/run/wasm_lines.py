"""Which line of the lab a WebAssembly firmware was at, from the firmware's own debug information
(its DWARF ``.debug_line``), for an address wasmtime names without a line.

A firmware stopped by the deadline (an epoch interrupt) is stopped at a loop's head, an
instruction clang gives line 0 (no line of its own), so wasmtime's backtrace names the lab's file
and no line. The line program says which line the instructions after it belong to: the loop's
first line with a number. Only what a firmware's line program holds is read (DWARF 4 and 5, as
zig's clang writes them); anything else gives None.

>>> line_at(b"not a module", 0x10, "lab.c") is None
True
"""

from __future__ import annotations

import struct
from pathlib import PurePath

DW_LNS = range(1, 13)
"""The standard opcodes of a line program."""


def _leb(data: bytes, i: int, signed: bool) -> tuple[int, int]:
    """The LEB128 number at ``data[i]`` (``signed``: two's complement) and the index after it.

    >>> _leb(bytes([0xE5, 0x8E, 0x26]), 0, False), _leb(bytes([0xC0, 0xBB, 0x78]), 0, True)
    ((624485, 3), (-123456, 3))
    """
    value = shift = 0
    while True:
        byte = data[i]
        i += 1
        value |= (byte & 0x7F) << shift
        shift += 7
        if byte < 0x80:
            return (value - (1 << shift) if signed and byte & 0x40 else value), i


def _uleb(data: bytes, i: int) -> tuple[int, int]:
    return _leb(data, i, False)


def _sleb(data: bytes, i: int) -> tuple[int, int]:
    return _leb(data, i, True)


def sections(module: bytes) -> tuple[int, dict[str, bytes]]:
    """The code section's payload offset in ``module`` and its custom sections by name."""
    if module[:4] != b"\0asm":
        raise ValueError("not a WebAssembly module")
    i, code, custom = 8, -1, {}
    while i < len(module):
        kind = module[i]
        size, i = _uleb(module, i + 1)
        if kind == 0:
            n, j = _uleb(module, i)
            custom[module[j:j + n].decode("utf-8", "replace")] = module[j + n:i + size]
        elif kind == 10:
            code = i
        i += size
    return code, custom


def _form(data: bytes, i: int, form: int, line_str: bytes) -> tuple[object, int]:
    """One attribute of a DWARF 5 entry format (the forms a line table's header uses)."""
    if form == 0x08:  # DW_FORM_string
        end = data.index(b"\0", i)
        return data[i:end].decode("utf-8", "replace"), end + 1
    if form == 0x1F:  # DW_FORM_line_strp
        at = struct.unpack_from("<I", data, i)[0]
        return line_str[at:line_str.index(b"\0", at)].decode("utf-8", "replace"), i + 4
    if form == 0x0E:  # DW_FORM_strp (into .debug_str: the name is not needed)
        return "", i + 4
    if form == 0x0F:  # DW_FORM_udata
        return _uleb(data, i)
    if form in (0x0B, 0x05, 0x06, 0x07, 0x1E):  # data1, data2, data4, data8, data16
        return None, i + {0x0B: 1, 0x05: 2, 0x06: 4, 0x07: 8, 0x1E: 16}[form]
    if form == 0x09:  # DW_FORM_block
        n, i = _uleb(data, i)
        return None, i + n
    raise ValueError(f"form {form:#x} in a line table's header")


def _rows(unit: bytes, line_str: bytes, file_name: str) -> list[tuple[int, int, bool]]:
    """(address, line, ends a sequence) of every row of one unit's line program whose file is
    named ``file_name`` (or that ends a sequence)."""
    version = struct.unpack_from("<H", unit, 0)[0]
    i = 2
    if version >= 5:
        i += 2  # address size, segment selector size
    header_length = struct.unpack_from("<I", unit, i)[0]
    i += 4
    program = i + header_length
    min_inst, i = unit[i], i + 1
    if version >= 4:
        i += 1  # maximum operations per instruction
    i += 1  # default is_stmt
    line_base = struct.unpack_from("<b", unit, i)[0]
    line_range, opcode_base = unit[i + 1], unit[i + 2]
    lengths = list(unit[i + 3:i + 3 + opcode_base - 1])
    i += 3 + opcode_base - 1
    files: list[str] = []
    if version >= 5:
        for is_files in (False, True):
            count_formats, i = unit[i], i + 1
            formats = []
            for _ in range(count_formats):
                content, i = _uleb(unit, i)
                form, i = _uleb(unit, i)
                formats.append((content, form))
            count, i = _uleb(unit, i)
            for _ in range(count):
                name = ""
                for content, form in formats:
                    value, i = _form(unit, i, form, line_str)
                    if content == 1:  # DW_LNCT_path
                        name = str(value)
                if is_files:
                    files.append(name)
    else:
        while unit[i]:  # include directories
            i = unit.index(b"\0", i) + 1
        i += 1
        files.append("")  # DWARF 4 numbers files from 1
        while unit[i]:
            end = unit.index(b"\0", i)
            files.append(unit[i:end].decode("utf-8", "replace"))
            i = end + 1
            for _ in range(3):
                _, i = _uleb(unit, i)
    wanted = {k for k, f in enumerate(files) if PurePath(f).name == file_name}
    rows: list[tuple[int, int, bool]] = []
    address, line, file = 0, 1, 1
    i = program

    def emit(end: bool = False) -> None:
        if file in wanted or end:
            rows.append((address, line, end))

    while i < len(unit):
        op = unit[i]
        i += 1
        if op >= opcode_base:
            adjusted = op - opcode_base
            address += (adjusted // line_range) * min_inst
            line += line_base + adjusted % line_range
            emit()
        elif op == 0:  # extended
            n, i = _uleb(unit, i)
            sub = unit[i]
            if sub == 1:  # end_sequence
                emit(end=True)
                address, line, file = 0, 1, 1
            elif sub == 2:  # set_address
                address = int.from_bytes(unit[i + 1:i + n], "little")
            i += n
        elif op == 1:  # copy
            emit()
        elif op == 2:
            step, i = _uleb(unit, i)
            address += step * min_inst
        elif op == 3:
            step, i = _sleb(unit, i)
            line += step
        elif op == 4:
            file, i = _uleb(unit, i)
        elif op == 8:  # const_add_pc
            address += ((255 - opcode_base) // line_range) * min_inst
        elif op == 9:  # fixed_advance_pc
            address += struct.unpack_from("<H", unit, i)[0]
            i += 2
        else:  # set_column, negate_stmt, ...: their operands skipped
            for _ in range(lengths[op - 1] if op - 1 < len(lengths) else 0):
                _, i = _uleb(unit, i)
    return rows


def line_at(module: bytes, module_offset: int, file_name: str) -> int | None:
    """The line of ``file_name`` (a file's name, no folder) the instruction at ``module_offset``
    (an offset in the module, as wasmtime's backtraces give it) belongs to: its row's line, or for
    an instruction of line 0 the next row's with a line; None when the module says nothing of it."""
    try:
        code, custom = sections(module)
        lines, line_str = custom.get(".debug_line", b""), custom.get(".debug_line_str", b"")
        pc = module_offset - code
        i = 0
        while i + 4 <= len(lines):
            length = struct.unpack_from("<I", lines, i)[0]
            unit = lines[i + 4:i + 4 + length]
            i += 4 + length
            rows = _rows(unit, line_str, file_name)
            for k, (address, _, end) in enumerate(rows):
                nxt = rows[k + 1] if k + 1 < len(rows) else None
                if end or nxt is None or not address <= pc < nxt[0]:
                    continue
                for _, later, later_end in rows[k:]:
                    if later_end:
                        break
                    if later:
                        return later
        return None
    except (ValueError, IndexError, struct.error):
        return None
