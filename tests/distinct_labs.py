"""Many distinct labs, made fast: one lab built once, then copies of its firmware that differ in
one constant (the text each prints first, ``variant 000123``), each with its compiled module kept
where the board keeps it, made by the same edit of the board's own compilation of the lab and
sealed as the board's are. Each is a module of its own to a worker (its own digest, its own
bytes, its own text printed), which the worker loads (some 5 ms) rather than compiles (0.1 s), and
no zig build runs but the first (0.3 s): a thousand labs in seconds."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from crslab.cache import SEAL_SUFFIX, write_sealed
from crslab.run.assemble import make_config
from crslab.run.board_run import BoardRun
from crslab.worker.config import RunConfig
from crslab.worker.wasm_runtime import WasmImage

MARKER = b"variant 000000"
TEXT = """/* Test lab: one of many that differ only in the text they print first. */
#include <tistdtypes.h>
#include <coecsl.h>
#include "user_includes.h"

float offset_Enc2_rad = -0.42;
float offset_Enc3_rad = 0.24;
long mycount = 0;
char variant[] = "variant 000000";

void lab(float theta1motor, float theta2motor, float theta3motor, float *tau1, float *tau2,
         float *tau3, int error)
{
    *tau1 = 0;
    *tau2 = 0;
    *tau3 = 0;
    if ((mycount % 500) == 0) SWI_post(&SWI_printf);
    mycount++;
}

void printing(void)
{
    serial_printf(&SerialA, "%s count %ld\\n\\r", variant, mycount);
}
"""


class DistinctLabs:
    """Variants of one lab in ``folder``: :meth:`make` the ``i``-th (its run's configuration, no
    startup delay), :meth:`remove` its files once it ran."""

    def __init__(self, folder: Path) -> None:
        folder.mkdir(parents=True, exist_ok=True)
        self.folder = folder
        base = folder / "distinct.c"
        base.write_text(TEXT)
        self.config = make_config(base, "tour", startup_delay=False)
        self.wasm = self.config.build.image.read_bytes()
        kept = WasmImage.read(self.config.build.image).compiled_path()
        assert kept is not None, "the build cache cannot be used"
        if not kept.exists():
            with BoardRun(self.config):  # the board compiles the module and keeps it
                pass
        self.cwasm = kept.read_bytes()
        assert self.wasm.count(MARKER) == 1 and self.cwasm.count(MARKER) == 1

    @staticmethod
    def printed(i: int) -> bytes:
        """What the ``i``-th variant prints on its first line."""
        return b"variant %06d count 1\n\r" % i

    def make(self, i: int) -> RunConfig:
        """The ``i``-th variant's run (0 < ``i`` < 1,000,000)."""
        marker = b"variant %06d" % i
        image = self.folder / f"variant{i}.wasm"
        write_sealed(image, self.wasm.replace(MARKER, marker))  # sealed as a build seals its firmware
        kept = WasmImage.read(image).compiled_path()
        assert kept is not None
        write_sealed(kept, self.cwasm.replace(MARKER, marker))
        return dataclasses.replace(self.config, build=dataclasses.replace(self.config.build, image=image))

    @staticmethod
    def remove(config: RunConfig) -> None:
        """Remove a variant's firmware and its compiled module."""
        kept = WasmImage.read(config.build.image).compiled_path()
        for path in (config.build.image, kept):
            if path is not None:
                path.unlink(missing_ok=True)
                path.with_name(path.name + SEAL_SUFFIX).unlink(missing_ok=True)
