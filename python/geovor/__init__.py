"""geovor: exact Voronoi cells, Delaunay triangulations and nearest sites on the Earth.

- SphericalVoronoi: a drop-in for scipy.spatial.SphericalVoronoi, exact on any input.
- Index: a nearest-site index over latitude/longitude sites (the same file as `geovor index`).
- cells, delaunay, relax: the `geovor` command's layers as GeoDataFrames.
- geovor.dask: the nearest-site join of a Dask DataFrame against a saved index.
"""
from ._spherical_voronoi import SphericalVoronoi
from ._index import Index
from ._layers import GeometryWarning, HiddenSiteWarning, balance, cells, delaunay, relax

__all__ = ["SphericalVoronoi", "Index", "cells", "delaunay", "relax", "balance", "GeometryWarning", "HiddenSiteWarning"]
__version__ = "0.1.0"
