"""Triangle quality: the paper's aspect ratio L²/A, angles, edge lengths."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

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
    """

    aspect_ratio: np.ndarray   # (M,) L²/A
    angles: np.ndarray         # (M, 3) degrees, angle at each corner
    edge_lengths: np.ndarray   # (M, 3) opposite each corner
    area: np.ndarray           # (M,)

    @property
    def min_angle(self) -> np.ndarray:
        return self.angles.min(axis=1)

    @property
    def max_angle(self) -> np.ndarray:
        return self.angles.max(axis=1)

    def stats(self) -> dict:
        """Mean, std, min and max of the aspect ratio, and the extreme angles."""
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
        """
        counts, edges = np.histogram(np.clip(self.aspect_ratio, *range), bins=bins, range=range)
        return counts, edges


def triangle_quality(vertices: np.ndarray, faces: np.ndarray) -> Quality:
    """Quality measures of the triangles ``faces`` over ``vertices`` (2D or 3D).

    Examples
    --------
    >>> import numpy as np
    >>> q = triangle_quality(np.array([[0, 0], [1, 0], [0.5, np.sqrt(3) / 2]]), np.array([[0, 1, 2]]))
    >>> bool(np.isclose(q.aspect_ratio[0], ASPECT_EQUILATERAL)), np.round(q.angles, 6).tolist()
    (True, [[60.0, 60.0, 60.0]])
    """
    corners = np.asarray(vertices, dtype=float)[np.asarray(faces)]        # (M, 3, d)
    # edge i is opposite corner i
    edges = np.roll(corners, -1, axis=1) - np.roll(corners, 1, axis=1)     # (M, 3, d)
    lengths = np.linalg.norm(edges, axis=2)
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    ab, ac = b - a, c - a
    if corners.shape[2] == 2:
        area = 0.5 * np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    else:
        area = 0.5 * np.linalg.norm(np.cross(ab, ac), axis=1)
    longest = lengths.max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        aspect = np.where(area > 0, longest**2 / area, np.inf)
        # law of cosines, clipped against rounding
        l0, l1, l2 = lengths[:, 0], lengths[:, 1], lengths[:, 2]
        cos = np.stack([(l1**2 + l2**2 - l0**2) / (2 * l1 * l2),
                        (l2**2 + l0**2 - l1**2) / (2 * l2 * l0),
                        (l0**2 + l1**2 - l2**2) / (2 * l0 * l1)], axis=1)
    angles = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    return Quality(aspect_ratio=aspect, angles=angles, edge_lengths=lengths, area=area)
