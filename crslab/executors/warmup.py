"""What the fork server of :mod:`crslab.executors.local` prepares once, by importing this module,
so that no job process prepares it again: the compiler's identity (``cc --version``, a
subprocess) and the board's cffi declarations. A missing compiler is left for the job that needs
it to say."""

from crslab.lab.build import LabBuildError, compiler
from crslab.sim.board_ffi import board_ffi

try:
    compiler()
except LabBuildError:
    pass
board_ffi()
