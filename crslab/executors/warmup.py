"""What the fork server of :mod:`crslab.executors.local` prepares once, by importing this module,
so that no job process prepares it again: the compiler's identity (``cc --version``, a
subprocess), the board's C core and wasmtime's library (each lab worker a job forks
starts with it loaded). A missing compiler or wasmtime is left for the job that needs it to say."""

from crslab import _bindings
from crslab.lab.build import LabBuildError, compiler
from crslab.worker.wasm_runtime import preload

try:
    compiler()
except LabBuildError:
    pass
_bindings.compiled_board()
preload()
