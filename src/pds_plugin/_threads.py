"""How many threads the compiled kernels of this process use.

Processes that share a machine's cores (a local pool, Dask workers) each run their
kernels on one thread, or they fight over the cores. This module is the one place that
knows how the kernels are threaded: numba reads ``NUMBA_NUM_THREADS`` when it is first
imported, and ``numba.set_num_threads`` lowers the count once it is running.
"""

from __future__ import annotations

import os
import sys

__all__ = ["limit_kernel_threads"]


def limit_kernel_threads(count: int = 1) -> None:
    """Run this process's kernels on at most ``count`` threads (the calling thread's
    kernels, once the kernels are loaded).

    Parameters
    ----------
    count : int

    Examples
    --------
    >>> limit_kernel_threads(1)
    >>> os.environ["NUMBA_NUM_THREADS"]
    '1'
    """
    os.environ["NUMBA_NUM_THREADS"] = str(count)       # for a numba not imported yet
    numba = sys.modules.get("numba")
    if numba is not None:
        numba.set_num_threads(min(count, numba.config.NUMBA_NUM_THREADS))
