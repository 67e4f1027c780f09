"""geovor.cells / delaunay / relax: GEOS validity (shapely), WGS84 areas against geographiclib's
PolygonArea, the ellipsoid's total, the command's output, degenerate and bad input."""
import json
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from geographiclib.geodesic import Geodesic

import geovor

gpd = pytest.importorskip("geopandas")
ROOT = Path(__file__).resolve().parents[2]
STATIONS = ROOT / "datasets" / "weather_stations.csv"
_A, _F = 6378137.0, 1 / 298.257223563
_E = np.sqrt(_F * (2 - _F))
ELLIPSOID_M2 = 2 * np.pi * _A**2 * (1 + (1 - _E**2) / _E * np.arctanh(_E))  # WGS84's surface area


def polygon_area_m2(geometry):
    """WGS84 area of a (Multi)Polygon by geographiclib's PolygonArea, ring by ring."""
    total = 0.0
    for polygon in getattr(geometry, "geoms", [geometry]):
        for k, ring in enumerate([polygon.exterior, *polygon.interiors]):
            area = Geodesic.WGS84.Polygon()
            for lon, lat in list(ring.coords)[:-1]:
                area.AddPoint(lat, lon)
            _, _, a = area.Compute(False, True)  # counter-clockwise: positive
            total += a if k == 0 else -abs(a)
    return total


@pytest.fixture(scope="module")
def stations():
    return pd.read_csv(STATIONS)


@pytest.fixture(scope="module")
def station_cells(stations):
    return geovor.cells(stations)


def test_station_cells_are_valid_and_measured(stations, station_cells):
    cells = station_cells
    assert cells.crs.to_epsg() == 4326
    assert len(cells) == 5631  # three stations share a position with another
    assert cells.is_valid.all() and not cells.is_empty.any()
    assert cells["area_m2"].sum() == pytest.approx(ELLIPSOID_M2, rel=1e-9)
    assert cells["area_sr"].sum() == pytest.approx(4 * np.pi, rel=1e-12)
    bounds = cells.total_bounds
    assert bounds[0] >= -180 and bounds[2] <= 180 and bounds[1] >= -90 and bounds[3] <= 90
    sample = cells.sample(150, random_state=3)
    for geometry, area in zip(sample.geometry, sample["area_m2"]):
        assert polygon_area_m2(geometry) == pytest.approx(area, rel=1e-9, abs=0.25)
    # Carried columns keep their types; ids lists hold every merged row.
    assert cells["lat_deg"].dtype == np.float64 and cells["name"].dtype == object
    assert (cells["n_rows"] == cells["ids"].map(lambda t: len(json.loads(t)))).all()
    assert cells["n_rows"].sum() == len(stations)
    merged = cells.attrs["merged"]
    assert len(merged) == 3
    # Each site's carried row is its first row.
    row = stations.set_index("icao").loc[cells["site_id"].iloc[10]]
    assert cells["name"].iloc[10] == row["name"]


def test_same_cells_as_the_command(tmp_path, station_cells):
    tool = ROOT / "build" / "tools" / "geovor"
    if not tool.exists():
        pytest.skip("the geovor command is not built")
    out = tmp_path / "cells.geojson"
    subprocess.run([str(tool), "cells", str(STATIONS), "-o", str(out), "-q", "--precision", "12"], check=True)
    command = gpd.read_file(out)
    assert command["site_id"].tolist() == station_cells["site_id"].tolist()
    # The command's GeoJSON holds the lists as arrays; the frame as JSON text.
    assert [list(n) for n in command["neighbors"]] == [json.loads(t) for t in station_cells["neighbors"]]
    np.testing.assert_allclose(command["area_sr"].astype(float), station_cells["area_sr"], rtol=1e-12)
    # Positions differ only by the command's 12 decimals.
    np.testing.assert_allclose(command["area_m2"].astype(float), station_cells["area_m2"], rtol=1e-6)


def test_antimeridian_and_poles():
    lat = [0.0, 0.0, 89.0, -89.0, 10.0, -10.0]
    lon = [179.5, -170.0, 0.0, 180.0, 90.0, -90.0]  # a's cell reaches -175.25: cut at 180
    cells = geovor.cells(lat=lat, lon=lon, ids=list("abcdef"))
    assert cells.is_valid.all()
    assert cells["area_m2"].sum() == pytest.approx(ELLIPSOID_M2, rel=1e-9)
    cut = cells.set_index("site_id").geometry
    assert cut["a"].geom_type == "MultiPolygon" and len(cut["a"].geoms) == 2  # cut at +-180
    for geometry, area in zip(cells.geometry, cells["area_m2"]):
        assert polygon_area_m2(geometry) == pytest.approx(area, rel=1e-9, abs=0.25)


@pytest.mark.parametrize("n", [1, 2, 3])
def test_tiny_sets(n):
    cells = geovor.cells(lat=[10.0, -20.0, 30.0][:n], lon=[0.0, 100.0, -120.0][:n])
    assert len(cells) == n and cells.is_valid.all()
    assert cells["area_m2"].sum() == pytest.approx(ELLIPSOID_M2, rel=1e-9)


def test_frames_and_merges():
    frame = gpd.GeoDataFrame({"code": ["x", "y", "z", "w"], "pop": [1, 2, 3, 4]},
                             geometry=gpd.points_from_xy([0.0, 0.0, 50.0, -70.0], [0.0, 0.0, 10.0, -5.0]),
                             crs="EPSG:4326")
    cells = geovor.cells(frame)
    assert cells["site_id"].tolist() == ["x", "z", "w"]
    assert cells["pop"].dtype == np.int64 and cells["pop"].tolist() == [1, 3, 4]
    assert json.loads(cells["ids"].iloc[0]) == ["x", "y"]
    assert cells.attrs["merged"] == [(1, 0)]
    # A column named like one of ours is carried as src_<name>.
    clash = pd.DataFrame({"lat": [0.0, 10.0, 20.0], "lon": [0.0, 10.0, -30.0], "area_m2": [7, 8, 9]})
    assert geovor.cells(clash)["src_area_m2"].tolist() == [7, 8, 9]


def test_bad_input():
    with pytest.raises(ValueError, match="site 2"):
        geovor.cells(lat=[0.0, 1.0, 91.0], lon=[0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="latitude/longitude"):
        geovor.cells(pd.DataFrame({"a": [1.0]}))
    with pytest.raises(ValueError, match="points"):
        geovor.cells(gpd.GeoDataFrame(geometry=gpd.GeoSeries.from_wkt(["LINESTRING (0 0, 1 1)"]), crs="EPSG:4326"))


def test_delaunay_octahedron():
    lat = [0.0, 0.0, 0.0, 0.0, 90.0, -90.0]
    lon = [0.0, 90.0, 180.0, -90.0, 0.0, 0.0]
    triangles, edges = geovor.delaunay(lat=lat, lon=lon)
    assert len(triangles) == 8 and len(edges) == 12
    assert triangles.is_valid.all()
    assert triangles["area_m2"].sum() == pytest.approx(ELLIPSOID_M2, rel=1e-9)
    np.testing.assert_allclose(triangles["area_m2"], ELLIPSOID_M2 / 8, rtol=1e-9)
    quarter_equator = Geodesic.WGS84.Inverse(0, 0, 0, 90)["s12"]
    quarter_meridian = Geodesic.WGS84.Inverse(0, 0, 90, 0)["s12"]
    lengths = sorted(edges["geodesic_m"])
    np.testing.assert_allclose(lengths[:8], quarter_meridian, rtol=1e-12)
    np.testing.assert_allclose(lengths[8:], quarter_equator, rtol=1e-12)


def test_delaunay_one_hemisphere_no_ghosts():
    rng = np.random.default_rng(4)
    lat, lon = rng.uniform(10, 60, 40), rng.uniform(-20, 40, 40)
    all_t, _ = geovor.delaunay(lat=lat, lon=lon)
    hull_t, hull_e = geovor.delaunay(lat=lat, lon=lon, no_ghosts=True)
    assert (hull_t["ghost"] == 0).all() and (all_t["ghost"] == 1).any()
    assert len(hull_t) < len(all_t) and (hull_e["ghost"] == 0).all()


def test_relax_lowers_the_energy():
    rng = np.random.default_rng(5)
    lat, lon = np.degrees(np.arcsin(rng.uniform(-1, 1, 300))), rng.uniform(-180, 180, 300)
    cells, sites = geovor.relax(lat=lat, lon=lon, iterations=8)
    energy = cells.attrs["energy"] + [cells.attrs["final_energy"]]
    assert all(b <= a for a, b in zip(energy, energy[1:]))
    assert len(cells) == len(sites) == 300 and cells.is_valid.all()
    assert cells["area_m2"].sum() == pytest.approx(ELLIPSOID_M2, rel=1e-9)
    # The relaxed cells are more even than the random ones.
    start = geovor.cells(lat=lat, lon=lon)
    assert cells["area_m2"].std() < 0.5 * start["area_m2"].std()
    # Every strategy gives the same sites.
    _, rebuilt = geovor.relax(lat=lat, lon=lon, iterations=8, relocation="rebuild")
    assert sites.geometry.equals(rebuilt.geometry)
    with pytest.raises(ValueError, match="relocation"):
        geovor.relax(lat=lat, lon=lon, relocation="teleport")
