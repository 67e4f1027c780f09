"""geovor.cells / delaunay with weights (power cells, docs/weighted.md): equal radii give the
Voronoi cells, every point lies in the cell of its largest power (brute force, numpy), hidden
sites are listed and empty, bad radii raise ValueError naming their index."""
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import geovor

gpd = pytest.importorskip("geopandas")
shapely = pytest.importorskip("shapely")
ROOT = Path(__file__).resolve().parents[2]
STATIONS = ROOT / "datasets" / "weather_stations.csv"
R = 6371008.771415
_A, _F = 6378137.0, 1 / 298.257223563
_E2 = _F * (2 - _F)


def directions(lat_deg, lon_deg):
    """Geocentric directions of WGS84 positions at height 0 (what a site stands for)."""
    lat, lon = np.radians(lat_deg), np.radians(lon_deg)
    n = _A / np.sqrt(1 - _E2 * np.sin(lat) ** 2)
    xyz = np.stack([n * np.cos(lat) * np.cos(lon), n * np.cos(lat) * np.sin(lon), n * (1 - _E2) * np.sin(lat)], axis=-1)
    return xyz / np.linalg.norm(xyz, axis=-1, keepdims=True)


@pytest.fixture(scope="module")
def stations():
    return pd.read_csv(STATIONS)


def test_equal_radii_give_the_voronoi_cells(stations):
    sample = stations.iloc[::10].reset_index(drop=True)
    plain = geovor.cells(sample)
    weighted = geovor.cells(sample, weights=np.full(len(sample), 25_000.0))
    assert (weighted["weight_m"] == 25_000.0).all()
    assert plain.geometry.geom_equals_exact(weighted.geometry, 0).all()
    assert np.array_equal(plain["area_m2"].to_numpy(), weighted["area_m2"].to_numpy())


def test_every_point_lies_in_the_cell_of_its_largest_power(stations):
    rng = np.random.default_rng(33)
    sample = stations.iloc[::8].reset_index(drop=True)
    radii = rng.choice([0.0, 20_000.0, 150_000.0, 400_000.0], size=len(sample))
    with pytest.warns(geovor.HiddenSiteWarning):  # radii up to 400 km hide some of 700 stations
        cells = geovor.cells(sample, weights=radii)
    assert len(cells.attrs["hidden"]) > 0
    assert len(cells) == len(sample) - len(cells.attrs["merged"])
    sites = directions(sample["lat_deg"].to_numpy(), sample["lon_deg"].to_numpy())
    lifts = np.cos(radii / R)
    lat = np.degrees(np.arcsin(rng.uniform(-1, 1, 3000)))
    lon = rng.uniform(-180, 180, 3000)
    power = directions(lat, lon) @ sites.T / lifts
    order = np.sort(power, axis=1)
    clear = (order[:, -1] - order[:, -2]) > 1e-4  # away from the boundaries (densified edges)
    best = np.argmax(power, axis=1)
    merged_into = dict(cells.attrs["merged"])  # a merged row's site is that of the row it went into
    checked = 0
    for k in np.nonzero(clear)[0]:
        # The cell holding the point is that of the site built from row best[k].
        holders = cells[cells.geometry.contains(shapely.geometry.Point(lon[k], lat[k]))]
        assert len(holders) == 1, (lat[k], lon[k])
        row = merged_into.get(int(best[k]), int(best[k]))
        assert holders.iloc[0]["site_id"] == str(sample.iloc[row]["icao"])
        checked += 1
    assert checked > 2500


def test_hidden_sites_are_listed_and_empty():
    frame = pd.DataFrame({"id": list("ABCDEFG"), "lat": [0, 0, 90, 0, 0, -90, 0], "lon": [0, 90, 0, 180, -90, 0, 0.05],
                          "r": [600_000, 0, 0, 0, 0, 0, 0]})
    with pytest.warns(geovor.HiddenSiteWarning, match="row 6 \\(held by row 0\\)"):
        cells = geovor.cells(frame, weights="r")
    assert cells.attrs["hidden"] == [(6, 0)]
    g = cells[cells["site_id"] == "G"].iloc[0]
    assert g.geometry.is_empty and g["area_m2"] == 0 and g["n_vertices"] == 0
    assert not cells[cells["site_id"] != "G"].geometry.is_empty.any()
    with pytest.warns(geovor.HiddenSiteWarning):
        triangles, _ = geovor.delaunay(frame, weights="r")
    assert triangles.attrs["hidden"] == [(6, 0)]


@pytest.mark.parametrize("bad", [-1.0, np.nan, 1e7 + 8000, np.inf])
def test_bad_radii_name_their_index(bad):
    radii = np.array([0.0, 10.0, bad])
    with pytest.raises(ValueError, match="weights\\[2\\]: radius"):
        geovor.cells(lat=[0, 10, 20], lon=[0, 10, 20], weights=radii)


def test_weight_column_errors(stations):
    with pytest.raises(ValueError, match="no weight column 'reach'"):
        geovor.cells(stations.iloc[:20], weights="reach")
    with pytest.raises(ValueError, match="weights has 2 values"):
        geovor.cells(lat=[0, 10, 20], lon=[0, 10, 20], weights=[1.0, 2.0])


def test_balance_gives_every_cell_its_share(stations):
    cells = geovor.balance(stations)
    assert len(cells) == 5631 and cells.attrs["iterations"][-1][0] < 1e-6
    assert np.allclose(cells["area_m2"] / cells["target_m2"], 1, atol=1e-5)  # as written (densified)
    # The same cells as cells() with those radii.
    again = geovor.cells(stations, weights=cells.attrs["radii_m"])
    assert cells.geometry.geom_equals_exact(again.geometry, 0).all()
    # Capacities: twice the share for the US stations.
    capacity = np.where(stations["icao"].str.startswith("K"), 2.0, 1.0)
    weighted = geovor.balance(stations, capacity=capacity)
    us = weighted["icao"].str.startswith("K")
    assert np.allclose(weighted.loc[us, "target_m2"].mean() / weighted.loc[~us, "target_m2"].median(), 2, rtol=1e-3)


def test_balance_not_converged_raises(stations):
    with pytest.raises(ValueError, match="not converged after 1 iterations"):
        geovor.balance(stations, max_iterations=1)
    with pytest.raises(ValueError, match="share|capacity"):
        geovor.balance(lat=[0, 10, 20, -30], lon=[0, 100, -120, 50], capacity=[1, 0, 1, 1])


def test_index_with_weights_answers_the_power_cell(stations, tmp_path):
    """geovor.Index(weights=): the site of largest power (brute force), the cell of geovor.cells
    holding the query, hidden sites never answered, by power for k > 1, saved and loaded."""
    rng = np.random.default_rng(34)
    sample = stations.iloc[::6].reset_index(drop=True)
    radii = rng.choice([0.0, 30_000.0, 200_000.0, 500_000.0], size=len(sample))
    lat_s, lon_s = sample["lat_deg"].to_numpy(), sample["lon_deg"].to_numpy()
    index = geovor.Index(lat_s, lon_s, weights=radii)
    assert index.weighted
    by_site = index.sites()  # rows merged into a site: its first row is the one it stands for
    hidden = by_site["hidden"].to_numpy()
    assert hidden.any()
    first = by_site["first_row"].to_numpy()
    lat_s, lon_s, radii = lat_s[first], lon_s[first], radii[first]
    lat = np.degrees(np.arcsin(rng.uniform(-1, 1, 4000)))
    lon = rng.uniform(-180, 180, 4000)
    site, dist = index.nearest(lat, lon)
    power = directions(lat, lon) @ directions(lat_s, lon_s).T / np.cos(radii / R)
    power[:, hidden] = -np.inf  # a hidden site's power is never the largest; it can be second
    order = np.argsort(-power, axis=1)[:, :4]
    top = np.take_along_axis(power, order, axis=1)
    clear = (top[:, 0] - top[:, 1]) > 1e-9
    assert clear.sum() > 3900
    assert np.array_equal(site[clear], order[clear, 0])
    assert not hidden[site].any()
    ang = np.arccos(np.clip(np.sum(directions(lat, lon) * directions(lat_s[site], lon_s[site]), axis=1), -1, 1))
    assert np.allclose(dist, ang * R, atol=1e-3)
    # k = 3: by decreasing power
    k3, _ = index.nearest(lat, lon, k=3)
    clear3 = clear & ((top[:, 1] - top[:, 2]) > 1e-9) & ((top[:, 2] - top[:, 3]) > 1e-9)
    assert np.array_equal(k3[clear3], order[clear3, :3])
    # the cells of the same sites hold the answers
    with pytest.warns(geovor.HiddenSiteWarning):
        cells = geovor.cells(lat=lat_s, lon=lon_s, weights=radii)  # the same sites, in site order
    geoms = dict(zip(cells["site_index"], cells.geometry))
    pts = gpd.points_from_xy(lon, lat)
    far = (top[:, 0] - top[:, 1]) > 1e-4  # away from the densified edges
    assert all(geoms[s].contains(p) for s, p, f in zip(site, pts, far) if f)
    # the metrics of unweighted sites are refused; the file keeps the weights
    with pytest.raises(ValueError, match="power"):
        index.nearest(lat[:5], lon[:5], metric="sphere")
    with pytest.raises(ValueError, match="power"):
        index.nearest(lat[:5], lon[:5], metric="geodesic")
    path = tmp_path / "weighted.gvi"
    index.save(path)
    again = geovor.Index.load(path)
    assert again.weighted
    assert np.array_equal(again.nearest(lat, lon, k=3)[0], k3)


def test_index_weights_errors_and_equal_radii(stations):
    sample = stations.iloc[::20].reset_index(drop=True)
    with pytest.raises(ValueError, match=r"weights\[2\]"):
        geovor.Index(sample["lat_deg"], sample["lon_deg"], weights=[0, 1, -5] + [0] * (len(sample) - 3))
    with pytest.raises(ValueError, match="weights"):
        geovor.Index(sample["lat_deg"], sample["lon_deg"], weights=[0, 1])
    with pytest.raises(ValueError, match="no column 'radius'"):
        geovor.Index.from_frame(sample, weights="radius")
    # equal radii are no weights: the ordinary index and its metrics
    equal = geovor.Index.from_frame(sample.assign(r=5000.0), weights="r")
    plain = geovor.Index.from_frame(sample)
    assert not equal.weighted
    rng = np.random.default_rng(35)
    lat, lon = rng.uniform(-80, 80, 500), rng.uniform(-180, 180, 500)
    for metric in (None, "sphere", "power"):
        assert np.array_equal(equal.nearest(lat, lon, metric=metric)[0], plain.nearest(lat, lon)[0])
    assert np.array_equal(equal.nearest(lat, lon, metric="geodesic")[0], plain.nearest(lat, lon, metric="geodesic")[0])
