"""geovor.cells, geovor.delaunay, geovor.relax: the command's layers as GeoDataFrames."""
import warnings

import numpy as np

from . import _geovor
from ._frames import ID_NAMES, find_column, frame_coordinates

__all__ = ["cells", "delaunay", "relax", "balance", "GeometryWarning", "HiddenSiteWarning"]


class GeometryWarning(UserWarning):
    """Some features could not be written valid and have an empty geometry (listed)."""


class HiddenSiteWarning(UserWarning):
    """Some weighted sites own no cell: a larger circle hides them (listed with a site that
    holds their position; their cells have an empty geometry)."""


def _values(data, values, what="weight"):
    """A float64 array from `values`: an array, or with `data` a column name; None for None."""
    if values is None:
        return None
    if isinstance(values, str):
        if data is None:
            raise ValueError(f"{what} names a column: give the DataFrame as data")
        if values not in data.columns:
            raise ValueError(f"no {what} column {values!r} (columns: {', '.join(map(str, data.columns))})")
        values = data[values].to_numpy()
    return np.asarray(values, dtype=np.float64)


def _warn_hidden(hidden):
    if hidden:
        listed = ", ".join(f"row {i} (held by row {by})" for i, by in hidden[:20])
        warnings.warn(f"{len(hidden)} weighted sites are hidden (their power cell is empty): {listed}",
                      HiddenSiteWarning, stacklevel=3)


def _sites(data, lat, lon, ids):
    """(lat, lon, ids, carried columns frame or None) from a frame or from arrays."""
    if data is None:
        if lat is None or lon is None:
            raise ValueError("give a DataFrame/GeoDataFrame, or lat= and lon= arrays")
        ids = None if ids is None else [str(i) for i in ids]
        return np.asarray(lat, dtype=np.float64), np.asarray(lon, dtype=np.float64), ids, None
    lat_deg, lon_deg = frame_coordinates(data, lat, lon)
    id_col = find_column(data, ID_NAMES, ids, "id")
    ids_list = None if id_col is None else data[id_col].astype(str).tolist()
    # Every column is carried, the coordinates included (as the command does); not the geometry.
    geometry_name = getattr(data, "_geometry_column_name", None)
    carried = data.drop(columns=[geometry_name]) if geometry_name in data.columns else data
    return lat_deg, lon_deg, ids_list, carried


def _geometries(wkb):
    """A GeoSeries (EPSG:4326) of a list of WKB bytes (none of them empty bytes)."""
    import geopandas as gpd
    import shapely

    if hasattr(shapely, "from_wkb") or getattr(gpd.options, "use_pygeos", False):
        return gpd.GeoSeries.from_wkb(wkb, crs="EPSG:4326")  # vectorised already
    from geopandas.array import GeometryArray
    from shapely.geos import WKBReader, lgeos

    # Shapely 1.8: GeoPandas makes a reader per geometry, then numpy's list assignment probes
    # each geometry as a sequence; one reader and one assignment per item take half the time.
    read = WKBReader(lgeos).read
    out = np.empty(len(wkb), dtype=object)
    for i, w in enumerate(wkb):
        out[i] = read(w)
    return gpd.GeoSeries(GeometryArray(out, crs="EPSG:4326"))


def _columns(features, carried=None, first_rows=None):
    """A DataFrame of the fields of features from _geovor, with the carried columns of each
    feature's site's first row (renamed src_<name> where they clash with ours, as `geovor cells`)."""
    import pandas as pd

    names = list(features["fields"])
    frame = pd.DataFrame({name: features[name] for name in names})
    if carried is not None and len(frame):
        rows = first_rows[frame["site_index"].to_numpy()]
        taken = carried.iloc[rows].reset_index(drop=True)
        ours = {n.lower() for n in names}
        taken.columns = [f"src_{c}" if str(c).lower() in ours else c for c in taken.columns]
        frame = pd.concat([frame, taken], axis=1)
    return frame


def _frame(features, carried=None, first_rows=None):
    """_columns() and the features' geometry: a GeoDataFrame in EPSG:4326."""
    import geopandas as gpd

    return gpd.GeoDataFrame(_columns(features, carried, first_rows), geometry=_geometries(features["geometry"]),
                            crs="EPSG:4326")


def _warn_unwritten(unwritten, what):
    if unwritten:
        listed = ", ".join(f"{i} ({why})" for i, why in unwritten[:20])
        warnings.warn(f"{len(unwritten)} {what} have an empty geometry (they would not be valid polygons): {listed}",
                      GeometryWarning, stacklevel=3)


def _region_wkb(clip):
    """(clip in EPSG:4326, the WKB of each region), each a Polygon or MultiPolygon."""
    from shapely.geometry import MultiPolygon, Polygon

    if getattr(clip, "crs", None) is not None and not clip.crs.equals("EPSG:4326"):
        clip = clip.to_crs("EPSG:4326")
    regions = []
    for row, geom in enumerate(clip.geometry):
        if not isinstance(geom, (Polygon, MultiPolygon)):
            kind = "no geometry" if geom is None else f"a {geom.geom_type}"
            raise ValueError(f"clip row {row}: {kind}, not a Polygon or MultiPolygon")
        regions.append(geom.wkb)
    return clip, regions


def _clipped(out, carried, clip):
    """The pieces' GeoDataFrame: ours, the sites' carried columns, then region_<name> columns."""
    import geopandas as gpd
    import pandas as pd

    # One GeoDataFrame at the end (each one built compares CRSs, which costs a millisecond);
    # a carried column named geometry gives way to the geometry, as in _frame().
    frame = _columns(out, carried, out["site_first_row"]).drop(columns="geometry", errors="ignore")
    taken = clip.drop(columns=[clip.geometry.name]).iloc[frame["region_index"].to_numpy()].reset_index(drop=True)
    names = {str(c).lower() for c in frame.columns} | {"geometry"}
    renamed = []
    for c in taken.columns:
        name = f"region_{c}"
        while name.lower() in names:
            name = f"src_{name}"
        names.add(name.lower())
        renamed.append(name)
    taken.columns = renamed
    return gpd.GeoDataFrame(pd.concat([frame, taken], axis=1), geometry=_geometries(out["geometry"]))


def cells(data=None, *, lat=None, lon=None, ids=None, densify_m=100.0, merge_m=0.0, threads=None, weights=None,
          clip=None):
    """The Voronoi cell of every site, as `geovor cells` writes them, in a GeoDataFrame.

    Parameters
    ----------
    data : GeoDataFrame of points or DataFrame, optional
        The sites. A DataFrame's coordinate columns are found as the command finds them
        (lat/latitude/lat_deg/y and lon/lng/long/longitude/lon_deg/x) or named by `lat`/`lon`;
        the id column is id/icao/code/name or `ids`. Its other columns are carried, typed as
        they are, from each site's first row.
    lat, lon : array_like or str
        Without `data`: latitudes and longitudes in degrees. With `data`: column names.
    ids : sequence of str or str, optional
        Without `data`: one id per site (default "0", "1", ...). With `data`: the id column.
    densify_m : float
        Largest distance in metres between a written edge and the true great-circle arc.
    merge_m : float
        Merge sites closer than this (metres); at least 0.38 m always.
    threads : int, optional
        Threads (default: one per core); the result does not depend on it.
    weights : array_like or str, optional
        Weighted sites (power cells, docs/weighted.md): each site's radius in metres,
        0 <= r < 10,007,557 (a quarter of the circumference), or with `data` the column holding
        it. Site i's cell is where cos(d(x, p_i)) / cos(r_i / R) is largest; equal radii give the
        Voronoi cells. A radius out of range or NaN is a ValueError naming its index.

    Returns
    -------
    GeoDataFrame in EPSG:4326, one row per site, in site order: site_index, site_id, ids (JSON
    text: the ids of every row of the site), n_rows, area_m2 (WGS84 ellipsoid, of the polygon as
    stored), area_sr (the exact cell on the unit sphere), n_vertices, neighbors (JSON text),
    weight_m (with weights), the carried columns, and geometry: MultiPolygons cut at +-180 (RFC
    7946), valid for GEOS. A cell that cannot be stored valid gets an empty geometry and a
    GeometryWarning lists it. `attrs["merged"]` lists (input row, row it was merged into); with
    weights, `attrs["hidden"]` lists (input row, row of a site holding its position) of the
    sites whose power cell is empty (empty geometry; a HiddenSiteWarning lists them too).

    With ``clip`` (a GeoDataFrame of Polygons/MultiPolygons, reprojected to EPSG:4326 when it
    has another CRS), the pieces of the cells inside each region instead, as `geovor cells
    --clip` makes them (layers/region_clip.hpp; GEOS's overlay in longitude/latitude, the
    regions' edges as drawn): one row per non-empty (site, region) piece, by site then region,
    with site_index, site_id, region_index (the clip row's position), region_id, area_m2,
    region_share (the piece's share of its region: the Thiessen weight), the sites' carried
    columns and the region's columns as region_<name>. `attrs["outside"]` lists the site
    indices whose cell meets no region, `attrs["problems"]` the (region_index, reason) of
    regions repaired (invalid polygons, made valid) or empty; a GeometryWarning names them.
    """
    lat_deg, lon_deg, id_list, carried = _sites(data, lat, lon, ids)
    if clip is not None:
        clip, regions = _region_wkb(clip)
        out = _geovor.cells_clipped(lat_deg, lon_deg, id_list, float(densify_m), float(merge_m),
                                    0 if threads is None else int(threads), _values(data, weights), regions)
        if out["problems"]:
            listed = ", ".join(f"region {r}: {why}" for r, why in out["problems"][:20])
            warnings.warn(f"{len(out['problems'])} clip regions: {listed}", GeometryWarning, stacklevel=2)
        frame = _clipped(out, carried, clip)
        frame.attrs["outside"] = list(out["outside"])
        frame.attrs["problems"] = list(out["problems"])
        return frame
    out = _geovor.cells(lat_deg, lon_deg, id_list, float(densify_m), float(merge_m), 0 if threads is None else int(threads),
                        _values(data, weights))
    _warn_unwritten(out["unwritten"], "cells (by site index)")
    _warn_hidden(list(out["hidden"]))
    frame = _frame(out, carried, out["site_first_row"])
    frame.attrs["merged"] = list(out["merged"])
    frame.attrs["hidden"] = list(out["hidden"])
    return frame


def delaunay(data=None, *, lat=None, lon=None, ids=None, densify_m=100.0, no_ghosts=False, merge_m=0.0, weights=None):
    """The Delaunay triangles and edges, as `geovor delaunay` writes them: a pair of
    GeoDataFrames (EPSG:4326), triangles (MultiPolygons with kind, ghost, areas, circumradius)
    and edges (MultiLineStrings with their great-circle and WGS84 geodesic lengths). Sites (and
    weights: the regular triangulation, of which hidden sites are no vertex) as in cells().
    no_ghosts leaves out the outer faces and edges (sites in one hemisphere)."""
    lat_deg, lon_deg, id_list, _ = _sites(data, lat, lon, ids)
    triangles, edges = _geovor.delaunay(lat_deg, lon_deg, id_list, float(densify_m), bool(no_ghosts), float(merge_m),
                                        _values(data, weights))
    _warn_unwritten(triangles["unwritten"], "triangles (by triangle id)")
    _warn_hidden(list(triangles["hidden"]))
    t = _frame(triangles)
    t.attrs["merged"] = list(triangles["merged"])
    t.attrs["hidden"] = list(triangles["hidden"])
    return t, _frame(edges)


def balance(data=None, *, lat=None, lon=None, ids=None, capacity=None, tolerance=1e-6, max_iterations=50,
            densify_m=100.0, merge_m=0.0, threads=None):
    """Balanced power cells (`geovor balance`): the radii for which every site's power cell on the
    WGS84 ellipsoid has its capacity's share of the Earth's area (equal shares without
    `capacity`), by damped Newton on the exact cells (docs/weighted.md).

    Sites as in cells(); `capacity` is an array of positive numbers or, with `data`, a column name
    (rows merged into one site pool theirs). Returns the cells as cells(weights=radii) gives them,
    with `weight_m` (the radius) and `target_m2` (the cell's target area; `area_m2` is that of the
    polygon as stored, within the densification of it); `attrs["radii_m"]` holds every row's
    radius, `attrs["iterations"]` (largest relative area error, damping step) per Newton step.
    Raises ValueError when the tolerance is not reached (e.g. sites all in one hemisphere: some
    region is then more than 90 degrees from every site), or for a capacity that is not positive.
    """
    lat_deg, lon_deg, id_list, carried = _sites(data, lat, lon, ids)
    shares = _values(data, capacity, "capacity")
    out = _geovor.balance(lat_deg, lon_deg, id_list, shares, float(tolerance), int(max_iterations), float(densify_m),
                          float(merge_m), 0 if threads is None else int(threads))
    _warn_unwritten(out["unwritten"], "cells (by site index)")
    frame = _frame(out, carried, out["site_first_row"])
    first = out["site_first_row"][frame["site_index"].to_numpy()]
    frame.insert(frame.columns.get_loc("weight_m") + 1, "target_m2", out["target_m2"][first])
    frame.attrs.update(merged=list(out["merged"]), radii_m=out["radii_m"], iterations=list(out["iterations"]))
    return frame


def relax(data=None, *, lat=None, lon=None, ids=None, iterations=10, tolerance_rad=0.0, relocation="filtered",
          densify_m=100.0, merge_m=0.0, threads=None):
    """Lloyd's iterations (`geovor relax`): every site moves to its cell's centroid, `iterations`
    times (or until no site moves more than tolerance_rad). Returns (cells, sites): the final
    cells as cells() gives them, and a GeoDataFrame of the final sites (site_index, site_id,
    Point geometry); `cells.attrs["energy"]` holds the energy at the start of each iteration,
    `cells.attrs["final_energy"]` the last."""
    import geopandas as gpd

    lat_deg, lon_deg, id_list, carried = _sites(data, lat, lon, ids)
    out = _geovor.relax(lat_deg, lon_deg, id_list, int(iterations), float(tolerance_rad), str(relocation),
                        float(densify_m), float(merge_m), 0 if threads is None else int(threads))
    _warn_unwritten(out["unwritten"], "cells (by site index)")
    cells_frame = _frame(out, carried, out["site_first_row"])
    cells_frame.attrs.update(merged=list(out["merged"]), energy=list(out["energy"]),
                             max_move_m=list(out["max_move_m"]), final_energy=out["final_energy"])
    live = cells_frame["site_index"].to_numpy()
    sites = gpd.GeoDataFrame({"site_index": live, "site_id": cells_frame["site_id"].to_numpy()},
                             geometry=gpd.points_from_xy(out["site_lon"][live], out["site_lat"][live]), crs="EPSG:4326")
    return cells_frame, sites
