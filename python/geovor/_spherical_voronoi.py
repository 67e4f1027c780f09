"""geovor.SphericalVoronoi: a drop-in for scipy.spatial.SphericalVoronoi, exact on any input."""
import numpy as np

from . import _geovor

__all__ = ["SphericalVoronoi"]


class SphericalVoronoi:
    """Voronoi diagram of points on a sphere, with scipy.spatial.SphericalVoronoi's interface.

    The diagram is the exact dual of geovor's Delaunay triangulation (exact predicates), so it
    also works where scipy's raises or errs: fewer than 4 points, points in one hemisphere,
    co-circular points, and duplicates.

    Parameters
    ----------
    points : array_like, shape (npoints, 3)
        Points on the sphere (3-D only; scipy's 2-D circle case is not supported).
    radius : float, optional
        Radius of the sphere (default 1).
    center : array_like, shape (3,), optional
        Centre of the sphere (default the origin).
    threshold : float, optional
        Largest relative mismatch between a point's distance to the centre and `radius`
        (default 1e-06, as scipy). Unlike scipy, it is not a duplicate threshold: points are
        merged only when closer than 2**-24 of the radius (chord), and then listed in `merged`.

    Attributes
    ----------
    points, radius, center : as given (points as a float64 array).
    vertices : ndarray, shape (nvertices, 3)
        The Voronoi vertices: one per Delaunay triangle (2 n - 4 of them for n >= 3 distinct
        points), its circumcentre on the sphere. Co-circular points give coincident vertices.
    regions : list of lists of int
        regions[i]: the vertices of point i's cell, counter-clockwise seen from outside the
        sphere (already sorted). Empty for a merged point, and with fewer than 3 distinct points
        (one point: the whole sphere; two: two hemispheres, whose boundary has no vertex).
        Made on first use (construction and areas do not pay for a million Python lists).
    merged : ndarray of int, shape (nmerged, 2)
        Rows (i, j): input point i was merged into input point j (a duplicate, or closer than
        2**-24 of the radius); point i's region is empty and its area 0.

    Raises
    ------
    ValueError
        If points is not of shape (n, 3), not finite, center is not of shape (3,), radius is not
        positive, or a point is off the sphere by more than threshold * radius.
    """

    def __init__(self, points, radius=1.0, center=None, threshold=1e-06):
        self.points = np.array(points, dtype=np.float64)
        if self.points.ndim != 2 or self.points.shape[1] != 3:
            raise ValueError(f"points must have shape (n, 3), not {self.points.shape}")
        if not np.all(np.isfinite(self.points)):
            bad = int(np.flatnonzero(~np.all(np.isfinite(self.points), axis=1))[0])
            raise ValueError(f"point {bad} is not finite: {self.points[bad]}")
        self.radius = float(radius)
        if not (self.radius > 0 and np.isfinite(self.radius)):
            raise ValueError(f"radius must be a positive number, not {radius}")
        self.center = np.zeros(3) if center is None else np.array(center, dtype=np.float64)
        if self.center.shape != (3,):
            raise ValueError(f"center must have shape (3,), not {self.center.shape}")
        trivial = self.radius == 1 and not self.center.any()
        relative = self.points if trivial else (self.points - self.center) / self.radius
        norms = np.sqrt(np.einsum("ij,ij->i", relative, relative))
        if len(norms):
            worst = int(np.argmax(np.abs(norms - 1)))
            if abs(norms[worst] - 1) >= threshold:
                raise ValueError(
                    f"Radius inconsistent with generators: point {worst} is at distance "
                    f"{norms[worst] * self.radius!r} from the center, radius is {self.radius!r}")
        diagram = _geovor.spherical_voronoi(relative)  # normalized there
        unit_vertices = diagram["vertices"]
        if trivial:
            self.vertices = unit_vertices
        else:
            self.vertices = unit_vertices * self.radius + self.center
        self._region_offsets = diagram["region_offsets"]
        self._region_vertices = diagram["region_vertices"]
        self._regions = None
        self.merged = diagram["merged"]
        self._areas_sr = diagram["areas_sr"]
        self._site_of_input = diagram["site_of_input"]

    @property
    def regions(self):
        """list of lists of int: regions[i], the vertices of point i's cell (see the class doc).

        Made on first use from flat arrays (a million Python lists cost more than the diagram),
        then kept: the same list object every time, which may be modified or replaced as scipy's.
        """
        if self._regions is None:
            self._regions = _geovor.regions_lists(self._region_offsets, self._region_vertices)
        return self._regions

    @regions.setter
    def regions(self, value):
        self._regions = value

    def sort_vertices_of_regions(self):
        """Does nothing: the regions are counter-clockwise (seen from outside) from the start."""

    def calculate_areas(self):
        """The areas of the regions, in input order (summing to 4 pi radius**2).

        Each area is the exact cell's, computed from the sphere's vertices by a fan of solid
        angles (no cancellation for lunes of co-circular points); merged points get 0.
        """
        return self._areas_sr * self.radius**2
