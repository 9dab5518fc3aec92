"""The package's error types: every bad-input error pds_plugin raises is a :class:`PdsError`.

``PdsError`` is a ``ValueError``, so ``except ValueError`` keeps working; its subclasses say
which input was wrong. A file that is missing or cannot be written stays an ``OSError``
(``FileNotFoundError``, ``IsADirectoryError``...), as Python's own file functions raise it.
Anything else escaping the package is a bug, and keeps its traceback in ``pds-mesh``.

>>> from pds_plugin.errors import PdsError, ArgumentError
>>> issubclass(ArgumentError, PdsError) and issubclass(PdsError, ValueError)
True
"""

from __future__ import annotations

__all__ = ["PdsError", "ArgumentError", "ArgumentTypeError", "RegionError", "SourceError",
           "SectionError", "BudgetError", "TopologyError", "EmptyMeshError",
           "MissingDependencyError"]


class PdsError(ValueError):
    """Bad input to pds_plugin; the message names the problem and what to do."""


class ArgumentError(PdsError):
    """An argument has a value pds_plugin cannot use (alpha <= 0, a zero normal...)."""


class ArgumentTypeError(ArgumentError, TypeError):
    """An argument has the wrong type (also a ``TypeError``)."""


class RegionError(PdsError):
    """The region's geometry cannot be meshed: empty, invalid, not polygonal, no area."""


class SourceError(PdsError):
    """A solid or drawing cannot be read: empty or unreadable file, invalid solid."""


class SectionError(SourceError):
    """A plane gives no usable section: it misses the solid, lies on a face, or cuts an
    open (not watertight) part of it."""


class BudgetError(PdsError):
    """The work asked for exceeds a limit: too many samples or grid cells for alpha."""


class TopologyError(PdsError):
    """No alpha within the budget gives a mesh with the region's topology.

    ``mesh`` is the last mesh tried (at the smallest alpha the budget allows), whose
    certificate says what it lost; :func:`pds_plugin.mesh_region` with ``"auto"``
    returns it, with a warning, instead of raising."""

    def __init__(self, message: str, mesh=None):
        super().__init__(message)
        self.mesh = mesh


class EmptyMeshError(PdsError):
    """A mesh without triangles was given where triangles are needed (alpha too large)."""


class MissingDependencyError(PdsError, ImportError):
    """An optional dependency is not installed (also an ``ImportError``); the message
    gives the ``pip install`` extra that provides it."""
