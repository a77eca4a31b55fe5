"""crslab: run a CRS-arm robotics lab's C file on a laptop, against a simulated arm.

The compiled C core lives in ``crslab._core`` (``ffi`` and ``lib`` only); every other module
wraps it with numpy arrays in and out.
"""

__version__ = "0.1.0"
