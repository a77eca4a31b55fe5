"""numpy arrays as the C core takes them (crslab/_bindings.py): C-contiguous float64 rows."""

from __future__ import annotations

import numpy as np


def as_rows(values: object, width: int, name: str) -> np.ndarray:
    """Return ``values`` as a C-contiguous float64 array whose last axis has ``width`` entries.

    >>> as_rows([1, 2, 3], 3, "q").shape
    (3,)
    """
    arr = np.ascontiguousarray(values, dtype=np.float64)
    if arr.ndim == 0 or arr.shape[-1] != width:
        raise ValueError(f"{name} must have shape (..., {width}), got {arr.shape}")
    return arr
