"""The periodic disc tile (pds_plugin.disc_tile) and the graded sampler seeded with it
(``graded_poisson_disc(..., tile=True)``, what pds.remesh uses on planar faces).

Oracles: brute-force nearest distances on the torus for the tile; for the sampler,
points drawn in every box it closes without darts, each checked against the samples
(distance within r at both ends, and the segment inside the region, by shapely); and
the graded certificate and separation of whole samplings.
"""

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import MultiPolygon, Point, box

import pds_plugin as pds
from pds_plugin import disc_tile, graded_sampling
from pds_plugin.graded_complex import graded_alpha_complex
from pds_plugin.graded_sampling import graded_poisson_disc
from pds_plugin.mesh import PlanarMesh
from pds_plugin.sizing import RadiusField, radius_field


def _torus_nearest(points, side, queries):
    """The distance from each query to the nearest point of the periodic sampling."""
    delta = queries[:, None, :] - points[None]
    delta -= side * np.round(delta / side)
    return np.hypot(delta[..., 0], delta[..., 1]).min(axis=1)


def test_the_shipped_tile_is_separated_and_covers_within_its_cover():
    tile = disc_tile.tile()
    assert len(tile.points) > 300 and tile.points.min() >= 0 and tile.points.max() < tile.side
    # separation, brute force over every pair across the tile's edges
    nearest = [_torus_nearest(np.delete(tile.points, k, axis=0), tile.side, tile.points[k:k + 1])[0]
               for k in range(len(tile.points))]
    assert min(nearest) >= 1.0
    # coverage: no point of the torus farther than the cover from the sampling
    queries = np.random.default_rng(0).random((20_000, 2)) * tile.side
    far = _torus_nearest(tile.points, tile.side, queries).max()
    assert far <= tile.cover < 1.0
    assert far > 0.9 * tile.cover                     # the cover is not a loose bound


def test_a_new_tile_is_a_maximal_disc_sampling_of_the_torus():
    points, side = disc_tile.make_tile(10, seed=4)
    assert disc_tile.periodic_separation(points, side) >= 1.0
    assert disc_tile.periodic_cover(points, side) <= 1.0
    queries = np.random.default_rng(1).random((5000, 2)) * side
    assert _torus_nearest(points, side, queries).max() <= 1.0


def _regions():
    """A plate with holes and a notch, an annulus, and far apart parts with an island
    in a hole (overlapping polygon boxes)."""
    plate = box(0, 0, 40, 25).difference(Point(12, 12).buffer(4)).difference(
        box(30, -1, 33, 10))
    ring = Point(0, 0).buffer(20).difference(Point(0, 0).buffer(6))
    frame = box(0, 0, 30, 30).difference(box(5, 5, 25, 25))
    apart = MultiPolygon([frame, box(8, 8, 22, 22), box(50, 0, 52, 30)])
    return [pds.Region.from_shapely(g) for g in (plate, ring, apart)]


def _check_closed(region, field):
    """Every box the tile closes, checked at 36 points: one of the 3 nearest samples is
    within r there and within its own r, the segment to it in the region."""
    sampler = graded_sampling._GradedSampler(region, field, 10**6)
    rng = np.random.default_rng(3)
    sampler.add_boundary(30.0, rng)
    sampler.kernel_field = graded_sampling.kern.Field(field)
    tiled = sampler._add_tile(rng)
    boxes = sampler._leaves()
    covered = sampler._tile_covered(boxes, *tiled)
    assert covered.any() and not covered.all()
    points, radius = sampler.points[:sampler.count], sampler.radius[:sampler.count]
    t = (np.arange(6) + 0.5) / 6
    x, y, s = (a[covered][:, None, None] for a in boxes[:3])
    grid = np.stack(np.broadcast_arrays(x + s * t[None, :, None], y + s * t[None, None, :]), -1)
    grid = grid.reshape(-1, 2)
    grid = grid[shapely.contains_xy(region.geometry, grid[:, 0], grid[:, 1])]
    r = field(grid)
    gap, nearest = cKDTree(points).query(grid, k=3)
    segments = shapely.linestrings(np.stack([np.repeat(grid[:, None], 3, 1), points[nearest]], 2))
    seen = shapely.covered_by(segments, region.geometry.buffer(1e-9 * field.cap))
    assert np.all(((gap <= np.minimum(r[:, None], radius[nearest])) & seen).any(axis=1))


@pytest.mark.parametrize("region", _regions(), ids=["plate", "annulus", "apart"])
@pytest.mark.parametrize("cap", [0.9, 0.45])
def test_the_boxes_closed_by_the_tile_are_covered(region, cap):
    _check_closed(region, radius_field(region, cap=cap))


@pytest.mark.parametrize("size", [0.02, 0.2])
def test_the_boxes_near_tile_points_with_a_smaller_radius_are_left_open(size):
    """A small radius in the middle of a square (a feature the field grades to): the
    tile's points there have r below the cap (holes in its cover), and the boxes beside
    them, where r is the cap, are not closed by them."""
    region = pds.Region.from_shapely(box(0, 0, 30, 30))
    _check_closed(region, RadiusField([[15.0, 15.0], [7.0, 21.0]], [size, size], 0.3, 0.6))


@pytest.mark.parametrize("region", _regions(), ids=["plate", "annulus", "apart"])
@pytest.mark.parametrize("seed", [0, 7])
def test_a_tiled_sampling_is_separated_maximal_and_certified(region, seed):
    field = radius_field(region, cap=0.6)
    samples = graded_poisson_disc(region, field, seed, tile=True)
    again = graded_poisson_disc(region, field, seed, tile=True)
    assert np.array_equal(samples.points, again.points)          # bit for bit
    assert len(np.unique(samples.points, axis=0)) == len(samples.points)
    faces = graded_alpha_complex(samples.points, samples.radius, field.grading,
                                 boundary=samples.rings, chords=samples.chords)
    mesh = PlanarMesh(samples.points, faces, samples.on_boundary, region, field.cap, True,
                      field=field)
    radius = field(mesh.vertices)
    a, b = mesh.edges.T
    gap = np.hypot(*(mesh.vertices[a] - mesh.vertices[b]).T)
    assert np.all(gap >= np.minimum(radius[a], radius[b]) * (1 - 1e-9))
    certificate = mesh.certificate()
    assert certificate.ok, str(certificate)
    other = graded_poisson_disc(region, field, seed + 1, tile=True)
    assert not np.array_equal(samples.points, other.points)


def test_no_tile_where_every_point_is_near_the_boundary():
    """Strips at most 4 covers wide get no tile point (no box there could be closed),
    and a region of only such strips no tile at all: darts as without one."""
    region = pds.Region.from_shapely(MultiPolygon([box(0, 0, 30, 1.9), box(0, 5, 1.9, 40)]))
    field = RadiusField(np.zeros((0, 2)), np.zeros(0), 0.2, 0.5)
    sampler = graded_sampling._GradedSampler(region, field, 10**6)
    rng = np.random.default_rng(2)
    sampler.add_boundary(30.0, rng)
    before = sampler.count
    assert sampler._add_tile(rng) is None and sampler.count == before
    samples = graded_poisson_disc(region, field, 2, tile=True)
    faces = graded_alpha_complex(samples.points, samples.radius, field.grading,
                                 boundary=samples.rings, chords=samples.chords)
    mesh = PlanarMesh(samples.points, faces, samples.on_boundary, region, field.cap, True,
                      field=field)
    assert mesh.certificate().ok
