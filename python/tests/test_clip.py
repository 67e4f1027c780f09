"""geovor.cells(clip=...): the stations' cells cut by Natural Earth's countries (shipped with
Debian's python3-geopandas) and by regions at the poles and across +-180, against oracles that
share no code with geovor: random points of each country go to the piece of their nearest
station by brute force (numpy), GEOS validity, pieces that union to their region, PolygonArea
(geographiclib) of each piece, shares summing to 1; bad regions."""
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from geographiclib.geodesic import Geodesic

import geovor

gpd = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")
from shapely.geometry import MultiPolygon, Point, Polygon, box  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
STATIONS = ROOT / "datasets" / "weather_stations.csv"
COUNTRIES = Path(gpd.datasets.get_path("naturalearth_lowres"))
R = 6371008.771415


def unit(lat, lon):
    """Geocentric directions of WGS84 positions (geovor's sphere metric), independently."""
    p, l = np.radians(lat), np.radians(lon)
    e2 = 0.0066943799901413165
    n = 1 / np.sqrt(1 - e2 * np.sin(p) ** 2)
    v = np.stack([n * np.cos(p) * np.cos(l), n * np.cos(p) * np.sin(l), n * (1 - e2) * np.sin(p)], axis=-1)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def polygon_area_m2(geometry):
    total = 0.0
    for polygon in getattr(geometry, "geoms", [geometry]):
        for ring in [polygon.exterior, *polygon.interiors]:
            area = Geodesic.WGS84.Polygon()
            for lon, lat in list(ring.coords)[:-1]:
                area.AddPoint(lat, lon)
            total += area.Compute(False, True)[2]
    return total


def check_pieces(pieces, sites_lat, sites_lon, regions, points_per_region=60, seed=1):
    assert pieces.is_valid.all()
    sums = pieces.groupby("region_index").region_share.sum()
    assert np.allclose(sums.to_numpy(), 1.0, rtol=0, atol=1e-9)
    for area, geom in zip(pieces.area_m2.to_numpy()[:400], pieces.geometry.values[:400]):
        assert area == pytest.approx(polygon_area_m2(geom), rel=1e-9, abs=1e-3)
    units = unit(np.asarray(sites_lat), np.asarray(sites_lon))
    rng = np.random.default_rng(seed)
    by_key = {(s, r): g for s, r, g in zip(pieces.site_index, pieces.region_index, pieces.geometry)}
    checked = 0
    for r, region in enumerate(regions.geometry):
        # The pieces union to the region as GEOS sees it.
        union = shapely.ops.unary_union(list(pieces.geometry[pieces.region_index == r]))
        assert union.symmetric_difference(region.buffer(0)).area <= 1e-6 * region.area + 1e-9, r
        w, s, e, n = region.bounds
        for lon, lat in zip(rng.uniform(w, e, 40 * points_per_region), rng.uniform(s, n, 40 * points_per_region)):
            if checked >= points_per_region * (r + 1):
                break
            if not region.contains(Point(lon, lat)):
                continue
            d = units @ unit(lat, lon)
            order = np.argsort(-d)
            best, second = order[0], order[1]
            gap_m = (np.arccos(min(1, d[second])) - np.arccos(min(1, d[best]))) * R
            piece = by_key.get((int(best), r))
            assert gap_m < 300 or (piece is not None and piece.intersects(Point(lon, lat))), (r, lat, lon, best)
            checked += 1
    assert checked > 0


def test_stations_by_country():
    sites = pd.read_csv(STATIONS)
    countries = gpd.read_file(COUNTRIES)
    pieces = geovor.cells(sites, clip=countries)
    assert list(pieces.columns[:6]) == ["site_index", "site_id", "region_index", "region_id", "area_m2", "region_share"]
    assert "region_name" in pieces.columns and "icao" in pieces.columns
    assert pieces.crs == "EPSG:4326"
    fiji = countries.index[countries.name == "Fiji"][0]
    assert (pieces.region_index == fiji).sum() >= 1
    assert len(pieces.attrs["outside"]) > 0  # ocean stations: listed, not dropped silently
    # geovor merges stations at one position: the sites are those of geovor.cells.
    cells = geovor.cells(sites)
    check_pieces(pieces, cells.lat_deg.to_numpy(), cells.lon_deg.to_numpy(), countries, points_per_region=8)


def test_poles_and_antimeridian():
    rng = np.random.default_rng(5)
    lat = np.concatenate([rng.uniform(-90, -60, 300), rng.uniform(60, 90, 300), rng.uniform(-30, 30, 300), [90, -90]])
    lon = np.concatenate([rng.uniform(-180, 180, 600), rng.uniform(170, 190, 300) - np.where(rng.uniform(size=300) > 0.5, 360, 0), [0, 0]])
    lon = (lon + 180) % 360 - 180
    regions = gpd.GeoDataFrame(
        {"name": ["antarctica", "arctic", "fiji", "holed"]},
        geometry=[Polygon([(-180, -90), (180, -90), (180, -70), (0, -65), (-180, -70)]),
                  box(-180, 75, 180, 90),
                  MultiPolygon([box(170, -20, 180, 10), box(-180, -20, -172, 10)]),
                  Polygon(box(-10, -10, 10, 10).exterior.coords, [box(-5, -5, 5, 5).exterior.coords])],
        crs="EPSG:4326")
    pieces = geovor.cells(lat=lat, lon=lon, clip=regions)
    assert set(pieces.region_name) == {"antarctica", "arctic", "fiji", "holed"}
    assert len(geovor.cells(lat=lat, lon=lon)) == len(lat)  # no merges: site i is point i
    check_pieces(pieces, lat, lon, regions)


def test_other_crs_and_bad_regions():
    rng = np.random.default_rng(9)
    lat, lon = rng.uniform(-60, 60, 500), rng.uniform(-180, 180, 500)
    mercator = gpd.GeoDataFrame({"id": ["a"]}, geometry=[box(0, 0, 2e6, 2e6)], crs="EPSG:3857")
    pieces = geovor.cells(lat=lat, lon=lon, clip=mercator)
    assert pieces.total_bounds[2] == pytest.approx(17.966, abs=1e-3)  # reprojected to degrees
    assert pieces.region_share.sum() == pytest.approx(1, abs=1e-9)
    with pytest.raises(ValueError, match="clip row 1: a Point"):
        geovor.cells(lat=lat, lon=lon, clip=gpd.GeoDataFrame(geometry=[box(0, 0, 1, 1), Point(0, 0)], crs="EPSG:4326"))
    bowtie = gpd.GeoDataFrame(geometry=[Polygon([(0, 0), (10, 10), (10, 0), (0, 10)])], crs="EPSG:4326")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        pieces = geovor.cells(lat=lat, lon=lon, clip=bowtie)
    assert any("Self-intersection" in str(w.message) for w in caught)
    assert pieces.is_valid.all() and pieces.attrs["problems"][0][0] == 0


def test_regions_with_z_and_empty_parts():
    # The regions reach the clip as WKB: a Z is dropped, empty polygons and parts are no region.
    rng = np.random.default_rng(3)
    lat, lon = rng.uniform(-60, 60, 400), rng.uniform(-180, 180, 400)
    flat = [box(0, 0, 20, 15), MultiPolygon([box(40, -10, 60, 10), box(70, 0, 80, 5)])]
    other = [Polygon([(x, y, 7.0) for x, y in flat[0].exterior.coords]), MultiPolygon([*flat[1].geoms, Polygon()])]
    ours = geovor.cells(lat=lat, lon=lon, clip=gpd.GeoDataFrame(geometry=flat, crs="EPSG:4326"))
    theirs = geovor.cells(lat=lat, lon=lon, clip=gpd.GeoDataFrame(geometry=other, crs="EPSG:4326"))
    assert ours.drop(columns="geometry").equals(theirs.drop(columns="geometry"))
    assert [g.wkb for g in ours.geometry] == [g.wkb for g in theirs.geometry]
    empty = geovor.cells(lat=lat, lon=lon, clip=gpd.GeoDataFrame(geometry=[Polygon(), flat[0]], crs="EPSG:4326"))
    assert set(empty.region_index) == {1} and empty.attrs["problems"][0][0] == 0
