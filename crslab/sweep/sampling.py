"""Where in the ranges a sweep's samples fall: unit fractions (0..1) per varied quantity, one row
per sample, from a seeded Latin hypercube or scrambled Sobol sequence (scipy.stats.qmc), or a
full grid. The same method, count and seed always give the same rows, in the same order.

>>> latin_hypercube(4, 2, seed=1).shape
(4, 2)
>>> grid(3, 2).tolist()
[[0.0, 0.0], [0.0, 0.5], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.5, 1.0], [1.0, 0.0], [1.0, 0.5], [1.0, 1.0]]
"""

from __future__ import annotations

import itertools
import warnings
from collections.abc import Sequence

import numpy as np

METHODS = ("lhs", "sobol")
"""Random sampling methods: Latin hypercube (each range cut into N equal strata, one sample in
each) and scrambled Sobol (a low-discrepancy sequence, best with a power-of-two count)."""
MAX_RUNS = 1_000_000


def latin_hypercube(n: int, dims: int, *, seed: int) -> np.ndarray:
    """``n`` Latin hypercube samples in ``[0, 1)^dims``, seeded.

    >>> u = latin_hypercube(8, 1, seed=3)
    >>> sorted((u[:, 0] * 8).astype(int).tolist())     # one sample in each eighth
    [0, 1, 2, 3, 4, 5, 6, 7]
    """
    from scipy.stats import qmc

    return qmc.LatinHypercube(d=dims, seed=np.random.default_rng(seed)).random(n)


def sobol(n: int, dims: int, *, seed: int) -> np.ndarray:
    """The first ``n`` points of a scrambled Sobol sequence in ``[0, 1)^dims``, seeded."""
    from scipy.stats import qmc

    with warnings.catch_warnings():  # a count that is not a power of two is allowed (and said so)
        warnings.simplefilter("ignore", UserWarning)
        return qmc.Sobol(d=dims, scramble=True, seed=np.random.default_rng(seed)).random(n)


def grid(levels: int, dims: int, fixed: Sequence[bool] = ()) -> np.ndarray:
    """Every combination of ``levels`` evenly spaced fractions (0 and 1 included) per quantity,
    the last quantity changing fastest; one level is the middle of each range. A ``fixed``
    quantity (a range of one value) takes one level.

    >>> grid(2, 2, fixed=[True, False]).tolist()
    [[0.0, 0.0], [0.0, 1.0]]
    """
    axis = np.linspace(0.0, 1.0, levels) if levels > 1 else np.array([0.5])
    fixed = list(fixed) + [False] * (dims - len(fixed))
    axes = [np.array([0.0]) if fixed[d] else axis for d in range(dims)]
    return np.array(list(itertools.product(*axes)), dtype=float).reshape(-1, dims)


def samples(
    method: str,
    dims: int,
    *,
    n: int | None = None,
    levels: int | None = None,
    seed: int = 1,
    fixed: Sequence[bool] = (),
) -> np.ndarray:
    """Unit fractions, one row per sample: ``method`` ``lhs``/``sobol`` with ``n`` samples, or
    ``grid`` with ``levels`` per quantity (one for each ``fixed`` one). Raises ``ValueError``
    for a count out of range."""
    if method == "grid":
        if levels is None or levels < 1:
            raise ValueError(f"--grid must be at least 1, got {levels}")
        varied = dims - sum(bool(f) for f in fixed)
        if levels**varied > MAX_RUNS:
            raise ValueError(
                f"--grid {levels} over {varied} quantities is {levels**varied} runs; at most "
                f"{MAX_RUNS} (use --samples for a random sample)"
            )
        return grid(levels, dims, fixed)
    if n is None or not 1 <= n <= MAX_RUNS:
        raise ValueError(f"--samples must be within 1 .. {MAX_RUNS}, got {n}")
    if method == "lhs":
        return latin_hypercube(n, dims, seed=seed)
    if method == "sobol":
        return sobol(n, dims, seed=seed)
    raise ValueError(f"no sampling method {method!r}; choose one of {', '.join(METHODS)}")
