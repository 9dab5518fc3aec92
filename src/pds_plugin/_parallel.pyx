# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
"""How many threads the compiled kernels use.

Kernel conventions (every ``_*_kernels.pyx``): typed memoryviews (``const`` for inputs,
which may be read-only), bounds and wraparound checks off, ``cdivision`` on (every index
is non-negative and no divisor is zero). A parallel loop is
``prange(n, nogil=True, schedule="dynamic", chunksize=CHUNK, num_threads=threads_for(n))``:
each iteration writes only its own outputs, so the result does not depend on the thread
count, and dynamic chunks let a thread the OS takes away from us hand its work to the
others, so a busy machine costs no more than one thread would. Float expressions are
written in the order of the numba kernels they replace and built with
``-ffp-contract=off`` (no fused multiply-add): the results are the same bit for bit.

Without OpenMP at build time the ``prange`` loops run serially; ``openmp`` says which.

>>> from pds_plugin import _parallel
>>> previous = _parallel.set_threads(1)
>>> _parallel.get_threads()
1
>>> _ = _parallel.set_threads(previous)
"""

import os

cdef extern from *:
    """
    #ifdef _OPENMP
    #define PDS_OPENMP 1
    #else
    #define PDS_OPENMP 0
    #endif
    """
    const int PDS_OPENMP

openmp = bool(PDS_OPENMP)
"""True if the kernels were built with OpenMP (else every loop runs in one thread)."""

cdef Py_ssize_t _MIN_WORK = 2048
MIN_WORK_PER_THREAD = _MIN_WORK
"""A loop of n iterations uses at most n // MIN_WORK_PER_THREAD threads, so short loops
run serial (docs/engine.md has the timings against one thread)."""

cdef int _threads = 1


cdef int threads_for(Py_ssize_t work) noexcept nogil:
    """The threads a parallel loop of ``work`` iterations uses: 1 for small loops."""
    cdef Py_ssize_t useful = work // _MIN_WORK
    if useful < 2:
        return 1
    return <int>min(<Py_ssize_t>_threads, useful)


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity), at least 1."""
    try:
        return max(len(os.sched_getaffinity(0)), 1)
    except AttributeError:          # no sched_getaffinity (macOS, Windows)
        return os.cpu_count() or 1


def get_threads() -> int:
    """The most threads a kernel uses."""
    return _threads


def set_threads(n=None) -> int:
    """Let the kernels use at most ``n`` threads; ``None`` means the environment
    variable ``PDS_THREADS`` if set, else every core available to the process. Returns
    the previous setting. Process-pool workers call ``set_threads(1)``: the pool already
    keeps the cores busy."""
    global _threads
    previous = _threads
    if n is None:
        n = os.environ.get("PDS_THREADS") or available_cores()
    try:
        n = int(n)
    except (TypeError, ValueError):
        raise ValueError(f"the thread count must be a positive integer, got {n!r}") from None
    if n < 1:
        raise ValueError(f"the thread count must be a positive integer, got {n}")
    _threads = n if PDS_OPENMP else 1
    return previous


set_threads()
