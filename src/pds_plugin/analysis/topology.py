"""Topology of a mesh against its region: Betti numbers, and what was lost or merged.

Theorem 2 of the paper promises ``|C| ~ R`` when alpha is small enough; this module
checks it on the actual mesh. The Betti numbers of the triangle complex ``|C|`` are
``b0`` (connected components of triangles joined through shared vertices) and
``b1 = b0 - χ`` (holes), ``χ = V - E + F`` over the vertices, edges and faces used by
triangles. They are compared with the region's overall and per region component, and
each disagreement is located in region coordinates: a hole filled, two holes merged, a
hole opened to the outside or split in two, components joined across a gap, a component
broken or lost, a notch of the outline closed off into a hole.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import shapely

from .._checks import check_planar_mesh

if TYPE_CHECKING:
    from ..mesh import PlanarMesh

__all__ = ["ComponentTopology", "TopologyReport", "topology_report"]


@dataclass(frozen=True)
class ComponentTopology:
    """Betti numbers of one region component and of the mesh parts lying on it.

    Attributes
    ----------
    component : int
        Index of the component in ``region.geometry.geoms``.
    betti_region : tuple of int
        ``(1, holes)`` of the component.
    betti_mesh : tuple of int
        ``(b0, b1)`` of the mesh components with a vertex on it.
    ok : bool
        They agree and no defect was found on the component.
    """

    component: int
    betti_region: tuple[int, int]
    betti_mesh: tuple[int, int]
    ok: bool


@dataclass(frozen=True)
class TopologyReport:
    """Topology of a mesh compared with its region.

    Attributes
    ----------
    betti_mesh, betti_region : tuple of int
        ``(b0, b1)``: components and holes.
    per_component : tuple of ComponentTopology
        One entry per region component, in ``region.geometry.geoms`` order. Its mesh
        numbers count the mesh components with a vertex on that region component, and
        their holes.
    topology_ok : bool
        True when every component matches and no hole is lost, merged, opened or split.
    problems : tuple of str
        One readable sentence per defect, located in region coordinates, with the alpha
        that would keep the feature.
    """

    betti_mesh: tuple[int, int]
    betti_region: tuple[int, int]
    per_component: tuple[ComponentTopology, ...]
    topology_ok: bool
    problems: tuple[str, ...]

    def as_dict(self) -> dict:
        """Plain JSON-ready values.

        Returns
        -------
        dict
            The attributes, ``per_component`` as a tuple of dicts.

        Examples
        --------
        >>> from shapely.geometry import box
        >>> import pds_plugin as pds
        >>> report = topology_report(pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.2))
        >>> report.as_dict()["per_component"]
        ({'component': 0, 'betti_region': (1, 0), 'betti_mesh': (1, 0), 'ok': True},)
        """
        return asdict(self)

    def __str__(self) -> str:
        verdict = "ok" if self.topology_ok else "MISMATCH"
        lines = [f"topology {verdict}: mesh (b0, b1) = {self.betti_mesh}, "
                 f"region = {self.betti_region}"]
        return "\n".join(lines + [f"  - {p}" for p in self.problems])


def topology_report(mesh: PlanarMesh) -> TopologyReport:
    """Compare the topology of ``mesh`` (a PlanarMesh) with that of its region.

    Parameters
    ----------
    mesh : PlanarMesh

    Returns
    -------
    TopologyReport
        Each defect located in region coordinates, with the alpha that would keep it.

    Examples
    --------
    >>> from shapely.geometry import Point
    >>> import pds_plugin as pds
    >>> disc_with_hole = Point(0, 0).buffer(1).difference(Point(0, 0).buffer(0.3))
    >>> region = pds.Region.from_shapely(disc_with_hole)
    >>> topology_report(pds.mesh_region(region, alpha=0.1)).topology_ok
    True
    >>> report = topology_report(pds.mesh_region(region, alpha=0.4, conforming=False))
    >>> report.betti_mesh, report.betti_region
    ((1, 0), (1, 1))
    >>> print(report.problems[0])         # doctest: +ELLIPSIS
    hole 0 of component 0 at (0, 0), about 0.599... wide, is filled by the mesh; keep it with alpha <= 0.149...
    """
    return _Comparison(check_planar_mesh(mesh, "topology_report")).report()


class _Comparison:
    """The mesh's parts and holes matched with the region's."""

    def __init__(self, mesh):
        self.region = mesh.region
        self.vertices = np.asarray(mesh.vertices, dtype=float)
        self.faces = np.asarray(mesh.faces, dtype=np.int64).reshape(-1, 3)
        self.alpha = float(mesh.alpha)
        self.labels, self.betti = mesh.vertex_component, mesh.component_betti
        self.components = list(self.region.geometry.geoms)
        self.owner = _owners(self.region, self.vertices)
        self.mesh = mesh
        self.problems = []          # (component, sentence)

    def report(self) -> TopologyReport:
        parts = self._match_components()
        # without holes in the region or the mesh (b1 = 0: the union of the triangles has
        # none either) there is no hole to match, and the outline is not needed
        if len(self.faces) and (self.region.betti[1] or self.betti[:, 1].any()):
            self._match_holes({c for c, ps in enumerate(parts) if not ps})
        per_component = []
        for c, (polygon, pieces) in enumerate(zip(self.components, parts)):
            region_betti = (1, len(polygon.interiors))
            mesh_betti = (len(pieces), int(self.betti[sorted(pieces), 1].sum()) if pieces else 0)
            clean = all(pc != c for pc, _ in self.problems)
            per_component.append(ComponentTopology(c, region_betti, mesh_betti,
                                                   clean and region_betti == mesh_betti))
        betti_mesh = (len(self.betti), int(self.betti[:, 1].sum()) if len(self.betti) else 0)
        ok = (betti_mesh == self.region.betti and not self.problems
              and all(p.ok for p in per_component))
        return TopologyReport(betti_mesh=betti_mesh, betti_region=self.region.betti,
                              per_component=tuple(per_component), topology_ok=ok,
                              problems=tuple(text for _, text in self.problems))

    @cached_property
    def covered(self):
        """The union of the triangles (the mesh's outline, built on first use)."""
        return self.mesh.outline

    @cached_property
    def triangles(self):
        return shapely.polygons(self.vertices[self.faces])

    def _problem(self, component, text):
        self.problems.append((component, text))

    # components -----------------------------------------------------------------------

    def _match_components(self) -> list[set[int]]:
        """Mesh components on each region component; reports lost, broken and joined ones."""
        used = self.labels >= 0
        n_owner = len(self.components)
        pairs = np.unique(self.labels[used] * n_owner + self.owner[used])
        pairs = np.column_stack([pairs // n_owner, pairs % n_owner])
        parts = [set(pairs[pairs[:, 1] == c, 0].tolist()) for c in range(len(self.components))]
        for c, pieces in enumerate(parts):
            if not pieces:
                self._lost_component(c)
            elif len(pieces) > 1 and all(np.count_nonzero(pairs[:, 0] == m) == 1 for m in pieces):
                self._broken_component(c, sorted(pieces))
        joining = np.flatnonzero(np.bincount(pairs[:, 0], minlength=len(self.betti)) > 1)
        for m in joining:
            self._joined_components(sorted(pairs[pairs[:, 0] == m, 1].tolist()))
        return parts

    def _lost_component(self, c):
        polygon = self.components[c]
        centre, radius = _inscribed(polygon)
        self._problem(c, f"component {c} at {_xy(centre)} (area {polygon.area:.4g}, about "
                         f"{2 * radius:.4g} wide) has no triangle: it is lost; keep it with "
                         f"alpha <= {radius / 2:.4g}")

    def _broken_component(self, c, pieces):
        shapes = [self._covered_by(self.labels[self.faces[:, 0]] == m) for m in pieces]
        line = shapely.shortest_line(shapes[0], shapely.union_all(shapes[1:]))
        where = np.asarray(line.interpolate(0.5, normalized=True).coords[0])
        width = 2 * self.components[c].boundary.distance(shapely.Point(where))
        self._problem(c, f"component {c} is broken into {len(pieces)} pieces near {_xy(where)}: "
                         f"the material there (about {width:.4g} thick) is not spanned by "
                         f"triangles; keep it with alpha <= {width / 4:.4g}")

    def _joined_components(self, comps):
        a, b = comps[0], comps[1]
        line = shapely.shortest_line(self.components[a], self.components[b])
        where = np.asarray(line.interpolate(0.5, normalized=True).coords[0])
        names = ", ".join(str(c) for c in comps[:-1]) + f" and {comps[-1]}"
        self._problem(a, f"components {names} are joined by triangles across the gap near "
                         f"{_xy(where)} ({line.length:.4g} wide between {a} and {b}); keep "
                         f"them apart with alpha <= {line.length / 4:.4g}")

    def _covered_by(self, mask):
        return shapely.coverage_union_all(shapely.polygons(self.vertices[self.faces[mask]]))

    # holes ------------------------------------------------------------------------------

    def _match_holes(self, lost_components):
        """Match region holes and mesh holes through their deepest points.

        A region hole is kept when exactly one mesh hole has its deepest point in it. With
        none, the region hole's own deepest point tells what happened: covered (filled),
        in a mesh hole centred in another region hole (merged) or outside (opened). With
        several, the hole is split by triangles bridging a narrow passage.
        """
        owner, number, shapes = _holes(self.components)
        region_holes = list(zip(owner.tolist(), number.tolist(), shapes))
        parts = shapely.get_parts(self.covered)
        filled = shapely.polygons(shapely.get_exterior_ring(parts))
        mesh_holes = list(_holes(parts)[2])
        x0, y0, x1, y1 = self.region.bounds
        frame = shapely.box(x0, y0, x1, y1).buffer(max(x1 - x0, y1 - y0))
        self.mesh_holes = mesh_holes
        self.mesh_outside = frame.difference(shapely.union_all(filled))
        mesh_centres = _inscribed_centres(_complement_faces(mesh_holes, filled))
        in_region = self._region_places(mesh_centres, [s for _, _, s in region_holes])
        mine = np.bincount([p for p in in_region if isinstance(p, int)], minlength=len(region_holes))
        for k, (c, h, shape) in enumerate(region_holes):
            if c in lost_components:
                continue
            name = f"hole {h} of component {c}"
            if mine[k] >= 2:
                self._bridge(f"{name} is split into {mine[k]}", shape)
            elif mine[k] == 0:
                centre, radius = _inscribed(shape.difference(self.region.geometry))
                place = self._mesh_place(centre, mesh_holes)
                if place == "covered":
                    self._problem(c, f"{name} at {_xy(centre)}, about {2 * radius:.4g} wide, is "
                                     f"filled by the mesh; keep it with alpha <= {radius / 2:.4g}")
                elif place != "outside" and isinstance(in_region[place], int):
                    c2, h2, shape2 = region_holes[in_region[place]]
                    self._wall(c, f"{name} is merged with hole {h2} of component {c2}",
                               shape.exterior, shape2.exterior)
                else:
                    self._wall(c, f"{name} is opened to the outside", shape.exterior,
                               self.components[c].exterior)
        for centre, place, shape in zip(mesh_centres, in_region, mesh_holes):
            if place == "material":
                c = int(self.owner[np.argmin(np.linalg.norm(self.vertices - centre, axis=1))])
                self._problem(c, f"the mesh leaves an uncovered hole inside component {c} at "
                                 f"{_xy(centre)} (the sampling does not cover the region there)")
            elif place == "outside":
                self._bridge("a notch of the outline is closed off into a hole", shape)

    def _mesh_place(self, point, mesh_holes):
        """'covered', a mesh hole index, or 'outside' (the unbounded part of the complement)."""
        if self.covered.covers(shapely.Point(point)):
            return "covered"
        return _innermost(point, mesh_holes, default="outside")

    def _region_places(self, points, region_holes) -> list:
        """Where each point lies: 'material' (in the region), the index of the smallest
        region hole holding it, or 'outside'."""
        points = np.asarray(points, dtype=float).reshape(-1, 2)
        places = np.where(shapely.intersects_xy(self.region.geometry, *points.T), -1, -2)
        if region_holes and len(points):
            shapes = np.asarray(region_holes, dtype=object)
            point, hole = shapely.STRtree(shapes).query(shapely.points(points), predicate="within")
            free = places[point] == -2
            point, hole = point[free], hole[free]
            first = np.lexsort((hole, shapely.area(shapes)[hole], point))   # smallest area first
            point, hole = point[first], hole[first]
            lead = np.r_[True, point[1:] != point[:-1]]
            places[point[lead]] = hole[lead]
        return ["material" if p == -1 else "outside" if p == -2 else int(p) for p in places]

    def _wall(self, c, what, ring_a, ring_b):
        line = shapely.shortest_line(ring_a, ring_b)
        where = np.asarray(line.interpolate(0.5, normalized=True).coords[0])
        t = line.length
        self._problem(c, f"{what}: the wall near {_xy(where)} ({t:.4g} thick) is broken; "
                         f"keep it with alpha <= {t / 4:.4g}")

    def _bridge(self, what, shape):
        """Locate the bridge: triangles near ``shape`` that reach outside the region and
        join two parts of the mesh's complement (a mesh hole and the outside, or two mesh
        holes), i.e. that close a passage of the region's complement."""
        shapely.prepare(self.region.geometry)
        reaching = self.triangles[~shapely.contains_properly(self.region.geometry, self.triangles)]
        spill = shapely.get_parts(shapely.union_all(
            shapely.difference(reaching, self.region.geometry)))
        spill = spill[(shapely.area(spill) > 0) & shapely.intersects(spill, shape)]
        if not len(spill):          # no triangle reaches outside: name the place only
            centre = _inscribed(shape)[0]
            c = int(self.owner[np.argmin(np.linalg.norm(self.vertices - centre, axis=1))])
            self._problem(c, f"{what} near {_xy(centre)}")
            return
        x0, y0, x1, y1 = self.region.bounds
        tolerance = 1e-9 * max(x1 - x0, y1 - y0)
        complement = [*self.mesh_holes, self.mesh_outside]
        touching = shapely.dwithin(spill[:, None], np.asarray(complement, dtype=object)[None, :],
                                   tolerance).sum(axis=1)
        pieces = spill[touching >= 2] if (touching >= 2).any() else spill
        piece = pieces[np.argmax(shapely.area(pieces))]
        where = _inscribed(piece)[0]
        width = 2 * self.region.geometry.boundary.distance(shapely.Point(where))
        c = int(self.owner[np.argmin(np.linalg.norm(self.vertices - where, axis=1))])
        self._problem(c, f"{what}: triangles bridge the passage near {_xy(where)} (about "
                         f"{width:.4g} wide); keep it open with alpha <= {width / 4:.4g}")


def _owners(region, points) -> np.ndarray:
    """Index of the region component holding each point (for points that rounding puts
    just outside, the component of the nearest boundary segment)."""
    components = region.geometry.geoms
    if len(components) == 1:
        return np.zeros(len(points), dtype=np.int64)
    owner = np.full(len(points), -1, dtype=np.int64)
    x, y = points.T
    for c, polygon in enumerate(components):
        x0, y0, x1, y1 = polygon.bounds        # only points in its box can lie on it
        test = np.flatnonzero((owner < 0) & (x0 <= x) & (x <= x1) & (y0 <= y) & (y <= y1))
        owner[test[shapely.intersects_xy(polygon, x[test], y[test])]] = c
    stray = np.flatnonzero(owner < 0)
    if len(stray):
        segment_owner = np.repeat([c for c, _ in region.ring_owners],
                                  [len(ring) for ring in region.rings])
        tree = shapely.STRtree(shapely.linestrings(region.segments))
        nearest = tree.query_nearest(shapely.points(points[stray]), all_matches=False)
        owner[stray[nearest[0]]] = segment_owner[nearest[1]]
    return owner


def _holes(polygons):
    """The holes of ``polygons`` as polygons: (owner, hole number, shapes) arrays, in
    the order of ``polygon.interiors``."""
    rings, owner = shapely.get_rings(np.asarray(polygons, dtype=object), return_index=True)
    number = np.arange(len(owner)) - np.searchsorted(owner, owner) - 1   # exterior: -1
    hole = number >= 0
    return owner[hole], number[hole], shapely.polygons(rings[hole])


def _complement_faces(holes, filled):
    """Each hole of the mesh minus the mesh parts inside it (islands, with their own
    holes filled): the face of the mesh's complement that the hole's ring bounds.

    A mesh part meeting the open hole lies inside it (parts do not overlap), so the parts
    a hole contains are its islands; the hole's own part only touches its ring."""
    holes = np.asarray(holes, dtype=object)
    if not len(holes):
        return holes
    hole, island = shapely.STRtree(filled).query(holes, predicate="contains")
    faces = holes.copy()
    for k in np.unique(hole):
        faces[k] = faces[k].difference(shapely.union_all(filled[island[hole == k]]))
    return faces


def _inscribed_centres(shapes) -> np.ndarray:
    """(n, 2) centres of the largest circles inside the polygonal ``shapes``."""
    lines = shapely.maximum_inscribed_circle(np.asarray(shapes, dtype=object))
    return shapely.get_coordinates(shapely.get_point(lines, 0)).reshape(-1, 2)


def _inscribed(shape):
    """Centre (2,) and radius of the largest circle inside a polygonal shape."""
    line = shapely.maximum_inscribed_circle(shape)
    coords = np.asarray(line.coords)
    return coords[0], float(line.length)


def _innermost(point, shapes, default):
    """Index of the smallest shape containing ``point``, else ``default``."""
    if not shapes:
        return default
    inside = shapely.contains_xy(np.asarray(shapes, dtype=object), point[0], point[1])
    if not inside.any():
        return default
    areas = np.where(inside, shapely.area(np.asarray(shapes, dtype=object)), np.inf)
    return int(np.argmin(areas))


def _xy(point) -> str:
    return f"({float(point[0]):.4g}, {float(point[1]):.4g})"
