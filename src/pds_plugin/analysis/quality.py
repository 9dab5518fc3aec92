"""Triangle quality: the paper's aspect ratio L²/A, angles, edge lengths."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._checks import check_faces

__all__ = ["Quality", "triangle_quality", "ASPECT_BOUND", "ASPECT_EQUILATERAL"]

ASPECT_EQUILATERAL = float(4 / np.sqrt(3))
"""L²/A of the equilateral triangle, the smallest possible aspect ratio."""
ASPECT_BOUND = float(4 * np.sqrt(3))
"""Theorem 1: no triangle of the solid alpha-complex of a PDS exceeds this L²/A."""


@dataclass(frozen=True)
class Quality:
    """Per-triangle quality of a mesh and its summary.

    ``aspect_ratio`` is L²/A (longest edge squared over area): 4/√3 ≈ 2.309 for the
    equilateral triangle, at most 4√3 ≈ 6.928 on a certified mesh (Theorem 1).

    Attributes
    ----------
    aspect_ratio : (M,) float ndarray
        L²/A of each triangle (inf for a flat one).
    angles : (M, 3) float ndarray
        The angle at each corner, in degrees.
    edge_lengths : (M, 3) float ndarray
        The length of the edge opposite each corner.
    area : (M,) float ndarray
        The area of each triangle.

    Examples
    --------
    >>> import numpy as np
    >>> q = triangle_quality(np.array([[0, 0], [2, 0], [0, 1]]), np.array([[0, 1, 2]]))
    >>> q.area.tolist(), q.max_angle.round(6).tolist(), q.aspect_ratio.tolist()
    ([1.0], [90.0], [5.000000000000001])
    """

    aspect_ratio: np.ndarray
    angles: np.ndarray
    edge_lengths: np.ndarray
    area: np.ndarray

    @property
    def min_angle(self) -> np.ndarray:
        """(M,) the smallest angle of each triangle, in degrees."""
        return self.angles.min(axis=1)

    @property
    def max_angle(self) -> np.ndarray:
        """(M,) the largest angle of each triangle, in degrees."""
        return self.angles.max(axis=1)

    def stats(self) -> dict:
        """Mean, std, min and max of the aspect ratio, and the extreme angles.

        Returns
        -------
        dict
            ``triangles``, ``aspect_mean``, ``aspect_std``, ``aspect_min``,
            ``aspect_max``, ``angle_min``, ``angle_max``, ``edge_min``, ``edge_max`` and
            ``above_bound`` (triangles over 4√3); only ``triangles`` (0) without any.

        Examples
        --------
        >>> import numpy as np
        >>> q = triangle_quality(np.array([[0, 0], [1, 0], [0, 1]]), np.array([[0, 1, 2]]))
        >>> q.stats()["angle_max"], q.stats()["above_bound"]
        (90.0, 0)
        """
        ar = self.aspect_ratio
        if len(ar) == 0:
            return {"triangles": 0}
        return {
            "triangles": int(len(ar)),
            "aspect_mean": float(ar.mean()), "aspect_std": float(ar.std()),
            "aspect_min": float(ar.min()), "aspect_max": float(ar.max()),
            "angle_min": float(self.angles.min()), "angle_max": float(self.angles.max()),
            "edge_min": float(self.edge_lengths.min()), "edge_max": float(self.edge_lengths.max()),
            "above_bound": int(np.count_nonzero(ar > ASPECT_BOUND * (1 + 1e-9))),
        }

    def histogram(self, bins: int = 20, range=(ASPECT_EQUILATERAL, ASPECT_BOUND)):
        """Counts and bin edges of the aspect ratio over ``range`` (the paper's Figure 5).

        Values outside ``range`` are clipped into the end bins so that none is lost.

        Parameters
        ----------
        bins : int
        range : (float, float)
            Default: from the equilateral triangle's 4/√3 to Theorem 1's 4√3.

        Returns
        -------
        counts : (bins,) int ndarray
        edges : (bins + 1,) float ndarray

        Examples
        --------
        >>> import numpy as np
        >>> q = triangle_quality(np.array([[0, 0], [1, 0], [0, 1]]), np.array([[0, 1, 2]]))
        >>> counts, edges = q.histogram(bins=4)     # L²/A = 4 for this one
        >>> counts.tolist(), bool(edges[-1] == ASPECT_BOUND)
        ([0, 1, 0, 0], True)
        """
        counts, edges = np.histogram(np.clip(self.aspect_ratio, *range), bins=bins, range=range)
        return counts, edges


def triangle_quality(vertices: np.ndarray, faces: np.ndarray) -> Quality:
    """Quality measures of the triangles ``faces`` over ``vertices`` (2D or 3D).

    Parameters
    ----------
    vertices : (N, 2) or (N, 3) array_like of float
    faces : (M, 3) array_like of int

    Returns
    -------
    Quality

    Raises
    ------
    ArgumentError
        If a face refers to a vertex that does not exist.

    Examples
    --------
    >>> import numpy as np
    >>> q = triangle_quality(np.array([[0, 0], [1, 0], [0.5, np.sqrt(3) / 2]]), np.array([[0, 1, 2]]))
    >>> bool(np.isclose(q.aspect_ratio[0], ASPECT_EQUILATERAL)), np.round(q.angles, 6).tolist()
    (True, [[60.0, 60.0, 60.0]])
    """
    from .._geometry_kernels import triangle_measures
    vertices = np.ascontiguousarray(vertices, dtype=float)
    faces = check_faces(faces, len(vertices))
    lengths, area, angles = triangle_measures(vertices, faces)
    with np.errstate(divide="ignore"):
        aspect = np.where(area > 0, lengths.max(axis=1, initial=0) ** 2 / area, np.inf)
    return Quality(aspect_ratio=aspect, angles=angles, edge_lengths=lengths, area=area)
