"""Tags of a mesh for finite elements: the region part of each triangle (materials) and the
boundary each boundary edge lies on (boundary conditions), with names.

The tags are found after meshing, from the mesh and its region alone, so the sampler and
the complex know nothing of them:

- a triangle's **region tag** is the component of the region (one polygon with its
  holes, in the order of ``region.geometry.geoms``) that holds its centroid, or the
  nearest one; component ``c`` has tag ``c + 1`` and the name ``"component c"``;
- a boundary edge's **boundary tag** is the ring it lies on (``by="ring"``, the
  default): the ring nearest its midpoint among ``region.rings``, if both its ends lie
  on that ring, tag ``ring + 1``, named
  ``"outline c"`` for the outline of component ``c`` and ``"hole c.h"`` for its hole
  ``h``; or the drawing element it was drawn by (``by="source"``: the SVG element's id,
  from ``region.curves``, see :mod:`pds_plugin.boundary_curves`).

Tag 0 means untagged: interior edges are never given a tag, and a boundary edge is
tagged only when both its ends are boundary samples of the same ring (a non-conforming
mesh can have boundary edges inside the region, across a gap it leaves open, or from
one ring to another).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from .errors import ArgumentError

__all__ = ["Tags", "region_tags", "boundary_tags"]

_ON_RING = 1e-9
"""How far from its ring (relative to the mesh's extent) a boundary sample may be found:
samples are placed on the rings' segments, so only rounding separates them."""


@dataclass(frozen=True, eq=False)
class Tags:
    """Integer tags with names: ``values[i]`` tags item ``i``; 0 means untagged.

    Attributes
    ----------
    values : (n,) int64 ndarray
        Read-only.
    names : dict of str to int
        The name of each tag in use (tags start at 1).

    Examples
    --------
    >>> tags = Tags(np.array([1, 2, 2, 0]), {"outline 0": 1, "hole 0.0": 2})
    >>> tags.where("hole 0.0").tolist(), tags.name_of(1)
    ([1, 2], 'outline 0')
    """

    values: np.ndarray
    names: dict

    def __post_init__(self):
        values = np.array(self.values, dtype=np.int64)
        values.setflags(write=False)
        object.__setattr__(self, "values", values)

    def where(self, name: str) -> np.ndarray:
        """Indices of the items tagged ``name``.

        Raises
        ------
        ArgumentError
            If no tag has that name (the message lists the names).
        """
        if name not in self.names:
            raise ArgumentError(f"no tag named {name!r}; the tags are {', '.join(self.names)}")
        return np.flatnonzero(self.values == self.names[name])

    def name_of(self, tag: int) -> str:
        """The name of ``tag``.

        Raises
        ------
        ArgumentError
            If no name has that tag (0, untagged, has none).
        """
        named = {value: name for name, value in self.names.items()}
        if int(tag) not in named:
            raise ArgumentError(f"no name has tag {tag}; the tags are "
                                f"{', '.join(f'{v} ({n})' for v, n in named.items())}")
        return named[int(tag)]


def region_tags(mesh) -> Tags:
    """The region component of each triangle of ``mesh`` (see the module's doc).

    Parameters
    ----------
    mesh : PlanarMesh

    Returns
    -------
    Tags
        One value per face.

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> two = pds.Region.from_shapely(box(0, 0, 1, 1).union(box(2, 0, 3, 1)))
    >>> tags = region_tags(pds.mesh_region(two, 0.2))
    >>> tags.names, sorted(set(tags.values.tolist()))
    ({'component 0': 1, 'component 1': 2}, [1, 2])
    """
    polygons = mesh.region.geometry.geoms
    names = {f"component {c}": c + 1 for c in range(len(polygons))}
    if not len(mesh.faces):
        return Tags(np.zeros(0, dtype=np.int64), names)
    centroids = mesh.vertices[mesh.faces].mean(axis=1)
    component = np.full(len(centroids), -1, dtype=np.int64)
    for c, polygon in enumerate(polygons):
        shapely.prepare(polygon)
        component[(component < 0) & shapely.contains_xy(polygon, *centroids.T)] = c
    outside = np.flatnonzero(component < 0)   # a non-conforming mesh's, or on an edge
    if len(outside):
        tree = shapely.STRtree(list(polygons))
        component[outside] = tree.query_nearest(shapely.points(centroids[outside]),
                                                all_matches=False)[1]
    return Tags(component + 1, names)


def boundary_tags(mesh, by: str = "ring") -> Tags:
    """The ring (``by="ring"``) or drawing element (``by="source"``) of each boundary edge
    of ``mesh``, in the order of ``mesh.boundary_edges`` (see the module's doc).

    Parameters
    ----------
    mesh : PlanarMesh
    by : {"ring", "source"}

    Returns
    -------
    Tags
        One value per boundary edge.

    Raises
    ------
    ArgumentError
        If ``by`` is neither, or is ``"source"`` for a region that kept no drawing
        curves (the drawing readers, :func:`pds_plugin.load_svg` and :func:`pds_plugin.load_dxf`, keep them).

    Examples
    --------
    >>> import pds_plugin as pds
    >>> from shapely.geometry import box
    >>> plate = pds.Region.from_shapely(box(0, 0, 4, 2).difference(box(1, 0.5, 2, 1.5)))
    >>> tags = boundary_tags(pds.mesh_region(plate, 0.25))
    >>> tags.names
    {'outline 0': 1, 'hole 0.0': 2}
    >>> bool((tags.values > 0).all())
    True
    """
    if by not in ("ring", "source"):
        raise ArgumentError(f"boundary tags are by 'ring' or by 'source', got {by!r}")
    edges = mesh.boundary_edges
    midpoints = mesh.vertices[edges].mean(axis=1) if len(edges) else np.zeros((0, 2))
    on_boundary = mesh.on_boundary[edges].all(axis=1) if len(edges) else np.zeros(0, bool)
    if by == "ring":
        region = mesh.region
        names = {(f"outline {c}" if h is None else f"hole {c}.{h}"): ring + 1
                 for ring, (c, h) in enumerate(region.ring_owners)}
        rings = shapely.linearrings(np.vstack(region.rings), indices=np.repeat(
            np.arange(len(region.rings)), [len(r) for r in region.rings]))
        if not len(edges):
            return Tags(np.zeros(0, dtype=np.int64), names)
        nearest = shapely.STRtree(rings).query_nearest(shapely.points(midpoints),
                                                       all_matches=False)[1]
        ends = shapely.points(mesh.vertices[edges])
        gap = shapely.distance(rings[nearest][:, None], ends).max(axis=1)
        on_ring = on_boundary & (gap <= _ON_RING * max(np.ptp(mesh.vertices, axis=0)))
        return Tags(np.where(on_ring, nearest + 1, 0), names)
    curves = mesh.region.curves
    if curves is None:
        raise ArgumentError("the region kept no drawing curves, so its boundary has no "
                            "sources: tag by='ring', or read the drawing with load_svg")
    names = {label: index + 1 for index, label in enumerate(curves.labels)}
    if not len(edges):
        return Tags(np.zeros(0, dtype=np.int64), names)
    piece = curves.locate(midpoints)[0]
    return Tags(np.where(on_boundary, curves.source[piece] + 1, 0), names)
