"""Helpers that move numpy arrays across the cffi boundary as whole buffers."""

from __future__ import annotations

import numpy as np

from crslab._core import ffi


def as_rows(values: object, width: int, name: str) -> np.ndarray:
    """Return ``values`` as a C-contiguous float64 array whose last axis has ``width`` entries.

    >>> as_rows([1, 2, 3], 3, "q").shape
    (3,)
    """
    arr = np.ascontiguousarray(values, dtype=np.float64)
    if arr.ndim == 0 or arr.shape[-1] != width:
        raise ValueError(f"{name} must have shape (..., {width}), got {arr.shape}")
    return arr


def dptr(arr: np.ndarray) -> object:
    """A ``double *`` onto a C-contiguous float64 array (no copy)."""
    return ffi.cast("double *", ffi.from_buffer(arr))


def iptr(arr: np.ndarray) -> object:
    """An ``int *`` onto a C-contiguous int32 array (no copy)."""
    return ffi.cast("int *", ffi.from_buffer(arr))
