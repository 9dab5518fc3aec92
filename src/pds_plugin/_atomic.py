"""Atomic file writes: write to a temporary name beside the file, then rename into place.

A reader, a crash, a killed worker or a Ctrl-C then sees either the old file or the
complete new one, never a half-written file under the final name. ``os.replace`` is
atomic when both names are on the same file system, which a temporary name in the same
folder guarantees.
"""

from __future__ import annotations

import os
import re
import secrets
from contextlib import contextmanager
from pathlib import Path

__all__ = ["atomic_path", "leftovers"]

_TEMPORARY = ".tmp"
_LEFTOVER = re.compile(r"\.(?P<stem>.+)\.[0-9a-f]{16}\.tmp(?P<suffix>(\.[^.]*)?)")


@contextmanager
def atomic_path(path):
    """Yield a temporary path beside ``path``; on success rename it to ``path``.

    Write the file to the yielded path (a fresh random name, so concurrent writers of
    the same file, e.g. a task run twice, never share one). When the block ends
    normally the file replaces ``path`` in one step; when it raises (including
    ``KeyboardInterrupt``) the temporary file is removed and ``path`` is left as it was;
    an ``OSError`` about the temporary file is raised about ``path`` (the name the user
    chose). The temporary name is hidden and keeps the suffix,
    ``.STEM.RANDOM.tmp.SUFFIX`` (writers choose the format by the suffix), so it never
    looks like a finished output; :func:`leftovers` finds those of killed processes.

    Parameters
    ----------
    path : str or os.PathLike
        The final name. Its folder must exist.

    Yields
    ------
    pathlib.Path
        The temporary file to write.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "mesh.txt"
    >>> with atomic_path(out) as partial:
    ...     _ = partial.write_text("complete")
    >>> out.read_text(), sorted(p.name for p in out.parent.iterdir())
    ('complete', ['mesh.txt'])
    >>> try:
    ...     with atomic_path(out) as partial:
    ...         _ = partial.write_text("half")
    ...         raise KeyboardInterrupt
    ... except KeyboardInterrupt:
    ...     pass
    >>> out.read_text(), sorted(p.name for p in out.parent.iterdir())
    ('complete', ['mesh.txt'])
    """
    path = Path(path)
    # not mkstemp: its file is private (0600), the writer's open() gives the usual mode
    partial = path.with_name(f".{path.stem}.{secrets.token_hex(8)}{_TEMPORARY}{path.suffix}")
    try:
        yield partial
        os.replace(partial, path)
    except OSError as error:
        partial.unlink(missing_ok=True)
        if error.filename is not None and os.fspath(error.filename) == os.fspath(partial):
            # name the file the user asked for, not the temporary one they never chose
            raise type(error)(error.errno, f"cannot write {path}: {error.strerror}") from error
        raise
    except BaseException:
        partial.unlink(missing_ok=True)
        raise


def leftovers(folder) -> dict[Path, Path]:
    """The temporary files :func:`atomic_path` left in ``folder`` (only a process killed
    outright, e.g. by SIGKILL, leaves one), each with the final name it was meant for.
    A temporary file of a temporary file (a writer's own :func:`atomic_path` inside a
    caller's) is meant for the caller's final name. One listing of the folder, however
    many files it holds.

    Parameters
    ----------
    folder : str or os.PathLike

    Returns
    -------
    dict
        Temporary path -> the final path it was written for.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / ".mesh.0123456789abcdef.tmp.ply").write_bytes(b"half")
    >>> _ = (folder / "mesh.ply").write_bytes(b"whole")
    >>> _ = (folder / "..mesh.0123456789abcdef.tmp.fedcba9876543210.tmp.ply").touch()
    >>> sorted((p.name, final.name) for p, final in leftovers(folder).items())
    [('..mesh.0123456789abcdef.tmp.fedcba9876543210.tmp.ply', 'mesh.ply'), ('.mesh.0123456789abcdef.tmp.ply', 'mesh.ply')]
    """
    folder = Path(folder)
    found = {}
    for entry in os.scandir(folder):
        if entry.is_file(follow_symlinks=False) and _LEFTOVER.fullmatch(entry.name):
            found[folder / entry.name] = folder / _final_name(entry.name)
    return found


def _final_name(name: str) -> str:
    """The name a temporary name (maybe of another temporary name) was meant for."""
    while match := _LEFTOVER.fullmatch(name):
        name = f"{match['stem']}{match['suffix']}"
    return name
