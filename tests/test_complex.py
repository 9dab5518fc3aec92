"""solid_alpha_complex: exactly the Delaunay triangles of circumradius <= alpha."""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from shapely.geometry import box

import pds_plugin as pds
from conftest import delaunay_alpha_faces, face_set


def signed_areas(points, faces):
    a, b, c = (points[faces[:, k]] for k in range(3))
    return 0.5 * ((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])


def assert_valid_triangulation(points, faces):
    """Counter-clockwise, every edge in at most two triangles, no overlap (the areas add
    up to the area of the union, which shapely computes independently)."""
    import shapely
    assert (signed_areas(points, faces) > 0).all()
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    assert np.unique(edges, axis=0, return_counts=True)[1].max(initial=0) <= 2
    union = shapely.union_all(shapely.polygons(points[faces]))
    assert np.isclose(union.area, signed_areas(points, faces).sum(), rtol=1e-9)


@settings(max_examples=40, deadline=None)
@given(n=st.integers(3, 400), seed=st.integers(0, 2**32 - 1), scale=st.floats(0.3, 3.0))
def test_equals_the_delaunay_oracle_on_random_points(n, seed, scale):
    points = np.random.default_rng(seed).random((n, 2))
    alpha = scale / np.sqrt(n)
    faces = pds.solid_alpha_complex(points, alpha)
    assert face_set(faces) == face_set(delaunay_alpha_faces(points, alpha))
    assert_valid_triangulation(points, faces)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), alpha=st.floats(0.03, 0.1))
def test_equals_the_oracle_on_poisson_samples(seed, alpha):
    region = pds.Region.from_shapely(box(0, 0, 1, 1).difference(box(0.3, 0.3, 0.5, 0.6)))
    points = pds.poisson_disc(region, alpha, seed=seed).points
    faces = pds.solid_alpha_complex(points, alpha)
    assert face_set(faces) == face_set(delaunay_alpha_faces(points, alpha))


@pytest.mark.parametrize("shape", [(7, 9), (20, 3)])
def test_cocircular_lattice_gives_one_valid_triangulation(shape):
    """Every square of a lattice has four cocircular corners: ties must be broken the
    same way by all four triangles, so the squares are split, never doubled."""
    points = np.stack(np.meshgrid(np.arange(shape[0]), np.arange(shape[1])), -1).reshape(-1, 2)
    points = points.astype(float) * 0.1
    faces = pds.solid_alpha_complex(points, 0.1 / np.sqrt(2) * 1.0001)
    assert len(faces) == 2 * (shape[0] - 1) * (shape[1] - 1)
    assert_valid_triangulation(points, faces)
    assert np.isclose(signed_areas(points, faces).sum(), 0.01 * (shape[0] - 1) * (shape[1] - 1))


def test_twelve_cocircular_points_are_split_once():
    angles = np.arange(12) * np.pi / 6
    ring = np.column_stack([np.cos(angles), np.sin(angles)])
    faces = pds.solid_alpha_complex(ring, 1.0001)         # every triangle has R = 1
    assert len(faces) == 10
    assert_valid_triangulation(ring, faces)
    assert len(pds.solid_alpha_complex(ring, 0.99)) == 0


def test_output_is_deterministic_and_counter_clockwise():
    points = np.random.default_rng(1).random((500, 2))
    a = pds.solid_alpha_complex(points, 0.08)
    b = pds.solid_alpha_complex(points.copy(), 0.08)
    assert np.array_equal(a, b) and a.dtype == np.int64
    assert (signed_areas(points, a) > 0).all()


def test_input_is_not_modified():
    points = np.random.default_rng(2).random((100, 2))
    before = points.copy()
    pds.solid_alpha_complex(points, 0.2)
    assert np.array_equal(points, before)


def test_too_few_points_give_no_triangle():
    assert pds.solid_alpha_complex(np.zeros((2, 2)) + [[0, 0], [1, 0]], 1.0).shape == (0, 3)


@pytest.mark.parametrize("points, message", [
    (np.zeros((4, 3)), r"\(N, 2\) array"),
    ([[0, 0], [1, 0], [np.nan, 1]], "NaN or infinite"),
    ([[0, 0], [1, 0], [0, 1], [1, 0]], "points 1 and 3 are the same point"),
])
def test_bad_points_are_refused(points, message):
    with pytest.raises(ValueError, match=message):
        pds.solid_alpha_complex(points, 1.0)


@pytest.mark.parametrize("boundary, message", [
    ([[0, 1, 2], [3, 4, 4]], r"distinct and in \[0, 6\); got \[3, 4, 4\]"),   # the ring named
    ([[0, 1, 2], [3, 4, 6], [5, 5, 3]], r"got \[3, 4, 6\]"),          # the first wrong one
    ([[0, 1, -1]], r"got \[0, 1, -1\]"),
    ([[0, 1]], "at least 3 point indices"),
    ([[0.0, 1.0, 2.0]], "at least 3 point indices"),
])
def test_bad_boundary_rings_are_refused(boundary, message):
    points = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [2, 1]], float)
    with pytest.raises(ValueError, match=message):
        pds.solid_alpha_complex(points, 1.0, boundary=boundary)


def test_bad_alpha_is_refused():
    with pytest.raises(ValueError, match="alpha must be a positive finite number"):
        pds.solid_alpha_complex(np.random.default_rng(0).random((5, 2)), -1)


@pytest.mark.parametrize("centre", [0.0, 10.0])
def test_many_cocircular_points_are_refused_quickly(centre):
    """100 points on a circle (about the origin: ties left to the integer test; away
    from it: settled in the kernel): every triangle ties, and the exact tie-break's work
    grows with the fourth power of their number."""
    angles = np.arange(100) * 2 * np.pi / 100
    circle = np.column_stack([np.cos(angles), np.sin(angles)]) + centre
    with pytest.raises(pds.PdsError, match="cocircular"):
        pds.solid_alpha_complex(circle, 1.5)


@pytest.mark.parametrize("centre", [0.0, 10.0])
def test_a_few_dozen_cocircular_points_are_split_once(centre):
    angles = np.arange(24) * 2 * np.pi / 24
    circle = np.column_stack([np.cos(angles), np.sin(angles)]) + centre
    faces = pds.solid_alpha_complex(circle, 1.5)
    assert len(faces) == 22
    assert_valid_triangulation(circle, faces)


def test_an_alpha_far_above_the_spacing_is_refused_before_any_work():
    points = np.random.default_rng(0).random((5000, 2))
    with pytest.raises(pds.PdsError, match="within 2 alpha"):
        pds.solid_alpha_complex(points, 10.0)


def test_points_spanning_the_float_range_are_refused():
    with pytest.raises(pds.PdsError, match="coordinates below 1e"):
        pds.solid_alpha_complex(np.array([[1e308, 1e308], [-1e308, 0], [0, 1]]), 0.5)


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), scale=st.sampled_from([1.0, 1e-8, 1e8]))
def test_orientation_sign_is_exact_on_nearly_collinear_points(seed, scale):
    """The segment-crossing test of the constrained complex rests on this sign."""
    from fractions import Fraction
    from pds_plugin._visibility_kernels import orient
    rng = np.random.default_rng(seed)
    a, b = rng.random(2) * scale, rng.random(2) * scale
    t = rng.random()
    c = a + t * (b - a) + rng.integers(-2, 3, 2) * np.spacing(scale)   # on the line, or an ulp off
    exact = ((Fraction(a[0]) - Fraction(c[0])) * (Fraction(b[1]) - Fraction(c[1]))
             - (Fraction(a[1]) - Fraction(c[1])) * (Fraction(b[0]) - Fraction(c[0])))
    assert orient(*a, *b, *c) == (exact > 0) - (exact < 0)


@settings(max_examples=200, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), scale=st.sampled_from([1.0, 1e-8, 1e8]),
       shared=st.sets(st.sampled_from(["ax=cx", "by=cy", "ay=cy", "bx=cx"]), min_size=1))
def test_orientation_sign_is_exact_with_shared_coordinates(seed, scale, shared):
    """Points on axis-parallel lines through each other (a box's corner on a chord's
    line), tiny differences among them: the shortcut for exact zeros agrees with exact
    rationals."""
    from fractions import Fraction
    from pds_plugin._visibility_kernels import orient
    rng = np.random.default_rng(seed)
    (ax, ay), (bx, by), (cx, cy) = (1 + rng.integers(-3, 4, (3, 2)) * 2e-16) * scale
    ax, by = (cx if "ax=cx" in shared else ax), (cy if "by=cy" in shared else by)
    ay, bx = (cy if "ay=cy" in shared else ay), (cx if "bx=cx" in shared else bx)
    exact = ((Fraction(ax) - Fraction(cx)) * (Fraction(by) - Fraction(cy))
             - (Fraction(ay) - Fraction(cy)) * (Fraction(bx) - Fraction(cx)))
    assert orient(ax, ay, bx, by, cx, cy) == (exact > 0) - (exact < 0)


def perturbed_inside_oracle(a, b, c, d, ranks) -> int:
    """The incircle sign of (a, b, c; d) in exact rationals, a tie settled by lifting
    each point by -eps**rank (the smallest rank perturbed most): the 4x4 determinant
    of rows (x, y, x² + y² - eps**rank, 1) expanded in the perturbations."""
    from fractions import Fraction
    rows = [[Fraction(v) for v in p] for p in (a, b, c, d)]

    def det3(m):
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))

    def minor(k):   # the rows but k, columns (x, y, 1)
        return [[x, y, 1] for i, (x, y) in enumerate(rows) if i != k]
    lifted = sum((-1) ** k * (x * x + y * y) * det3(minor(k)) for k, (x, y) in enumerate(rows))
    if lifted:
        return 1 if lifted > 0 else -1
    for k in sorted(range(4), key=lambda k: ranks[k]):
        factor = -((-1) ** k) * det3(minor(k))      # the factor of -eps**rank[k]
        if factor:
            return 1 if factor > 0 else -1
    raise AssertionError("a, b, c are collinear")


@settings(max_examples=300, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(["lattice", "circle", "ulp"]))
def test_the_kernels_tie_break_is_exact(seed, kind):
    """The kernel's exact incircle (expansions) and its perturbation agree with rational
    arithmetic where the filter cannot decide: exactly cocircular points (a lattice's
    rectangles), points on a float circle, and both an ulp off."""
    from pds_plugin import _complex_kernels as kern
    rng = np.random.default_rng(seed)
    centre = rng.uniform(10, 50, 2)         # every difference an exact float (Sterbenz)
    if kind == "lattice":
        step = rng.uniform(0.1, 2.0, 2)
        points = centre + rng.integers(0, 3, (4, 2)) * step
    else:
        angles = np.sort(rng.random(4)) * 2 * np.pi
        points = centre + rng.uniform(0.1, 3.0) * np.column_stack([np.cos(angles), np.sin(angles)])
    if kind == "ulp":
        points = points + rng.integers(-2, 3, (4, 2)) * np.spacing(points)
    a, b, c, d = points
    cross = (b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0]
    if len(np.unique(points, axis=0)) < 4 or cross == 0:
        return
    if cross < 0:
        points = points[[0, 2, 1, 3]]
    ranks = rng.permutation(4)
    sign = kern.tie_sign(np.ascontiguousarray(points), 0, 1, 2, 3, ranks.astype(np.int64))
    assert sign == perturbed_inside_oracle(*points, ranks)


def test_ties_off_exact_differences_are_left_to_the_integer_test():
    """A difference of coordinates that is not an exact float (points spanning
    magnitudes) is not the kernel's: it says 0, and local_complex's integer test settles
    the tie; the lattice is still split once."""
    from pds_plugin import _complex_kernels as kern
    square = np.array([[-0.1, -0.1], [1e-17, -0.1], [1e-17, 1e-17 + 0.1], [-0.1, 0.1]])
    assert kern.tie_sign(square, 0, 1, 2, 3, np.arange(4)) == 0
    points = np.stack(np.meshgrid(np.arange(6), np.arange(5)), -1).reshape(-1, 2) * 0.1 - 0.2
    faces = pds.solid_alpha_complex(points, 0.1 / np.sqrt(2) * 1.0001)
    assert len(faces) == 2 * 5 * 4
    assert_valid_triangulation(points, faces)


@pytest.mark.parametrize("power", [-130, 130, 252, 266, 332])
def test_far_scales_give_the_same_triangles_or_a_clean_refusal(power):
    """The complex of points scaled by a power of two (exact) is the same triangulation
    or a clean refusal: never another one. Coordinates beyond 1e50 are refused (the
    predicates raise them to powers of up to six: at 2^252 the circumradius test
    overflowed and the triangles overlapped), as a region's are; below, ties beyond the
    expansions' range go to the integer test."""
    scale = 2.0 ** power
    import warnings
    points = np.random.default_rng(0).random((300, 2))
    reference = pds.solid_alpha_complex(points, 0.1)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)    # the filter's overflow
            faces = pds.solid_alpha_complex(points * scale, 0.1 * scale)
    except pds.PdsError:
        return
    assert face_set(faces) == face_set(reference)


def test_a_lattice_off_the_axes_is_settled_in_the_kernel():
    """Lattice squares away from zero (every difference exact, as in a remesh's laid-out
    patches): no triangle is left to the integer test."""
    from pds_plugin import _complex_kernels as kern
    from pds_plugin._visibility_kernels import no_chords
    points = (np.stack(np.meshgrid(np.arange(9), np.arange(7)), -1).reshape(-1, 2) * 0.37 + 20.0)
    order, start = kern.bin_points(points, 20.0, 20.0, 0.5, 7, 6)
    faces, flags, status = kern.local_complex(points[order], 0.37 / np.sqrt(2) * 1.0001, start,
                                              20.0, 20.0, 0.5, 7, 6, 64, no_chords(len(points)),
                                              order)
    assert status == kern.COMPLETE and len(faces) == 2 * 8 * 6
    assert not (flags == kern.UNSURE).any()
    assert_valid_triangulation(points[order], faces)


def test_boundary_keeps_triangles_out_of_a_notch():
    """The constrained complex of a V-notched pentagon: no triangle spans the notch, and
    the union of the triangles is the pentagon."""
    import shapely
    points = np.array([[0, 0], [2, 0], [2, 2], [1, 0.2], [0, 2]], float)
    faces = pds.solid_alpha_complex(points, 3.0, boundary=[[0, 1, 2, 3, 4]])
    union = shapely.union_all(shapely.polygons(points[faces]))
    assert union.symmetric_difference(shapely.Polygon(points)).area == 0
    assert_valid_triangulation(points, faces)
    bridged = pds.solid_alpha_complex(points, 3.0)
    assert shapely.union_all(shapely.polygons(points[bridged])).area > union.area
