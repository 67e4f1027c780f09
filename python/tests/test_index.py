"""geovor.Index against brute force: geocentric directions and great-circle distances computed
here with numpy, WGS84 geodesics with geographiclib (Karney's Python package)."""
import subprocess
from pathlib import Path

import numpy as np
import pytest
from geographiclib.geodesic import Geodesic

import geovor

EARTH_RADIUS_M = 6371008.771415  # the mean radius geovor's sphere metric uses (R1 of WGS84)
ROOT = Path(__file__).resolve().parents[2]


def unit_vectors(lat_deg, lon_deg):
    """Geocentric directions of geodetic WGS84 positions (via ECEF)."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    lat, lon = np.radians(lat_deg), np.radians(lon_deg)
    n = a / np.sqrt(1 - e2 * np.sin(lat) ** 2)
    xyz = np.column_stack([n * np.cos(lat) * np.cos(lon), n * np.cos(lat) * np.sin(lon), n * (1 - e2) * np.sin(lat)])
    return xyz / np.linalg.norm(xyz, axis=1)[:, None]


def brute_force(site_lat, site_lon, q_lat, q_lon):
    """Great-circle distances (m) of every query to every site."""
    s, q = unit_vectors(site_lat, site_lon), unit_vectors(q_lat, q_lon)
    dots = q @ s.T
    cross = np.linalg.norm(np.cross(q[:, None, :], s[None, :, :]), axis=2)
    return EARTH_RADIUS_M * np.arctan2(cross, dots)


def awkward_sites(seed):
    """Random sites plus a grid through the poles and the antimeridian, and shared latitudes."""
    rng = np.random.default_rng(seed)
    lat = np.degrees(np.arcsin(rng.uniform(-1, 1, 400)))
    lon = rng.uniform(-180, 180, 400)
    glat, glon = np.meshgrid(np.arange(-90, 91, 15.0), np.arange(-180, 180, 20.0))
    lat = np.concatenate([lat, glat.ravel(), np.full(20, 45.0), [89.9999, -89.9999]])
    lon = np.concatenate([lon, glon.ravel(), np.linspace(179.9, 180.1, 20), [0.0, 179.0]])
    # Grid rows at the poles are one point each: keep one.
    keep = np.ones(len(lat), bool)
    pole_rows = np.flatnonzero(np.abs(lat) == 90)
    keep[pole_rows] = False
    keep[pole_rows[lat[pole_rows] > 0][0]] = keep[pole_rows[lat[pole_rows] < 0][0]] = True
    return lat[keep], ((lon[keep] + 180) % 360) - 180


def queries(seed, n=3000):
    rng = np.random.default_rng(seed)
    # A random walk (coherent, as GPS tracks) and uniform points, the poles included.
    walk_lat = np.clip(np.cumsum(rng.normal(0, 0.5, n // 2)), -90, 90)
    walk_lon = ((np.cumsum(rng.normal(0, 0.5, n // 2)) + 180) % 360) - 180
    lat = np.concatenate([walk_lat, np.degrees(np.arcsin(rng.uniform(-1, 1, n - n // 2))), [90.0, -90.0]])
    lon = np.concatenate([walk_lon, rng.uniform(-180, 180, n - n // 2), [0.0, 0.0]])
    return lat, lon


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_nearest_is_the_brute_force_nearest(threads):
    slat, slon = awkward_sites(1)
    index = geovor.Index(slat, slon)
    qlat, qlon = queries(2)
    site, dist = index.nearest(qlat, qlon, threads=threads)
    assert site.shape == dist.shape == (len(qlat),) and site.dtype == np.int64
    d = brute_force(slat, slon, qlat, qlon)
    best = d.min(axis=1)
    np.testing.assert_allclose(dist, best, rtol=1e-9, atol=1e-6)
    # The answer is a nearest site (ties: any of the tied ones, here none are closer).
    assert np.all(d[np.arange(len(qlat)), site] <= best + 1e-6)


def test_k_nearest_and_max_distance():
    slat, slon = awkward_sites(3)
    index = geovor.Index(slat, slon)
    qlat, qlon = queries(4, 500)
    d = brute_force(slat, slon, qlat, qlon)
    site, dist = index.nearest(qlat, qlon, k=6)
    assert site.shape == (len(qlat), 6)
    np.testing.assert_allclose(dist, np.sort(d, axis=1)[:, :6], rtol=1e-9, atol=1e-6)
    assert np.all(np.diff(dist, axis=1) >= 0)
    limit = 300e3
    site_r, dist_r = index.nearest(qlat, qlon, k=6, max_distance_m=limit)
    within = np.sort(d, axis=1)[:, :6] <= limit
    assert np.array_equal(site_r >= 0, within)
    assert np.all(np.isinf(dist_r[~within]))
    np.testing.assert_allclose(dist_r[within], dist[within])


def test_geodesic_metric():
    slat, slon = awkward_sites(5)
    slat, slon = slat[::3], slon[::3]
    index = geovor.Index(slat, slon)
    qlat, qlon = queries(6, 120)
    site, dist = index.nearest(qlat, qlon, metric="geodesic")
    geod = Geodesic.WGS84
    site3, dist3 = index.nearest(qlat, qlon, k=3, metric="geodesic", max_distance_m=2e6)
    for i in range(len(qlat)):
        d = np.array([geod.Inverse(qlat[i], qlon[i], a, b)["s12"] for a, b in zip(slat, slon)])
        assert dist[i] == pytest.approx(d.min(), rel=1e-12, abs=1e-6)
        assert d[site[i]] <= d.min() + 1e-6
        best3 = np.sort(d)[:3]
        within = best3 <= 2e6
        np.testing.assert_allclose(dist3[i][within], best3[within], rtol=1e-12, atol=1e-6)
        assert np.all(site3[i][~within] == -1) and np.all(np.isinf(dist3[i][~within]))


def test_ids_merges_and_sites_table():
    index = geovor.Index([10.0, 10.0, 20.0, 10.000000001], [5.0, 5.0, 6.0, 5.0], ids=["a", "b", "c", "d"])
    assert index.num_sites == 2
    sites = index.sites()
    assert sites["id"].tolist() == ["a", "c"]
    assert sites["rows"].tolist() == [[0, 1, 3], [2]]
    assert sites["first_row"].tolist() == [0, 2]
    site, _ = index.nearest([19.0], [6.0])
    assert site.tolist() == [1]


def test_save_load_round_trip_and_the_command_reads_it(tmp_path):
    slat, slon = awkward_sites(7)
    index = geovor.Index(slat, slon, ids=[f"s{i}" for i in range(len(slat))])
    path = tmp_path / "sites.gvi"
    index.save(path)
    with pytest.raises(OSError, match="exists"):
        index.save(path)
    index.save(path, overwrite=True)
    loaded = geovor.Index.load(path)
    qlat, qlon = queries(8, 400)
    for a, b in zip(index.nearest(qlat, qlon, k=3), loaded.nearest(qlat, qlon, k=3)):
        np.testing.assert_array_equal(a, b)
    assert loaded.sites()["id"].tolist() == index.sites()["id"].tolist()
    geovor_tool = ROOT / "build" / "tools" / "geovor"
    if not geovor_tool.exists():
        pytest.skip("the geovor command is not built")
    text = "\n".join(f"{a!r},{b!r}" for a, b in zip(qlat[:50], qlon[:50]))
    out = subprocess.run([str(geovor_tool), "nearest", "--sites", str(path)], input="lat,lon\n" + text + "\n",
                         capture_output=True, text=True, check=True).stdout.splitlines()
    assert out[0] == "query_id,site_index,site_id,distance_m,lat,lon"  # then the query's columns
    site, dist = loaded.nearest(qlat[:50], qlon[:50])
    for line, s, d in zip(out[1:], site, dist):
        _, s_cmd, id_cmd, d_cmd, _, _ = line.split(",")
        assert int(s_cmd) == s and id_cmd == f"s{s}" and float(d_cmd) == pytest.approx(d, abs=1e-3)


def test_index_from_a_geovor_index_file(tmp_path):
    geovor_tool = ROOT / "build" / "tools" / "geovor"
    if not geovor_tool.exists():
        pytest.skip("the geovor command is not built")
    path = tmp_path / "stations.gvi"
    subprocess.run([str(geovor_tool), "index", str(ROOT / "datasets" / "weather_stations.csv"), "-o", str(path)],
                   check=True)
    index = geovor.Index.load(path)
    assert index.num_sites > 5000
    site, dist = index.nearest([51.4775], [-0.4614])  # Heathrow
    assert index.sites()["id"][site[0]] == "EGLL"
    assert dist[0] < 2000


def test_from_frame():
    pd = pytest.importorskip("pandas")
    gpd = pytest.importorskip("geopandas")
    frame = pd.DataFrame({"Name": ["x", "y"], "Latitude": [0.0, 45.0], "Longitude": [0.0, 90.0]})
    index = geovor.Index.from_frame(frame)
    assert index.sites()["id"].tolist() == ["x", "y"]
    gdf = gpd.GeoDataFrame({"code": ["p", "q"]}, geometry=gpd.points_from_xy([0.0, 90.0], [0.0, 45.0]), crs="EPSG:4326")
    assert geovor.Index.from_frame(gdf).nearest([44.0], [89.0])[0].tolist() == [1]
    mercator = gdf.to_crs("EPSG:3857")
    assert geovor.Index.from_frame(mercator).nearest([44.0], [89.0])[0].tolist() == [1]
    with pytest.raises(ValueError, match="latitude/longitude"):
        geovor.Index.from_frame(pd.DataFrame({"a": [1.0]}))


def test_bad_input_names_the_row(tmp_path):
    with pytest.raises(ValueError, match="site 1"):
        geovor.Index([0.0, 95.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="site 0"):
        geovor.Index([np.nan], [0.0])
    index = geovor.Index([0.0, 10.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="query 2"):
        index.nearest([0.0, 1.0, np.inf], [0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="k must"):
        index.nearest([0.0], [0.0], k=0)
    with pytest.raises(ValueError, match="metric"):
        index.nearest([0.0], [0.0], metric="manhattan")
    with pytest.raises(ValueError, match="values"):
        index.nearest([0.0, 1.0], [0.0])
    with pytest.raises(OSError):
        geovor.Index.load(tmp_path / "missing.gvi")
    (tmp_path / "junk.gvi").write_bytes(b"GEOVORIX" + b"\0" * 100)
    with pytest.raises(ValueError, match="junk.gvi"):
        geovor.Index.load(tmp_path / "junk.gvi")
