"""geovor.SphericalVoronoi against scipy's SphericalVoronoi (where scipy is right) and against
the definition of a Voronoi diagram (brute-force distances), on random and degenerate inputs."""
import itertools

import numpy as np
import pytest
from scipy.spatial import SphericalVoronoi as ScipyVoronoi
from scipy.spatial import distance

import geovor
from geovor import _geovor


def sphere_points(n, seed):
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(n, 3))
    return p / np.linalg.norm(p, axis=1)[:, None]


def check_voronoi(sv, tol=1e-9):
    """Every vertex is on the sphere, equidistant from the points whose regions hold it, and no
    point is closer to it (brute force); the areas sum to the sphere's."""
    unit_vertices = (sv.vertices - sv.center) / sv.radius
    np.testing.assert_allclose(np.linalg.norm(unit_vertices, axis=1), 1.0, atol=1e-12)
    unit_points = (sv.points - sv.center) / sv.radius
    unit_points /= np.linalg.norm(unit_points, axis=1)[:, None]
    dist = distance.cdist(unit_vertices, unit_points)
    nearest = dist.min(axis=1)
    for i, region in enumerate(sv.regions):
        for v in region:
            assert dist[v, i] == pytest.approx(nearest[v], abs=tol), (i, v)
    assert sv.calculate_areas().sum() == pytest.approx(4 * np.pi * sv.radius**2, rel=1e-12)


def regions_as_positions(sv, decimals=9):
    """Each region as the set of its rounded vertex positions (vertex numbering differs)."""
    out = []
    for region in sv.regions:
        out.append(frozenset(tuple(np.round(sv.vertices[v], decimals) + 0.0) for v in region))
    return out


@pytest.mark.parametrize("n,seed", [(4, 1), (10, 2), (100, 3), (2000, 4)])
def test_agrees_with_scipy_on_random_points(n, seed):
    points = sphere_points(n, seed)
    ours, theirs = geovor.SphericalVoronoi(points), ScipyVoronoi(points)
    assert ours.vertices.shape == theirs.vertices.shape == (2 * n - 4, 3)
    np.testing.assert_allclose(ours.calculate_areas(), theirs.calculate_areas(), rtol=1e-9, atol=1e-14)
    assert regions_as_positions(ours) == regions_as_positions(theirs)
    check_voronoi(ours)


@pytest.mark.parametrize("radius", [0.5, 1.0, 6371008.8])
@pytest.mark.parametrize("center", [None, (1.0, 2.0, 3.0)])
def test_radius_and_center(radius, center):
    unit = sphere_points(50, 5)
    c = np.zeros(3) if center is None else np.array(center)
    sv = geovor.SphericalVoronoi(unit * radius + c, radius=radius, center=center)
    assert sv.points.dtype == np.float64 and sv.center.dtype == np.float64
    assert isinstance(sv.radius, float)
    ref = geovor.SphericalVoronoi(unit)
    assert sv.regions == ref.regions
    np.testing.assert_allclose(sv.vertices, ref.vertices * radius + c, rtol=1e-12, atol=1e-12 * radius)
    np.testing.assert_allclose(sv.calculate_areas(), ref.calculate_areas() * radius**2, rtol=1e-12)
    check_voronoi(sv)


def test_one_hemisphere():
    points = sphere_points(10, 0)
    points[:, 0] = np.abs(points[:, 0])
    sv = geovor.SphericalVoronoi(points)
    check_voronoi(sv)
    np.testing.assert_allclose(sv.calculate_areas(), ScipyVoronoi(points).calculate_areas(), rtol=1e-9)


def test_fewer_than_four_points():
    # One point: the whole sphere; two: hemispheres; three: three lunes through the poles of
    # their plane.
    one = geovor.SphericalVoronoi([[0.0, 0.0, 1.0]])
    assert one.calculate_areas().tolist() == [pytest.approx(4 * np.pi)]
    assert one.regions == [[]]
    two = geovor.SphericalVoronoi([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    np.testing.assert_allclose(two.calculate_areas(), [2 * np.pi, 2 * np.pi])
    three = geovor.SphericalVoronoi(np.eye(3))
    check_voronoi(three)
    # The three lunes meet at +-(1,1,1)/sqrt(3), each 120 degrees wide: 4 pi / 3 each.
    np.testing.assert_allclose(three.calculate_areas(), [4 * np.pi / 3] * 3, rtol=1e-12)
    expected = np.array([[1, 1, 1], [-1, -1, -1]]) / np.sqrt(3)
    assert distance.cdist(three.vertices, expected).min(axis=1).max() < 1e-12


def test_points_on_one_great_circle():
    # scipy refuses these ("Rank of input points"); the cells are lunes meeting at the poles.
    angles = np.sort(np.random.default_rng(7).uniform(0, 2 * np.pi, 12))
    points = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(12)])
    with pytest.raises(ValueError):
        ScipyVoronoi(points)
    sv = geovor.SphericalVoronoi(points)
    check_voronoi(sv)
    gaps = np.diff(np.concatenate([angles, [angles[0] + 2 * np.pi]]))
    # A lune's area is twice its width: the width is half of each neighbouring gap.
    width = (gaps + np.roll(gaps, 1)) / 2
    np.testing.assert_allclose(sv.calculate_areas(), 2 * width, rtol=1e-12)


@pytest.mark.parametrize("name", ["tetrahedron", "octahedron", "cube", "icosahedron"])
def test_regular_polyhedra_have_equal_areas(name):
    phi = (1 + np.sqrt(5)) / 2
    shapes = {
        "tetrahedron": [[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]],
        "octahedron": np.concatenate([np.eye(3), -np.eye(3)]),
        "cube": list(itertools.product([-1, 1], repeat=3)),
        "icosahedron": [p for a, b in itertools.product([-1, 1], repeat=2)
                        for p in ([0, a, b * phi], [a, b * phi, 0], [b * phi, 0, a])],
    }
    points = np.array(shapes[name], dtype=float)
    points /= np.linalg.norm(points, axis=1)[:, None]
    sv = geovor.SphericalVoronoi(points)
    check_voronoi(sv)
    np.testing.assert_allclose(sv.calculate_areas(), 4 * np.pi / len(points), rtol=1e-12)


def test_cube_vertices_are_the_octahedron():
    points = np.array(list(itertools.product([-1, 1], repeat=3)), dtype=float) / np.sqrt(3)
    sv = geovor.SphericalVoronoi(points)
    expected = np.concatenate([np.eye(3), -np.eye(3)])
    # Co-circular faces give two coincident vertices each: every vertex is one of the six.
    assert distance.cdist(sv.vertices, expected).min(axis=1).max() < 1e-12
    assert all(len({tuple(np.round(sv.vertices[v], 9)) for v in r}) == 3 for r in sv.regions)


def test_duplicates_are_merged_not_refused():
    points = sphere_points(30, 8)
    doubled = np.concatenate([points, points[:5], points[[3]]])
    with pytest.raises(ValueError):
        ScipyVoronoi(doubled)
    sv = geovor.SphericalVoronoi(doubled)
    ref = geovor.SphericalVoronoi(points)
    areas = sv.calculate_areas()
    np.testing.assert_allclose(areas[:30], ref.calculate_areas(), rtol=1e-12)
    assert areas[30:].tolist() == [0.0] * 6
    assert sv.regions[30:] == [[]] * 6
    assert sorted(map(tuple, sv.merged.tolist())) == [(30, 0), (31, 1), (32, 2), (33, 3), (34, 4), (35, 3)]
    assert sv.calculate_areas().sum() == pytest.approx(4 * np.pi, rel=1e-12)


def test_regions_are_counter_clockwise_from_outside():
    sv = geovor.SphericalVoronoi(sphere_points(200, 9))
    for i, region in enumerate(sv.regions):
        ring = sv.vertices[region]
        # The signed area of the region's fan about its point is positive.
        p = sv.points[i]
        signed = sum(np.dot(p, np.cross(ring[j], ring[(j + 1) % len(ring)])) for j in range(len(ring)))
        assert signed > 0
    before = [list(r) for r in sv.regions]
    sv.sort_vertices_of_regions()
    assert sv.regions == before


def test_regions_are_one_list_object_kept_like_scipys():
    """regions is made on first use, then the same list: edits and assignment stick, as in scipy."""
    points = sphere_points(50, 4)
    sv = geovor.SphericalVoronoi(points)
    ref = ScipyVoronoi(points)
    ref.sort_vertices_of_regions()
    regions = sv.regions
    assert regions is sv.regions
    assert all(type(r) is list and all(type(v) is int for v in r) for r in regions)
    assert sorted(map(len, regions)) == sorted(map(len, ref.regions))
    regions[0].append(-1)
    assert sv.regions[0][-1] == -1
    sv.regions = [[1, 2, 3]]
    assert sv.regions == [[1, 2, 3]]


def test_vertices_outlive_the_diagram():
    """vertices is the diagram's own array (no copy), kept alive by numpy after the object is gone."""
    points = sphere_points(100, 6)
    sv = geovor.SphericalVoronoi(points)
    vertices = sv.vertices
    expected = vertices.copy()
    del sv
    import gc
    gc.collect()
    geovor.SphericalVoronoi(sphere_points(100, 7))  # reuses freed memory, if any was freed
    assert np.array_equal(vertices, expected)
    assert np.allclose(np.linalg.norm(vertices, axis=1), 1, rtol=0, atol=1e-15)


def test_regions_lists_checks_its_arrays():
    assert _geovor.regions_lists(np.array([0, 2, 2, 3]), np.array([7, 8, 7], dtype=np.uint32)) == [[7, 8], [], [7]]
    with pytest.raises(ValueError):
        _geovor.regions_lists(np.array([0, 3, 2]), np.array([1, 2, 3], dtype=np.uint32))
    with pytest.raises(ValueError):
        _geovor.regions_lists(np.array([0, 4]), np.array([1, 2, 3], dtype=np.uint32))


@pytest.mark.parametrize("bad,message", [
    (np.zeros((3, 2)), "shape"),
    ([[1.0, 0.0, 0.0], [np.nan, 0.0, 1.0]], "point 1 is not finite"),
    ([[1.0, 0.0, 0.0], [0.0, 0.9, 0.0]], "Radius inconsistent"),
])
def test_bad_input(bad, message):
    with pytest.raises(ValueError, match=message):
        geovor.SphericalVoronoi(bad)
    with pytest.raises(ValueError, match="radius"):
        geovor.SphericalVoronoi(np.eye(3), radius=-1)
    with pytest.raises(ValueError, match="center"):
        geovor.SphericalVoronoi(np.eye(3), center=[0, 0])
