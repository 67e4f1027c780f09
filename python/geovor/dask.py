"""geovor.dask: the nearest-site join of a Dask DataFrame of queries against a saved index.

Each worker process loads the index file once (then keeps it), so the same code joins a query
table larger than one machine on a Dask cluster.
"""
import os
import threading

import numpy as np
import pandas as pd

from ._index import Index

__all__ = ["nearest", "nearest_frame"]

_cache = {}
_cache_lock = threading.Lock()


def _load(index_path):
    """The index at index_path, loaded once per process (again if the file changes)."""
    stat = os.stat(index_path)
    key = (os.path.realpath(index_path), stat.st_size, stat.st_mtime_ns)
    with _cache_lock:
        index = _cache.get(key)
        if index is None:
            index = Index.load(index_path)
            _cache.clear()  # one index per process: a cluster worker joins one table at a time
            _cache[key] = index
        return index, _site_table(index, key)


_site_tables = {}


def _site_table(index, key):
    table = _site_tables.get(key)
    if table is None:
        table = index.sites()
        _site_tables.clear()
        _site_tables[key] = table
    return table


def _output_columns(frame_columns, k, site_columns):
    out = list(frame_columns)
    if k > 1:
        out.append("rank")
    out += ["site_index", "distance_m"] + [f"site_{c}" for c in site_columns]
    clash = sorted(set(frame_columns) & set(out[len(frame_columns):]))
    if clash:
        raise ValueError(f"the query table already has the column(s) {clash}; rename them first")
    return out


def nearest_frame(frame, index, *, lat="lat", lon="lon", k=1, metric="sphere", max_distance_m=None,
                  site_columns=("id",), threads=None, sites=None):
    """The pandas version: `frame` joined with its nearest sites in `index` (an Index).

    One row per query (k == 1), or k rows per query with a `rank` column (1 = nearest); then
    site_index (-1 beyond max_distance_m), distance_m (metres; inf beyond max_distance_m) and
    `site_<column>` for each of site_columns (columns of index.sites(): id, lat, lon, and the
    columns of the table the index was built from).
    """
    sites = index.sites() if sites is None else sites
    missing = [c for c in site_columns if c not in sites.columns]
    if missing:
        raise ValueError(f"site column(s) {missing} not in the index; it has {list(sites.columns)}")
    _output_columns(frame.columns, k, site_columns)
    site, dist = index.nearest(frame[lat].to_numpy(dtype=np.float64), frame[lon].to_numpy(dtype=np.float64),
                               k=k, metric=metric, max_distance_m=max_distance_m, threads=threads)
    if k > 1:
        out = frame.loc[frame.index.repeat(k)].copy()
        out["rank"] = np.tile(np.arange(1, k + 1), len(frame))
        site, dist = site.ravel(), dist.ravel()
    else:
        out = frame.copy()
    out["site_index"] = site
    out["distance_m"] = dist
    found = site >= 0
    for c in site_columns:
        values = sites[c].to_numpy()
        column = np.empty(len(site), dtype=values.dtype if values.dtype != object else object)
        if values.dtype == object:
            column[:] = None
        else:
            column[:] = np.nan if np.issubdtype(values.dtype, np.floating) else 0
        column[found] = values[site[found]]
        out[f"site_{c}"] = column
    return out


def _partition(frame, index_path, lat, lon, k, metric, max_distance_m, site_columns, threads):
    index, sites = _load(index_path)
    return nearest_frame(frame, index, lat=lat, lon=lon, k=k, metric=metric, max_distance_m=max_distance_m,
                         site_columns=site_columns, threads=threads, sites=sites)


def nearest(ddf, index_path, lat="lat", lon="lon", k=1, metric="sphere", max_distance_m=None,
            site_columns=("id",), threads=1):
    """A Dask DataFrame: every partition of `ddf` joined with its nearest sites (nearest_frame's
    columns), each partition on the worker that holds it.

    index_path must be readable by every worker (a shared file system or a copy on each). The
    index is loaded once per worker process. threads: threads per partition (default 1: Dask
    runs partitions in parallel already).
    """
    index_path = os.fspath(index_path)
    site_columns = tuple(site_columns)
    # The output's schema, from an empty partition and the index's site table.
    index, sites = _load(index_path)
    meta = nearest_frame(ddf._meta, index, lat=lat, lon=lon, k=k, metric=metric,
                         max_distance_m=max_distance_m, site_columns=site_columns, sites=sites)
    return ddf.map_partitions(_partition, index_path, lat, lon, k, metric, max_distance_m, site_columns, threads,
                              meta=meta)
