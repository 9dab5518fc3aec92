"""Meshes a finite-element code takes as they are (issue 23): tags, meshio formats,
scikit-fem meshes, quadratic triangles on the true curves, and their convergence."""

import numpy as np
import pytest
import shapely
from shapely.geometry import Point, box

import pds_plugin as pds
from pds_plugin.errors import ArgumentError, MissingDependencyError
from pds_plugin.tags import boundary_tags

meshio = pytest.importorskip("meshio")
skfem = pytest.importorskip("skfem")


@pytest.fixture(scope="module")
def plate():
    """Two plates, one with a round and a square hole: 2 components, 3 rings."""
    shape = (box(0, 0, 4, 2).difference(Point(1, 1).buffer(0.4))
             .difference(box(2.5, 0.5, 3.5, 1.5)).union(box(5, 0, 6, 1)))
    return pds.mesh_region(pds.Region.from_shapely(shape), 0.15)


def _svg(tmp_path, body, name="drawing.svg", view="-1 -1 2 2"):
    path = tmp_path / name
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{view}">{body}</svg>')
    return path


# --- tags ---------------------------------------------------------------------------

def test_every_boundary_edge_names_its_ring_and_no_interior_edge_is_tagged(plate):
    tags = plate.boundary_tags
    assert tags.names == {"outline 0": 1, "hole 0.0": 2, "hole 0.1": 3, "outline 1": 4}
    assert len(tags.values) == len(plate.boundary_edges) and (tags.values > 0).all()
    rings = plate.region.rings
    for tag in tags.names.values():
        ring = shapely.LinearRing(rings[tag - 1])
        ends = plate.vertices[plate.boundary_edges[tags.values == tag]].reshape(-1, 2)
        assert shapely.distance(ring, shapely.points(ends)).max() < 1e-12   # on that ring
        others = [shapely.LinearRing(r) for k, r in enumerate(rings) if k != tag - 1]
        assert min(shapely.distance(o, shapely.points(ends)).min() for o in others) > 0.1
    # each ring's edges close into a loop as long as the ring's chords between samples
    for tag in tags.names.values():
        edges = plate.boundary_edges[tags.values == tag]
        assert sorted(edges[:, 0]) == sorted(edges[:, 1])
    # interior edges: tagged nowhere (the tags are indexed by the boundary edges only)
    interior = len(plate.edges) - len(plate.boundary_edges)
    exported = plate.to_meshio()
    assert interior > 0 and len(exported.cells[1].data) == len(plate.boundary_edges)


def test_region_tags_give_each_triangle_its_component(plate):
    tags = plate.region_tags
    assert tags.names == {"component 0": 1, "component 1": 2}
    centroids = plate.vertices[plate.faces].mean(axis=1)
    for c, polygon in enumerate(plate.region.geometry.geoms):
        assert shapely.contains_xy(polygon, *centroids[tags.where(f"component {c}")].T).all()
    square = plate.faces[tags.where("component 1")]     # a square: meshed exactly
    a, b, c = (plate.vertices[square[:, k]] for k in range(3))
    area = 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    assert np.isclose(area.sum(), 1.0, rtol=1e-12)
    assert len(tags.values) == len(plate.faces) and (tags.values > 0).all()


def test_tags_by_source_name_the_svg_elements(tmp_path):
    drawing = _svg(tmp_path, '<path id="plate" fill-rule="evenodd" d="M0 0H4V2H0Z '
                   'M1 0.5H2V1.5H1Z"/><circle id="boss" cx="4" cy="1" r="0.5"/>',
                   view="0 0 5 2")
    mesh = pds.mesh_region(pds.load_svg(drawing), 0.1)
    tags = boundary_tags(mesh, by="source")
    assert tags.names == {"plate": 1, "boss": 2} and (tags.values > 0).all()
    ends = mesh.vertices[mesh.boundary_edges]
    boss = ends[tags.values == 2].reshape(-1, 2)
    assert len(boss) and np.abs(np.linalg.norm(boss - (4, 1), axis=1) - 0.5).max() < 1e-3
    plate = ends[tags.values == 1]
    on_a_line = np.isclose(plate[:, 0], plate[:, 1]).any(axis=1)    # same x or same y
    assert on_a_line.all() and (plate[..., 0] <= 4 + 1e-9).all()
    with pytest.raises(ArgumentError, match="kept no drawing curves"):
        boundary_tags(pds.mesh_region(pds.Region.from_shapely(box(0, 0, 1, 1)), 0.3), "source")
    with pytest.raises(ArgumentError, match="by 'ring' or by 'source'"):
        boundary_tags(mesh, by="layer")


# --- meshio -------------------------------------------------------------------------

@pytest.mark.parametrize("suffix", [".msh", ".vtu", ".xdmf"])
def test_meshio_round_trip_keeps_points_triangles_and_both_tags(plate, tmp_path, suffix):
    path = tmp_path / f"plate{suffix}"
    plate.export(path)
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]     # one file
    back = meshio.read(path)
    np.testing.assert_array_equal(back.points[:, :2], plate.vertices)
    np.testing.assert_array_equal(back.cells_dict["triangle"], plate.faces)
    np.testing.assert_array_equal(back.cells_dict["line"], plate.boundary_edges)
    key = ("gmsh:physical", "gmsh:physical") if suffix == ".msh" else ("region", "boundary")
    np.testing.assert_array_equal(back.cell_data_dict[key[0]]["triangle"],
                                  plate.region_tags.values)
    np.testing.assert_array_equal(back.cell_data_dict[key[1]]["line"],
                                  plate.boundary_tags.values)
    if suffix == ".msh":                       # gmsh keeps the names: physical groups
        assert {name: tuple(v) for name, v in back.field_data.items()} == {
            **{n: (t, 2) for n, t in plate.region_tags.names.items()},
            **{n: (t, 1) for n, t in plate.boundary_tags.names.items()}}


@pytest.fixture(scope="module")
def composite():
    """Steel core in a concrete section: one interface ring, graded."""
    core, shell = box(1, 1, 2, 2), box(0, 0, 3, 3).difference(box(1, 1, 2, 2))
    return pds.mesh_regions({"steel": core, "concrete": shell}, 0.3, graded=True)


@pytest.mark.parametrize("suffix", [".msh", ".vtu"])
def test_composite_round_trip_keeps_the_interface_lines_and_their_tags(composite, tmp_path,
                                                                       suffix):
    path = tmp_path / f"composite{suffix}"
    composite.export(path)
    back = meshio.read(path)
    boundary, interface = composite.boundary_edges, composite.interface_edges
    lines = back.cells_dict["line"]
    np.testing.assert_array_equal(lines, np.concatenate([boundary, interface]))
    key = "gmsh:physical" if suffix == ".msh" else "boundary"
    tags = back.cell_data_dict[key]["line"]
    offset = max(composite.boundary_tags.names.values())
    np.testing.assert_array_equal(tags[:len(boundary)], composite.boundary_tags.values)
    np.testing.assert_array_equal(tags[len(boundary):], composite.interface_tags.values + offset)
    regions = back.cell_data_dict["gmsh:physical" if suffix == ".msh" else "region"]["triangle"]
    np.testing.assert_array_equal(regions, composite.region_tags.values)
    if suffix == ".msh":                       # the interface is a named physical group
        assert tuple(back.field_data["steel|concrete"]) == (offset + 1, 1)
    # every interface line is an inner edge: two triangles, one of each material
    faces = back.cells_dict["triangle"]
    for a, b in lines[len(boundary):].tolist():
        sides = np.flatnonzero(np.isin(faces, [a, b]).sum(axis=1) == 2)
        assert sorted(regions[sides].tolist()) == [1, 2]


def test_composite_interfaces_go_out_quadratic_and_to_skfem(composite):
    m = composite.to_meshio(order=2)
    q = composite.quadratic()
    lines = m.cells[1].data
    inner = lines[len(composite.boundary_edges):]
    middle = q.points[inner[:, 2]]
    np.testing.assert_allclose(middle, q.points[inner[:, :2]].mean(axis=1), atol=1e-14)
    fem = composite.to_skfem()
    facets = fem.boundaries["steel|concrete"]
    assert len(facets) == len(composite.interface_edges)
    assert not set(facets.tolist()) & set(fem.boundary_facets().tolist())    # inner facets


def test_abaqus_keeps_the_tags_as_element_sets(plate, tmp_path):
    plate.export(tmp_path / "plate.inp")
    back = meshio.read(tmp_path / "plate.inp")
    assert len(back.cells_dict["triangle"]) == len(plate.faces)
    sizes = {name: sum(len(m) for m in members) for name, members in back.cell_sets.items()}
    assert sizes["hole_0.1"] == np.count_nonzero(plate.boundary_tags.values == 3)
    assert sizes["component_1"] == np.count_nonzero(plate.region_tags.values == 2)


def test_abaqus_names_an_interface_set_with_letters_and_underscores(composite, tmp_path):
    composite.export(tmp_path / "composite.inp")
    back = meshio.read(tmp_path / "composite.inp")
    sizes = {name: sum(len(m) for m in members) for name, members in back.cell_sets.items()}
    assert sizes["steel_concrete"] == len(composite.interface_edges)


def test_ply_and_obj_keep_their_exact_writers(plate, tmp_path):
    plate.export(tmp_path / "plate.obj")
    assert (tmp_path / "plate.obj").read_text().startswith("# pds_plugin mesh")


def test_quadratic_meshio_cells(plate):
    m = plate.to_meshio(order=2)
    assert [block.type for block in m.cells] == ["triangle6", "line3"]
    q = plate.quadratic()
    np.testing.assert_array_equal(m.cells[0].data, q.triangles)
    with pytest.raises(ArgumentError, match="order must be 1"):
        plate.to_meshio(order=3)


@pytest.mark.parametrize("module, call", [("meshio", lambda m: m.to_meshio()),
                                          ("meshio", lambda m: m.export("never.msh")),
                                          ("skfem", lambda m: m.to_skfem())])
def test_a_missing_fem_library_is_a_clear_error(plate, monkeypatch, module, call):
    import sys
    monkeypatch.setitem(sys.modules, module, None)
    with pytest.raises(MissingDependencyError, match=r'pip install "pds_plugin\[fem\]"'):
        call(plate)


def test_tags_name_lookups_fail_clearly(plate):
    with pytest.raises(ArgumentError, match="no tag named 'hole 7.0'"):
        plate.boundary_tags.where("hole 7.0")
    with pytest.raises(ArgumentError, match="no name has tag 0"):
        plate.boundary_tags.name_of(0)
    with pytest.raises(ArgumentError, match="by 'ring' or by 'source'"):
        plate.to_skfem(boundary="layer")


def test_graded_meshes_go_out_with_tags_and_curved_nodes(tmp_path):
    region = pds.load_svg(_svg(tmp_path, '<path id="ring" fill-rule="evenodd" '
                               'd="M1 0A1 1 0 0 0 -1 0A1 1 0 0 0 1 0Z '
                               'M0.3 0A0.3 0.3 0 0 0 -0.3 0A0.3 0.3 0 0 0 0.3 0Z"/>'))
    mesh = pds.mesh_region(region, 0.2, graded=True)
    assert mesh.boundary_tags.names == {"outline 0": 1, "hole 0.0": 2}
    q = mesh.quadratic()
    radius = np.linalg.norm(q.points[np.unique(q.boundary_lines)], axis=1)
    assert np.minimum(np.abs(radius - 1), np.abs(radius - 0.3)).max() < 1e-12
    assert len(q.inverted) == 0
    assert abs(q.area - np.pi * (1 - 0.09)) < abs(mesh.outline.area - np.pi * (1 - 0.09)) / 10


# --- scikit-fem ---------------------------------------------------------------------

def test_skfem_boundaries_and_subdomains_are_the_tags(plate):
    m = plate.to_skfem()
    assert set(m.boundaries) == set(plate.boundary_tags.names)
    assert set(m.subdomains) == set(plate.region_tags.names)
    assert np.array_equal(np.sort(np.concatenate(list(m.boundaries.values()))),
                          np.sort(m.boundary_facets()))
    for name, facets in m.boundaries.items():
        ring = shapely.LinearRing(plate.region.rings[plate.boundary_tags.names[name] - 1])
        ends = m.p[:, m.facets[:, facets]].T.reshape(-1, 2)
        assert shapely.distance(ring, shapely.points(ends)).max() < 1e-12
    m2 = plate.to_skfem(order=2)
    assert isinstance(m2, skfem.MeshTri2) and set(m2.boundaries) == set(m.boundaries)


# --- quadratic meshes ---------------------------------------------------------------

def test_quadratic_nodes_of_an_svg_circle_are_on_the_circle(tmp_path):
    disc = pds.load_svg(_svg(tmp_path, '<circle r="1"/>'))
    mesh = pds.mesh_region(disc, 0.2)
    q = mesh.quadratic()
    boundary_nodes = np.unique(q.boundary_lines)
    radius = np.linalg.norm(q.points[boundary_nodes], axis=1)
    assert np.abs(radius - 1).max() < 1e-12
    assert q.moved <= disc.curves.tolerance
    ends = q.points[q.boundary_lines]               # mid node halfway in arc length
    angle = np.arctan2(ends[..., 1], ends[..., 0])
    half = np.angle(np.exp(1j * (angle[:, 2] - angle[:, 0])))
    other = np.angle(np.exp(1j * (angle[:, 1] - angle[:, 2])))
    np.testing.assert_allclose(half, other, atol=1e-12)
    assert len(q.inverted) == 0 and q.min_jacobian.min() > 0.5
    assert abs(q.area - np.pi) < 0.2 ** 4            # curved: O(h^4) area, not O(h^2)
    assert abs(mesh.outline.area - np.pi) > 10 * abs(q.area - np.pi)


def test_a_node_that_would_invert_its_triangle_leaves_the_edge_straight(tmp_path):
    """A triangle whose third vertex lies nearer the chord of a round hole than the hole's
    arc does: on the arc, the edge's node would pass that vertex and invert the map."""
    region = pds.load_svg(_svg(tmp_path, '<path fill-rule="evenodd" d="M-2 -2H2V2H-2Z '
                               'M1 0A1 1 0 0 1 -1 0A1 1 0 0 1 1 0Z"/>', view="-2 -2 4 4"))
    hole = region.rings[1]
    angle = np.arctan2(hole[:, 1], hole[:, 0])
    a, b = hole[np.argmin(np.abs(angle))], hole[np.argmin(np.abs(angle - np.pi / 2))]
    for radius, straightened in ((1.1, 1), (1.5, 0)):
        c = radius * (a + b) / np.linalg.norm(a + b)
        turn = (b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0]
        faces = [[0, 1, 2]] if turn > 0 else [[0, 2, 1]]          # counter-clockwise
        mesh = pds.PlanarMesh([a, b, c], faces, [True, True, False], region, 1.0)
        on_hole = np.flatnonzero(mesh.boundary_tags.values == 2)
        assert len(on_hole) == 1
        if straightened:
            with pytest.warns(UserWarning, match="1 boundary edge.* left straight"):
                q = mesh.quadratic()
            assert q.straightened.tolist() == on_hole.tolist()
            np.testing.assert_allclose(q.points[q.boundary_lines[on_hole[0], 2]], (a + b) / 2)
        else:                                   # room for the arc: curved, and valid
            q = mesh.quadratic()
            node = q.points[q.boundary_lines[on_hole[0], 2]]
            assert len(q.straightened) == 0 and abs(np.linalg.norm(node) - 1) < 1e-12
        assert len(q.inverted) == 0 and (q.min_jacobian > 0).all()


def test_quadratic_check_reports_an_inverted_triangle(plate):
    import dataclasses
    from pds_plugin.quadratic import _min_jacobian
    q = plate.quadratic()
    points = np.array(q.points)
    triangle = q.triangles[0]
    points[triangle[3]] = points[triangle[2]] * 3 - points[triangle[0]] - points[triangle[1]]
    assert _min_jacobian(points[q.triangles[:1]])[0] < 0
    assert len(dataclasses.replace(q, min_jacobian=_min_jacobian(points[q.triangles])).inverted)


def test_the_quadratic_certificate_fails_a_nearly_folded_curved_triangle(tmp_path):
    """The triangle of the test above with its third vertex at 1.3 and 1.5 times the hole's
    radius: the arc's node is kept both times (its triangle is not inverted), but at 1.3 the
    map shrinks some area element about thirty-fold."""
    region = pds.load_svg(_svg(tmp_path, '<path fill-rule="evenodd" d="M-2 -2H2V2H-2Z '
                               'M1 0A1 1 0 0 1 -1 0A1 1 0 0 1 1 0Z"/>', view="-2 -2 4 4"))
    hole = region.rings[1]
    angle = np.arctan2(hole[:, 1], hole[:, 0])
    a, b = hole[np.argmin(np.abs(angle))], hole[np.argmin(np.abs(angle - np.pi / 2))]
    for radius, passes in ((1.3, False), (1.5, True)):
        c = radius * (a + b) / np.linalg.norm(a + b)
        turn = (b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0]
        faces = [[0, 1, 2]] if turn > 0 else [[0, 2, 1]]
        q = pds.PlanarMesh([a, b, c], faces, [True, True, False], region, 1.0).quadratic()
        report = q.certificate().quadratic
        assert len(q.straightened) == 0 and len(q.inverted) == 0
        assert report.min_jacobian == q.min_jacobian.min() > 0
        assert report.ok is passes and report.below_bound == (0 if passes else 1)
        assert ("FAILED" in str(report)) is not passes


def test_the_quadratic_certificate_is_the_linear_one_and_its_jacobians(tmp_path):
    import dataclasses
    import json
    disc = pds.load_svg(_svg(tmp_path, '<circle r="1"/>'))
    mesh = pds.mesh_region(disc, 0.2)
    q = mesh.quadratic()
    cert = q.certificate()
    assert mesh.certificate().ok and cert.ok and mesh.certificate().quadratic is None
    assert cert.quadratic.min_jacobian == q.min_jacobian.min() > 0.5
    assert json.loads(json.dumps(cert.as_dict()))["quadratic"]["ok"] is True
    assert "quadratic    min Jacobian" in str(cert)
    # the check is exact: the Jacobian sampled densely over every triangle stays above it
    u, v = np.meshgrid(np.linspace(0, 1, 21), np.linspace(0, 1, 21))
    keep = u + v <= 1
    u, v = u[keep], v[keep]
    gradients = np.stack([                       # d(shape functions)/du and /dv at (u, v)
        [4 * u + 4 * v - 3, 4 * u - 1, 0 * u, 4 - 8 * u - 4 * v, 4 * v, -4 * v],
        [4 * u + 4 * v - 3, 0 * u, 4 * v - 1, -4 * u, 4 * u, 4 - 4 * u - 8 * v]])
    nodes = q.points[q.triangles]                               # (M, 6, 2)
    jac = np.einsum("dkp,mkc->mpdc", gradients, nodes)          # (M, P, 2, 2)
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    corners = mesh.vertices[mesh.faces]          # relative to the linear mesh's triangle
    straight = np.abs(np.linalg.det(np.stack([corners[:, 1] - corners[:, 0],
                                              corners[:, 2] - corners[:, 0]], axis=1)))
    sampled = (det / straight[:, None]).min(axis=1)
    assert (sampled >= q.min_jacobian - 1e-12).all()
    assert (sampled - q.min_jacobian).min() < 0.05   # and it is reached (to the grid's step)
    # one curved triangle below the bound, and the certificate is no longer ok
    low = q.min_jacobian.copy()
    low[int(np.argmin(low))] = 0.05
    worse = dataclasses.replace(q, min_jacobian=low).certificate()
    assert not worse.ok and not worse.ok_with_exceptions and worse.quadratic.below_bound == 1


# --- convergence (the target) ----------------------------------------------

def _l2_error(m, element, intorder):
    from skfem import Basis, Functional, asm, condense, solve
    from skfem.models.poisson import laplace, unit_load

    basis = Basis(m, element, intorder=intorder)
    u = solve(*condense(asm(laplace, basis), asm(unit_load, basis), D=basis.get_dofs()))

    @Functional
    def squared(w):
        return (w["u"] - (1 - w.x[0] ** 2 - w.x[1] ** 2) / 4) ** 2
    return np.sqrt(squared.assemble(basis, u=basis.interpolate(u)))


def test_p1_and_p2_converge_on_the_unit_disc_from_an_svg_circle(tmp_path):
    """-Δu = 1 on the unit disc, u = 0 on the circle: u = (1 - r²)/4."""
    from skfem import ElementTriP1, ElementTriP2

    disc = pds.load_svg(_svg(tmp_path, '<circle r="1"/>'), tolerance=1e-6)
    alphas = np.array([0.2, 0.1, 0.05])
    errors = {1: [], 2: []}
    for alpha in alphas:
        mesh = pds.mesh_region(disc, alpha)
        errors[1].append(_l2_error(mesh.to_skfem(1), ElementTriP1(), 4))
        errors[2].append(_l2_error(mesh.to_skfem(2), ElementTriP2(), 6))
    rate = {k: np.polyfit(np.log(alphas), np.log(e), 1)[0] for k, e in errors.items()}
    assert rate[1] >= 1.8, errors[1]
    assert rate[2] >= 2.8, errors[2]


def test_dxf_layers_name_the_boundaries_and_its_arcs_carry_the_mid_nodes(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    document = ezdxf.new()
    space = document.modelspace()
    space.add_lwpolyline([(0, 0, 0), (4, 0, 0), (4, 2, 1), (0, 2, 0)], format="xyb",
                         close=True, dxfattribs={"layer": "OUTLINE"})  # a semicircle on top
    space.add_circle((1, 1), radius=0.4, dxfattribs={"layer": "HOLES"})
    document.saveas(tmp_path / "plate.dxf")
    mesh = pds.mesh_region(pds.load_dxf(tmp_path / "plate.dxf"), 0.1)
    tags = boundary_tags(mesh, by="source")
    assert tags.names == {"OUTLINE": 1, "HOLES": 2} and (tags.values > 0).all()
    np.testing.assert_array_equal(tags.values == 2, mesh.boundary_tags.values == 2)
    q = mesh.quadratic()
    hole = np.unique(q.boundary_lines[tags.values == 2])
    assert np.abs(np.linalg.norm(q.points[hole] - (1, 1), axis=1) - 0.4).max() < 1e-12
    outline = q.points[np.unique(q.boundary_lines[tags.values == 1])]
    top = outline[outline[:, 1] > 2 + 1e-9]                 # the bulge: centre (2, 2), r 2
    assert len(top) and np.abs(np.linalg.norm(top - (2, 2), axis=1) - 2).max() < 1e-12
    assert len(q.inverted) == 0


def test_the_same_input_gives_the_same_tags_and_nodes_bit_for_bit(tmp_path):
    region = pds.load_svg(_svg(tmp_path, '<circle id="rim" r="1"/>'))
    first, second = (pds.mesh_region(region, 0.15) for _ in range(2))
    assert np.array_equal(first.quadratic().points, second.quadratic().points)
    assert np.array_equal(first.boundary_tags.values, second.boundary_tags.values)
    assert np.array_equal(first.to_skfem(2).doflocs, second.to_skfem(2).doflocs)


def test_isolated_samples_are_left_out_of_the_skfem_mesh(plate):
    extra = np.vstack([plate.vertices, [[4.5, 1.5]]])         # in no triangle
    mesh = pds.PlanarMesh(extra, plate.faces, np.r_[plate.on_boundary, False],
                          plate.region, plate.alpha)
    for order in (1, 2):
        m = mesh.to_skfem(order)
        assert m.t.max() + 1 == len(plate.vertices) and m.nvertices == len(plate.vertices)
        assert set(m.boundaries) == set(plate.boundary_tags.names)
    assert np.array_equal(mesh.to_skfem(2).doflocs, plate.to_skfem(2).doflocs)


def test_curve_pieces_locate_points_and_halve_arc_length():
    from pds_plugin.boundary_curves import curves_builder
    build = curves_builder(1e-6)
    build.arc((1, 1), [[2, 0.5], [0, 1]], 0.3, 2.0, "skewed ellipse")
    build.cubic([(0, 0), (1, 2), (2, -1), (3, 1)], "s-curve")
    curves = build.done()
    for piece in range(2):
        t = np.linspace(0, 1, 200_001)
        dense = curves.point(np.full(len(t), piece), t)
        along = np.r_[0, np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))]
        for t0, t1 in ((0.0, 1.0), (0.1, 0.7), (0.9, 0.2)):
            middle = curves.arc_midpoint([piece], [t0], [t1])[0]
            def s(u):
                return np.interp(u, t, along)
            assert abs(abs(s(middle) - s(t0)) - abs(s(t1) - s(middle))) < 1e-8
        on = dense[::997]                                   # points on the piece, nudged
        nudged = on + 1e-4 * np.array([0.6, -0.8])
        found, _, distance = curves.locate(nudged)
        assert (found == piece).all() and (distance <= 1e-4 + 1e-12).all()
        assert np.linalg.norm(curves.point(found, curves.locate(on)[1]) - on, axis=1).max() < 1e-9


def test_a_real_drawing_goes_out_quadratic_with_its_elements_named():
    from conftest import shared_file
    with pytest.warns(UserWarning, match="stroke end"):        # two open strokes in it
        region = pds.load_svg(shared_file("MIL.svg"))
    mesh = pds.mesh_region(region, 30.0)
    with pytest.warns(UserWarning, match="left straight"):     # corners under 30° unsampled
        q = mesh.quadratic()
    assert len(q.inverted) == 0 and 0 < len(q.straightened) <= 0.01 * len(q.boundary_lines)
    curved = np.delete(q.boundary_lines, q.straightened, axis=0)
    nodes = q.points[np.unique(curved)]
    _, _, distance = region.curves.locate(nodes)
    assert distance.max() < 1e-9 * np.ptp(nodes, axis=0).max()       # on the true curves
    straight = q.boundary_lines[q.straightened]
    np.testing.assert_allclose(q.points[straight[:, 2]], q.points[straight[:, :2]].mean(axis=1))
    sources = boundary_tags(mesh, by="source")
    assert (sources.values > 0).all() and set(sources.names) == set(region.curves.labels)
    assert (mesh.boundary_tags.values > 0).all()


@pytest.mark.parametrize("order", [1, 2])
def test_dolfinx_files_hold_one_grid_each_with_its_tags(plate, tmp_path, order):
    import xml.etree.ElementTree as ElementTree
    from pds_plugin.sinks.fem import write_dolfinx
    domain, facets = write_dolfinx(plate, tmp_path / "plate.xdmf", order=order)
    m = plate.to_meshio(order)
    for path, block, name in ((domain, 0, "region"), (facets, 1, "boundary")):
        grids = ElementTree.parse(path).getroot().findall(".//Grid")
        assert [g.get("Name") for g in grids] == ["Grid"]          # dolfinx's name="Grid"
        back = meshio.read(path)
        assert len(back.cells) == 1 and back.cells[0].type == m.cells[block].type
        np.testing.assert_array_equal(back.points, m.points)
        np.testing.assert_array_equal(back.cells[0].data, m.cells[block].data)
        np.testing.assert_array_equal(back.cell_data[name][0], m.cell_data[name][block])
    with pytest.raises(ArgumentError, match=r"\.xdmf"):
        write_dolfinx(plate, tmp_path / "plate.msh")


@pytest.mark.parametrize("graded", [False, True])
def test_boundary_samples_of_a_drawn_circle_are_on_the_circle(tmp_path, graded):
    disc = pds.load_svg(_svg(tmp_path, '<circle r="1"/>'))
    mesh = pds.mesh_region(disc, 0.2, graded=graded)
    assert mesh.certificate().ok
    radius = np.linalg.norm(mesh.vertices[mesh.on_boundary], axis=1)
    assert np.abs(radius - 1).max() <= 4e-16
    assert np.abs(np.linalg.norm(np.concatenate(disc.rings), axis=1) - 1).max() <= 4e-16
    assert mesh.quadratic().moved == 0                  # nothing left to move
    again = pds.mesh_region(disc, 0.2, graded=graded)   # bit for bit
    np.testing.assert_array_equal(again.vertices, mesh.vertices)


def test_a_move_onto_the_curve_past_the_samplings_bounds_is_undone():
    from pds_plugin.boundary_curves import curves_builder, samples_onto_curves
    build = curves_builder(0.01)
    build.arc((0, 0), np.eye(2), 0.0, np.pi, "upper")
    build.arc((0, 0), np.eye(2), np.pi, np.pi, "lower")
    curves = build.done()
    theta = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    ring = np.column_stack([np.cos(theta), np.sin(theta)])           # sagitta 0.0085
    samples = (ring + np.roll(ring, -1, axis=0))[::3] / 2            # chord middles
    chord = np.hypot(*(np.roll(samples, -1, axis=0) - samples).T)
    [moved], geometry = samples_onto_curves(curves, [ring], [(0, None)], [samples], 0.1, np.inf)
    assert np.allclose(np.hypot(*moved.T), 1, rtol=0, atol=1e-15)   # all onto the circle
    assert geometry.is_valid and len(geometry.geoms[0].exterior.coords) == 24 + 8 + 1
    grown = np.hypot(*(np.roll(moved, -1, axis=0) - moved).T)
    assert (grown > chord).all()                     # moving out lengthens every chord
    # with the longest chord allowed between the two: every move is undone
    [kept], none = samples_onto_curves(curves, [ring], [(0, None)], [samples], 0.1,
                                       0.5 * (chord.max() + grown.min()))
    np.testing.assert_array_equal(kept, samples)
    assert none is None


def test_the_certificate_measures_the_mesh_against_the_exact_curves(tmp_path, plate):
    disc = pds.load_svg(_svg(tmp_path, '<circle r="1"/>'))
    mesh = pds.mesh_region(disc, 0.2)
    boundary = mesh.vertices[mesh.boundary_edges]                  # chords of the circle
    half = np.arcsin(np.clip(np.hypot(*(boundary[:, 1] - boundary[:, 0]).T) / 2, 0, 1))
    sagitta = (1 - np.cos(half)).max()                             # exact: samples on it
    cert = mesh.certificate()
    assert cert.ok                                   # probes alpha/50 apart: the middle
    assert 0 <= sagitta - cert.curve_deviation * mesh.alpha <= (mesh.alpha / 100) ** 2
    assert cert.curve_deviation >= cert.boundary_deviation - 1e-12   # the polygon is inside
    assert "exact curves within" in str(cert) and plate.certificate().curve_deviation is None
