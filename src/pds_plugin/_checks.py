"""Checks of the arguments users pass in, each written once.

Every check returns the value in the form the code uses (a float, an int, a float64
array, a Path) or raises a :class:`~pds_plugin.errors.PdsError` (an
``OSError`` for a directory that does not exist) naming the argument and what to do.
"""

from __future__ import annotations

import math
import os
from importlib import import_module
from pathlib import Path

import numpy as np

from .errors import ArgumentError, ArgumentTypeError, EmptyMeshError, MissingDependencyError

__all__ = ["check_positive", "check_alpha", "check_positive_int", "check_seed", "check_grading",
           "check_vector", "check_instance", "check_planar_mesh", "check_flag", "check_path",
           "check_faces", "check_output_directory", "check_has_triangles", "import_optional"]


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
    pds_plugin.errors.ArgumentError: grading must lie in (0, 1) (the Lipschitz constant of the radius field; 0.1-0.4 is usual), got 1.0
    """
    try:
        number = float(grading)
    except (TypeError, ValueError):
        number = None
    if number is None or isinstance(grading, (bool, np.bool_)):
        raise ArgumentTypeError(f"grading must be a number in (0, 1), got {grading!r}")
    if not 0 < number < 1:
        raise ArgumentError("grading must lie in (0, 1) (the Lipschitz constant of the radius "
                            f"field; 0.1-0.4 is usual), got {number}")
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


def check_instance(value, kind: type, who: str, make: str):
    """``value`` itself if it is a ``kind`` (a pds_plugin class), else a clear error.

    Parameters
    ----------
    value : object
    kind : type
    who : str
        The function that needs it, for the message.
    make : str
        How to make one, for the message.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a ``kind``.

    Examples
    --------
    >>> check_instance("a square", dict, "poisson_disc", "dict()")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentTypeError: poisson_disc needs a pds_plugin.dict, got str; make one with dict()
    """
    if not isinstance(value, kind):
        raise ArgumentTypeError(f"{who} needs a pds_plugin.{kind.__name__}, got "
                                f"{type(value).__name__}; make one with {make}")
    return value


def check_planar_mesh(value, who: str):
    """``value`` itself if it has a PlanarMesh's attributes, else a clear error (by its
    attributes: the analysis and sink layers cannot import the mesh layer's class back).

    Parameters
    ----------
    value : object
    who : str
        The function that needs the mesh, for the message.

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a mesh.

    Examples
    --------
    >>> check_planar_mesh(None, "topology_report")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentTypeError: topology_report needs a pds_plugin.PlanarMesh, got NoneType; make one with pds_plugin.mesh_region(region, alpha)
    """
    if not all(hasattr(value, name) for name in ("vertices", "faces", "on_boundary", "region",
                                                  "alpha")):
        raise ArgumentTypeError(f"{who} needs a pds_plugin.PlanarMesh, got "
                                f"{type(value).__name__}; make one with "
                                f"pds_plugin.mesh_region(region, alpha)")
    return value


def check_flag(value, name: str) -> bool:
    """``value`` if it is a bool (``True``/``False``, also numpy's), else a clear error.

    A string such as ``"no"`` is truthy, so it is refused rather than read as True.

    Parameters
    ----------
    value : bool
    name : str
        The argument's name, for the message.

    Returns
    -------
    bool

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a bool.

    Examples
    --------
    >>> check_flag("no", "repair")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentTypeError: repair must be True or False, got 'no'
    """
    if not isinstance(value, (bool, np.bool_)):
        raise ArgumentTypeError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def check_path(value, name: str = "path") -> str:
    """``value`` as a file system path (str), else a clear error.

    Parameters
    ----------
    value : str or os.PathLike
    name : str
        The argument's name, for the message.

    Returns
    -------
    str

    Raises
    ------
    ArgumentTypeError
        If ``value`` is not a str or an os.PathLike (bytes are refused too).

    Examples
    --------
    >>> check_path(None)
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentTypeError: path must be a file name (str or pathlib.Path), got None
    """
    try:
        path = os.fspath(value)
    except TypeError:
        path = None
    if not isinstance(path, str):
        raise ArgumentTypeError(f"{name} must be a file name (str or pathlib.Path), "
                                f"got {value!r}")
    return path


def check_faces(faces, vertex_count: int) -> np.ndarray:
    """``faces`` as a new (m, 3) int64 array of indices into ``vertex_count`` vertices.

    Parameters
    ----------
    faces : (m, 3) array_like of int
    vertex_count : int

    Returns
    -------
    (m, 3) int64 ndarray

    Raises
    ------
    ArgumentTypeError
        If ``faces`` are not integers.
    ArgumentError
        If they are not triples, or an index is negative or past the last vertex (the
        kernels would read memory that is not a vertex).

    Examples
    --------
    >>> check_faces([[0, 1, 3]], 3)
    Traceback (most recent call last):
    ...
    pds_plugin.errors.ArgumentError: face 0 refers to vertex 3, but there are 3 vertices (indices 0 to 2)
    """
    array = np.asarray(faces)
    if array.size and not np.issubdtype(array.dtype, np.integer):
        raise ArgumentTypeError(f"faces must be integer vertex indices, got {array.dtype}")
    array = np.array(array, dtype=np.int64)
    if array.size % 3 or (array.ndim != 2 and array.size):
        raise ArgumentError(f"faces must be an (m, 3) array of vertex indices, got shape "
                            f"{array.shape}")
    array = array.reshape(-1, 3)
    bad = np.flatnonzero(((array < 0) | (array >= vertex_count)).any(axis=1))
    if len(bad):
        index = array[bad[0]][(array[bad[0]] < 0) | (array[bad[0]] >= vertex_count)][0]
        raise ArgumentError(f"face {bad[0]} refers to vertex {index}, but there are "
                            f"{vertex_count} vertices (indices 0 to {vertex_count - 1})")
    return array


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
    NotADirectoryError
        If the parent of ``path`` is a file.
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
    if path.parent.exists() and not path.parent.is_dir():
        raise NotADirectoryError(f"cannot write {path}: {path.parent} is a file, not a "
                                 "directory")
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
    >>> square = SimpleNamespace(bounds=(0, 0, 2, 1))
    >>> check_has_triangles(SimpleNamespace(faces=np.empty((0, 3)), vertices=np.zeros((1, 2)),
    ...                                     alpha=5.0, region=square), "to plot")
    Traceback (most recent call last):
    ...
    pds_plugin.errors.EmptyMeshError: the mesh has 1 sample and no triangles to plot: alpha=5 is probably too large for the region (it spans 2 x 1); use a smaller alpha
    """
    if len(mesh.faces) == 0:
        xmin, ymin, xmax, ymax = mesh.region.bounds
        count = len(mesh.vertices)
        raise EmptyMeshError(f"the mesh has {count} sample{'s' if count != 1 else ''} and no "
                             f"triangles {purpose}: alpha={mesh.alpha:.6g} is probably too "
                             f"large for the region (it spans {xmax - xmin:.6g} x "
                             f"{ymax - ymin:.6g}); use a smaller alpha")


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

