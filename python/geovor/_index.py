"""geovor.Index: the exact nearest site of every query, over numpy arrays."""
import os

import numpy as np

from . import _geovor
from ._frames import ID_NAMES, find_column, frame_coordinates

__all__ = ["Index"]


class Index:
    """A nearest-site index: a Delaunay hierarchy over sites given by latitude/longitude (WGS84
    degrees), queried exactly (Keep, Jump & Climb), saved in the file format of `geovor index`.

    Sites closer than 0.38 m are merged into one site (the first); `sites()` lists which input
    rows each site holds. Site indices are the sites' ids: input rows in order, merged rows
    skipped.

    Parameters
    ----------
    lat, lon : array_like of float
        Site latitudes and longitudes in degrees (longitudes are normalised to [-180, 180)).
    ids : sequence of str, optional
        One identifier per site (default: the row numbers "0", "1", ...).
    weights : array_like of float, optional
        Weighted sites (docs/weighted.md): each site's radius in metres, 0 <= r < 10,007,557 (a
        quarter of the circumference). `nearest` then answers the site whose power cell holds
        the query, the cell `geovor.cells(..., weights=)` draws (metric "power"). A site whose
        cell is empty (hidden) is never an answer; `sites()` marks it.

    Raises
    ------
    ValueError
        Naming the first row whose position or radius is not valid (NaN, latitude beyond +-90,
        a negative radius, ...).
    """

    def __init__(self, lat=None, lon=None, ids=None, *, weights=None, _core=None):
        if _core is not None:
            self._core = _core
            return
        if lat is None or lon is None:
            raise ValueError("Index needs lat and lon arrays (or Index.from_frame / Index.load)")
        ids = None if ids is None else [str(i) for i in ids]
        radii = None if weights is None else np.asarray(weights, dtype=np.float64)
        self._core = _geovor.Index(np.asarray(lat, dtype=np.float64), np.asarray(lon, dtype=np.float64), ids, radii)

    @classmethod
    def from_frame(cls, frame, *, lat=None, lon=None, id=None, weights=None):
        """The index of a GeoDataFrame of points or a DataFrame with coordinate columns (found as
        `geovor` finds them: lat/latitude/lat_deg/y, lon/lng/long/longitude/lon_deg/x; the id
        column id/icao/code/name, else the row numbers), or the columns named. `weights`: the
        name of a column of radii in metres, or an array (see Index)."""
        lat_deg, lon_deg = frame_coordinates(frame, lat, lon)
        id_col = find_column(frame, ID_NAMES, id, "id")
        ids = None if id_col is None else frame[id_col].astype(str).tolist()
        if isinstance(weights, str):
            if weights not in frame.columns:
                raise ValueError(f"weights: no column {weights!r} (columns: {', '.join(map(str, frame.columns))})")
            weights = frame[weights].to_numpy(dtype=np.float64)
        return cls(lat_deg, lon_deg, ids, weights=weights)

    @classmethod
    def load(cls, path):
        """Loads an index file written by `save` or by `geovor index` (OSError if it cannot be
        read, ValueError if it is not a valid index)."""
        return cls(_core=_geovor.Index.load(os.fspath(path)))

    def save(self, path, overwrite=False):
        """Saves the index (`geovor nearest --sites PATH` reads it). The file appears complete
        or not at all; an existing file is replaced only with overwrite=True."""
        self._core.save(os.fspath(path), overwrite)

    @property
    def num_sites(self):
        """Number of sites (merged rows count once)."""
        return self._core.num_sites

    @property
    def weighted(self):
        """True for an index of weighted sites (its metric is power)."""
        return self._core.weighted

    def sites(self):
        """The sites as a pandas DataFrame indexed by site index: id, lat, lon (the first row's),
        first_row (0-based input row), rows (every input row merged into the site), hidden (for
        weighted sites: True where the site's power cell is empty), then, for an index built from
        a table (`geovor index`), the first row's field of each of its columns as text."""
        import pandas as pd

        s = self._core.sites()
        begin = s["rows_begin"]
        rows = s["rows"]
        columns = {
            "id": s["id"], "lat": s["lat"], "lon": s["lon"], "first_row": s["first_row"],
            "rows": [rows[begin[i]:begin[i + 1]].tolist() for i in range(len(begin) - 1)],
        }
        if self.weighted:
            columns["hidden"] = self._core.weights()[1]
        for name, values in s["fields"].items():
            columns.setdefault(name, values)
        return pd.DataFrame(columns).rename_axis("site_index")

    def nearest(self, lat, lon, k=1, metric=None, max_distance_m=None, threads=None):
        """The exact nearest site (or k nearest) of every query.

        Parameters
        ----------
        lat, lon : array_like of float
            Query latitudes and longitudes in degrees (float64 contiguous arrays are not copied).
        k : int
            Number of neighbours, nearest first (ties to the lower site index).
        metric : "sphere", "geodesic" or "power", optional
            Great-circle distance on the sphere of the Earth's mean radius (6371008.8 m), the
            WGS84 geodesic distance (GeographicLib), or power: the site whose power cell holds the
            query, then by decreasing power (weighted sites: the default and the only metric; the
            distance is still the great-circle distance to the site). Default: "power" for a
            weighted index, else "sphere".
        max_distance_m : float, optional
            Only sites within this distance count; beyond it the index is -1, the distance inf.
        threads : int, optional
            Threads (default: one per core). The GIL is released; the answers do not depend on it.

        Returns
        -------
        (site_index, distance_m) : int64 and float64 arrays of shape (n,) for k == 1, (n, k) else.

        Raises
        ------
        ValueError
            Naming the first query whose position is not valid, or for a bad k, metric or
            max_distance_m.
        """
        k = int(k)
        if k < 1:
            raise ValueError(f"k must be at least 1, not {k}")
        return self._core.nearest(np.asarray(lat, dtype=np.float64), np.asarray(lon, dtype=np.float64), k,
                                  "" if metric is None else str(metric), max_distance_m,
                                  0 if threads is None else int(threads))
