"""Silence what C and C++ libraries print straight to the process's stdout and stderr."""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys

__all__ = ["silenced"]


def _flush_streams() -> None:
    """Flush Python's and C's buffered stdout/stderr into the descriptors they use now."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(AttributeError, ValueError, OSError):
            stream.flush()
    with contextlib.suppress(OSError, AttributeError, TypeError):   # no C runtime this way
        ctypes.CDLL(None).fflush(None)


@contextlib.contextmanager
def silenced():
    """Send everything written to file descriptors 1 and 2 to the null device.

    MeshLab, qhull and other C++ code print straight to the process's stdout/stderr,
    past ``sys.stdout`` (so ``contextlib.redirect_stdout`` cannot catch them, PyMeshLab
    issues #222, #267, #328). This swaps the file descriptors themselves and restores
    them on exit, exceptions included. Python exceptions still carry their messages.
    The descriptors are process-wide: other threads writing meanwhile are silenced too.

    Yields
    ------
    None

    Examples
    --------
    >>> import os
    >>> with silenced():
    ...     _ = os.write(1, b"not shown\\n")
    """
    _flush_streams()               # what was written before still reaches the terminal
    try:
        saved = [os.dup(1), os.dup(2)]
    except OSError:                # no descriptors 1/2 (e.g. pythonw): nothing to silence
        yield
        return
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        os.dup2(null, 2)
        yield
    finally:
        _flush_streams()           # what was buffered inside goes to the null device
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (null, *saved):
            os.close(fd)
