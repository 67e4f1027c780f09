"""geovor: exact Voronoi cells, Delaunay triangulations and nearest sites on the Earth.

- SphericalVoronoi: a drop-in for scipy.spatial.SphericalVoronoi, exact on any input.
- Index: a nearest-site index over latitude/longitude sites (the same file as `geovor index`).
"""
from ._spherical_voronoi import SphericalVoronoi
from ._index import Index

__all__ = ["SphericalVoronoi", "Index"]
__version__ = "0.1.0"
