"""Checks of the arguments users pass in, each written once.

Every check returns the value in the form the code uses (a float, an int, a float64
array, a Path) or raises a :class:`~pds_plugin.errors.PdsError` (an
``OSError`` for a directory that does not exist) naming the argument and what to do.
"""

from __future__ import annotations

import math
from importlib import import_module
from pathlib import Path

import numpy as np

from .errors import ArgumentError, ArgumentTypeError, EmptyMeshError, MissingDependencyError

__all__ = ["check_positive", "check_alpha", "check_positive_int", "check_seed", "check_grading", "check_vector",
           "check_output_directory", "check_has_triangles", "import_optional"]


def check_positive(value, name: str) -> float:
    """``value`` as a positive finite float.

    Parameters
    ----------
    value : float-like
    name : str
        The argument's name, for the message.

    Returns
    -------
    float

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a number.
    ArgumentError
        If it is not finite or not positive.

    Examples
    --------
    >>> check_positive("0.5", "tolerance")
    0.5
    >>> check_positive(-1, "alpha")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentError: alpha must be a positive finite number, got -1.0
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = None
    if number is None or isinstance(value, (bool, np.bool_)):     # True is not a length
        raise ArgumentTypeError(f"{name} must be a positive number, got {value!r}")
    if not math.isfinite(number) or number <= 0:
        raise ArgumentError(f"{name} must be a positive finite number, got {number}")
    return number


def check_alpha(alpha) -> float:
    """``alpha`` as a float, or an error saying why it can't be a radius.

    Parameters
    ----------
    alpha : float-like

    Returns
    -------
    float

    Raises
    ------
    ArgumentTypeError, ArgumentError
        As :func:`check_positive`.

    Examples
    --------
    >>> check_alpha(1)
    1.0
    """
    return check_positive(alpha, "alpha")


def check_positive_int(value, name: str) -> int:
    """``value`` as a positive int (``bool`` and floats refused).

    Parameters
    ----------
    value : int
    name : str
        The argument's name, for the message.

    Returns
    -------
    int

    Raises
    ------
    ArgumentError
        If ``value`` is not an integer >= 1.

    Examples
    --------
    >>> check_positive_int(3, "count")
    3
    >>> check_positive_int(2.5, "count")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentError: count must be a positive integer, got 2.5
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ArgumentError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def check_seed(seed) -> int:
    """``seed`` as an int >= 0, what ``numpy.random.default_rng`` takes; an
    :class:`~pds_plugin.errors.ArgumentError` otherwise (``bool`` refused).

    Examples
    --------
    >>> check_seed(-1)
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentError: seed must be an integer >= 0, got -1
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ArgumentError(f"seed must be an integer >= 0, got {seed!r}")
    return int(seed)


def check_grading(grading) -> float:
    """``grading``, the Lipschitz constant L of a graded mesh's radius field, as a float
    in (0, 1) (docs/graded.md).

    Examples
    --------
    >>> check_grading("0.2")
    0.2
    >>> check_grading(1.0)
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentError: grading must lie in (0, 1) (the Lipschitz constant of the radius field; 0.1-0.3 is usual), got 1.0
    """
    try:
        number = float(grading)
    except (TypeError, ValueError):
        number = None
    if number is None or isinstance(grading, (bool, np.bool_)):
        raise ArgumentTypeError(f"grading must be a number in (0, 1), got {grading!r}")
    if not 0 < number < 1:
        raise ArgumentError("grading must lie in (0, 1) (the Lipschitz constant of the radius "
                            f"field; 0.1-0.3 is usual), got {number}")
    return number


def check_vector(value, name: str, size: int = 3) -> np.ndarray:
    """``value`` as a finite float64 vector of ``size`` numbers.

    Parameters
    ----------
    value : array_like
    name : str
        The argument's name, for the message.
    size : int

    Returns
    -------
    (size,) float64 ndarray
        A new array: the caller's value is never modified.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not numbers.
    ArgumentError
        If it has the wrong shape or a NaN or infinite value.

    Examples
    --------
    >>> check_vector((0, 0, 1), "plane_normal").tolist()
    [0.0, 0.0, 1.0]
    """
    try:
        vector = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ArgumentTypeError(f"{name} must be {size} numbers (x, y, z), "
                                f"got {value!r}") from None
    if vector.shape != (size,):
        raise ArgumentError(f"{name} must be {size} numbers (x, y, z), got shape {vector.shape}")
    if not np.isfinite(vector).all():
        raise ArgumentError(f"{name} has NaN or infinite values: {vector.tolist()}")
    return vector


def check_output_directory(path) -> Path:
    """``path`` as a Path, after checking that its directory exists.

    Parameters
    ----------
    path : str or os.PathLike
        A file to be written.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    FileNotFoundError
        If the parent directory of ``path`` does not exist.
    IsADirectoryError
        If ``path`` is a directory.

    Examples
    --------
    >>> check_output_directory("no/such/dir/out.ply")
    Traceback (most recent call last):
    ...
    FileNotFoundError: cannot write no/such/dir/out.ply: directory no/such/dir does not exist; create it first
    """
    path = Path(path)
    if not path.parent.is_dir():
        raise FileNotFoundError(f"cannot write {path}: directory {path.parent} does not exist; "
                                "create it first")
    if path.is_dir():
        raise IsADirectoryError(f"cannot write {path}: it is a directory; give a file name")
    return path


def check_has_triangles(mesh, purpose: str) -> None:
    """Refuse a mesh without triangles where triangles are needed.

    Parameters
    ----------
    mesh : PlanarMesh
    purpose : str
        What the triangles are needed for, completing "... has no triangles <purpose>".

    Raises
    ------
    EmptyMeshError
        If ``mesh.faces`` is empty.

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> check_has_triangles(SimpleNamespace(faces=np.empty((0, 3))), "to plot")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.EmptyMeshError: namespace(faces=array([], shape=(0, 3), dtype=float64)) has no triangles to plot (alpha is probably too large for the region)
    """
    if len(mesh.faces) == 0:
        raise EmptyMeshError(f"{mesh!r} has no triangles {purpose} "
                             "(alpha is probably too large for the region)")


def import_optional(module: str, extra: str, needed_for: str):
    """Import an optional dependency, or say which pds_plugin extra installs it.

    Parameters
    ----------
    module : str
        The module to import, e.g. ``"matplotlib.backend_bases"``.
    extra : str
        The pds_plugin extra that installs it (``"plot"``, ``"meshlab"``).
    needed_for : str
        What needs it, completing "<package> is needed for ...".

    Returns
    -------
    module

    Raises
    ------
    MissingDependencyError
        If the module cannot be imported (also an ``ImportError``).

    Examples
    --------
    >>> import_optional("no_such_plotting_library", "plot", "the pictures")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.MissingDependencyError: no_such_plotting_library is needed for the pictures: pip install "pds_plugin[plot]"
    """
    try:
        return import_module(module)
    except ImportError as error:
        raise MissingDependencyError(f"{module.partition('.')[0]} is needed for {needed_for}: "
                                     f'pip install "pds_plugin[{extra}]"') from error

