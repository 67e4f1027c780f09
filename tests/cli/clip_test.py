#!/usr/bin/python3
"""geovor cells --clip (issue 35) on the bundled stations and Natural Earth's countries (Debian's
python3-geopandas), against oracles that share no code with geovor: every piece valid as written
(shapely/GEOS), its area_m2 geographiclib's PolygonArea of the rings as written, the shares of each
country summing to 1, the pieces of a country covering it (GEOS), random points of each country
in the piece of their nearest station (brute force in numpy); the weights table (--no-geometry)
the same pieces; regions in Web Mercator reprojected; the same bytes on 1 and 2 threads; the
geovor.cells(clip=) pieces the same; bad regions reported (a line feature, a bow tie, a point
layer), --no-geometry without --clip refused.
Usage: clip_test.py GEOVOR WORKDIR [PYTHON_EXTENSION]"""
import csv
import json
import os
import subprocess
import sys

import numpy as np

geovor, work = sys.argv[1:3]
extension = sys.argv[3] if len(sys.argv) > 3 else None
os.makedirs(work, exist_ok=True)
import geopandas as gpd  # noqa: E402
from geographiclib.geodesic import Geodesic  # noqa: E402
from shapely.geometry import Point, shape  # noqa: E402
from shapely.ops import unary_union  # noqa: E402

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
stations = os.path.join(root, "datasets", "weather_stations.csv")
countries_shp = os.path.join(os.path.dirname(gpd.datasets.get_path("naturalearth_lowres")), "naturalearth_lowres.shp")
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what, flush=True)


def run(*args, expect=0):
    r = subprocess.run([geovor, *args], capture_output=True, text=True)
    check(r.returncode == expect, f"geovor {' '.join(args)}: exit {r.returncode} (expected {expect}): {r.stderr[-500:]}")
    return r


def polygon_area(geometry):
    total = 0.0
    for polygon in getattr(geometry, "geoms", [geometry]):
        for ring in [polygon.exterior, *polygon.interiors]:
            a = Geodesic.WGS84.Polygon()
            for lon, lat in list(ring.coords)[:-1]:
                a.AddPoint(lat, lon)
            total += a.Compute(False, True)[2]
    return total


countries = os.path.join(work, "countries.gpkg")
subprocess.run(["ogr2ogr", "-overwrite", "-f", "GPKG", countries, countries_shp, "-nln", "countries"], check=True)
pieces_path = os.path.join(work, "pieces.geojson")
r = run("cells", stations, "--clip", countries, "--region-id-field", "name", "-o", pieces_path, "--overwrite")
check("222 sites' cells meet no region" in r.stderr, f"the sites at sea are listed: {r.stderr[-300:]}")
with open(pieces_path) as f:
    pieces = json.load(f)["features"]
check(len(pieces) == 6723, f"{len(pieces)} pieces")
shares, by_key, by_region = {}, {}, {}
for p in pieces:
    q = p["properties"]
    g = shape(p["geometry"])
    check(g.is_valid, f"piece of {q['site_id']} in {q['region_id']} is valid")
    shares[q["region_id"]] = shares.get(q["region_id"], 0) + q["region_share"]
    by_key[(q["site_index"], q["region_id"])] = g
    by_region.setdefault(q["region_id"], []).append(g)
for p in pieces[::25]:
    a = polygon_area(shape(p["geometry"]))
    check(abs(p["properties"]["area_m2"] - a) <= 1e-9 * a + 1e-3, f"area_m2 of {p['properties']['site_id']}: {p['properties']['area_m2']} vs {a}")
check(all(abs(s - 1) <= 1e-9 for s in shares.values()), f"shares sum to 1: {min(shares.values())} .. {max(shares.values())}")
check({"region_name", "region_iso_a3", "icao", "name", "region_share", "area_m2"} <= set(pieces[0]["properties"]), "fields")

world = gpd.read_file(countries)
# The sites as geovor builds them (the merged stations share one site): the cells' first rows.
run("cells", stations, "-o", os.path.join(work, "cells.geojson"), "--overwrite", "-q")
with open(os.path.join(work, "cells.geojson")) as f:
    cell_features = json.load(f)["features"]
lat = np.array([c["properties"]["lat_deg"] for c in cell_features], dtype=float)
lon = np.array([c["properties"]["lon_deg"] for c in cell_features], dtype=float)
site_index = np.array([c["properties"]["site_index"] for c in cell_features])


def unit(la, lo):
    p, l = np.radians(la), np.radians(lo)
    e2 = 0.0066943799901413165
    n = 1 / np.sqrt(1 - e2 * np.sin(p) ** 2)
    v = np.stack([n * np.cos(p) * np.cos(l), n * np.cos(p) * np.sin(l), n * (1 - e2) * np.sin(p)], axis=-1)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


units = unit(lat, lon)
rng = np.random.default_rng(35)
checked = 0
for name, region in zip(world.name, world.geometry):
    union = unary_union(by_region.get(name, []))
    check(union.symmetric_difference(region).area <= 1e-5 * region.area, f"{name}: the pieces cover it")
    w, s, e, n = region.bounds
    for lo_, la_ in zip(rng.uniform(w, e, 200), rng.uniform(s, n, 200)):
        if not region.contains(Point(lo_, la_)):
            continue
        d = units @ unit(la_, lo_)
        order = np.argsort(-d)
        gap = (np.arccos(min(1, d[order[1]])) - np.arccos(min(1, d[order[0]]))) * 6371008.8
        piece = by_key.get((int(site_index[order[0]]), name))
        check(gap < 300 or (piece is not None and piece.buffer(1e-7).contains(Point(lo_, la_))),
              f"{name}: ({la_}, {lo_}) not in the piece of its nearest site {site_index[order[0]]}")
        checked += 1
        if checked % 5 == 0:
            break
check(checked > 300, f"{checked} random points checked")

# The weights table: the same pieces.
weights = os.path.join(work, "weights.csv")
run("cells", stations, "--clip", countries, "--region-id-field", "name", "--no-geometry", "-o", weights, "--overwrite", "-q")
with open(weights) as f:
    rows = list(csv.DictReader(f))
check(len(rows) == len(pieces), f"weights: {len(rows)} rows")
got = {(int(r["site_index"]), r["region_id"]): float(r["region_share"]) for r in rows}
# Both of doubles: the weights and the GeoPackage pieces (GeoJSON's are cut at 7 decimals).
gpkg = os.path.join(work, "pieces.gpkg")
run("cells", stations, "--clip", countries, "--region-id-field", "name", "-o", gpkg, "--overwrite", "-q")
doubles = gpd.read_file(gpkg)
check(len(doubles) == len(rows) and all(got[(int(i), n)] == s for i, n, s in zip(doubles.site_index, doubles.region_id, doubles.region_share)),
      "weights table = the pieces' shares")
check(all(abs(got[(p["properties"]["site_index"], p["properties"]["region_id"])] - p["properties"]["region_share"]) < 1e-6
          for p in pieces), "the shares at 7 decimals are within 1e-6 of the doubles'")
# Threads and CRS.
one, two = os.path.join(work, "t1.geojson"), os.path.join(work, "t2.geojson")
run("cells", stations, "--clip", countries, "-o", one, "--threads", "1", "--overwrite", "-q")
run("cells", stations, "--clip", countries, "-o", two, "--threads", "2", "--overwrite", "-q")
check(open(one, "rb").read() == open(two, "rb").read(), "the same bytes on 1 and 2 threads")
mercator = os.path.join(work, "countries_3857.gpkg")
subprocess.run(["ogr2ogr", "-overwrite", "-f", "GPKG", mercator, countries, "-t_srs", "EPSG:3857", "-where", "name = 'France'"], check=True)
r = run("cells", stations, "--clip", mercator, "--region-id-field", "name", "--no-geometry", "-o", "-", "-q")
france = [row for row in csv.DictReader(r.stdout.splitlines())]
check(len(france) > 100 and abs(sum(float(x["region_share"]) for x in france) - 1) < 1e-9, f"France in Web Mercator: {len(france)} pieces")
# Python gives the same pieces (doubles: the GeoPackage output).
if extension:  # the package's sources with the extension just built, as the QGIS test does
    import shutil

    pylib = os.path.join(work, "pylib")
    shutil.rmtree(pylib, ignore_errors=True)
    shutil.copytree(os.path.join(root, "python", "geovor"), os.path.join(pylib, "geovor"))
    shutil.copy(extension, os.path.join(pylib, "geovor", os.path.basename(extension)))
    sys.path.insert(0, pylib)
try:
    import geovor as geovor_py
    import pandas as pd

    py = geovor_py.cells(pd.read_csv(stations), clip=world)
    cmd = gpd.read_file(gpkg)
    check(len(py) == len(cmd) and np.allclose(py.region_share.to_numpy(), cmd.region_share.to_numpy(), rtol=1e-12, atol=0)
          and (py.region_index.to_numpy() == cmd.region_index.to_numpy()).all(),
          "geovor.cells(clip=) = geovor cells --clip (GeoPackage)")
except ImportError:
    print("no geovor Python package: the comparison with geovor.cells(clip=) is skipped")
# Bad regions.
bad = os.path.join(work, "bad_regions.geojson")
with open(bad, "w") as f:
    json.dump({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {"id": "line"}, "geometry": {"type": "LineString", "coordinates": [[0, 0], [10, 10]]}},
        {"type": "Feature", "properties": {"id": "bowtie"}, "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [10, 10], [10, 0], [0, 10], [0, 0]]]}},
        {"type": "Feature", "properties": {"id": "ok"}, "geometry": {"type": "Polygon", "coordinates": [[[20, 20], [30, 20], [30, 30], [20, 20]]]}}]}, f)
r = run("cells", stations, "--clip", bad, "--region-id-field", "id", "--no-geometry", "-o", "-", "-q")
check("feature 1 (FID 0): geometry is a Line String, not a Polygon" in r.stderr.replace("LineString", "Line String"), f"line feature: {r.stderr}")
check("region bowtie (feature 2): invalid polygon (" in r.stderr and "Self-intersection" in r.stderr, f"bow tie: {r.stderr}")
check("ok" in r.stdout and "bowtie" in r.stdout, f"the valid regions' pieces: {r.stdout[:200]}")
points_layer = os.path.join(work, "points.geojson")
with open(points_layer, "w") as f:
    json.dump({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {}, "geometry": {"type": "Point", "coordinates": [0, 0]}}]}, f)
r = run("cells", stations, "--clip", points_layer, "-o", "-", expect=3)
check("no feature is a polygon" in r.stderr, f"a point layer: {r.stderr}")
r = run("cells", stations, "--no-geometry", "-o", "-", expect=2)
check("--no-geometry is the weights table of --clip" in r.stderr, f"--no-geometry alone: {r.stderr}")
print(f"clip_test: {len(failures)} failures")
sys.exit(1 if failures else 0)
