"""Coordinates of a DataFrame or GeoDataFrame, found as the geovor command finds them."""
import numpy as np

# The command's column names (geo/site_reader.hpp), compared trimmed and case-insensitively; the
# earlier name wins.
LAT_NAMES = ("lat", "latitude", "lat_deg", "y")
LON_NAMES = ("lon", "lng", "long", "longitude", "lon_deg", "x")
ID_NAMES = ("id", "icao", "code", "name")


def find_column(frame, names, given=None, what="column"):
    """The column of `frame` named `given`, or the first of `names` present; None if none."""
    columns = {str(c).strip().lower(): c for c in reversed(list(frame.columns))}
    if given is not None:
        if given not in frame.columns:
            raise ValueError(f"{what} column {given!r} is not a column of the frame")
        return given
    for name in names:
        if name in columns:
            return columns[name]
    return None


def frame_coordinates(frame, lat=None, lon=None):
    """(lat_deg, lon_deg) float64 arrays of a GeoDataFrame of points (in EPSG:4326, reprojected
    if needed) or of a DataFrame's coordinate columns."""
    geometry = getattr(frame, "geometry", None) if lat is None and lon is None else None
    if geometry is not None and hasattr(frame, "crs"):
        if frame.crs is not None and not frame.crs.equals("EPSG:4326"):
            geometry = geometry.to_crs("EPSG:4326")
        kinds = set(geometry.geom_type.dropna().unique())
        if not kinds <= {"Point"}:
            raise ValueError(f"the geometry must be points, not {sorted(kinds)}")
        if geometry.isna().any() or geometry.is_empty.any():
            bad = int(np.flatnonzero((geometry.isna() | geometry.is_empty).to_numpy())[0])
            raise ValueError(f"row {bad}: empty geometry")
        return geometry.y.to_numpy(dtype=np.float64), geometry.x.to_numpy(dtype=np.float64)
    lat_col = find_column(frame, LAT_NAMES, lat, "lat")
    lon_col = find_column(frame, LON_NAMES, lon, "lon")
    if lat_col is None or lon_col is None:
        raise ValueError(
            f"no latitude/longitude columns among {list(frame.columns)}: name them "
            f"(lat=..., lon=...) or use one of {LAT_NAMES} and {LON_NAMES}")
    return (frame[lat_col].to_numpy(dtype=np.float64, na_value=np.nan),
            frame[lon_col].to_numpy(dtype=np.float64, na_value=np.nan))
