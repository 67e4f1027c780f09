"""The FastAPI + uvicorn + scipy cKDTree nearest-site service that bench/serve/run.sh measures
geovor serve against (issue 34): what a user would write around a k-d tree.

GET /nearest?lat=..&lon=.. answers a GeoJSON FeatureCollection of the nearest site, shaped like
geovor serve's answer (properties site_index, site_id, rank, distance_m, then the site's columns).

Sites: the CSV named by GEOVOR_BENCH_SITES, with the columns GEOVOR_BENCH_LAT, GEOVOR_BENCH_LON
and GEOVOR_BENCH_ID (defaults lat_deg, lon_deg, icao: datasets/weather_stations.csv).

Distance: the nearest site by chord length between unit vectors, the same unit vectors as geovor's
sphere metric (the geocentric direction of the point on the WGS84 ellipsoid, SiteEncoder), and
great-circle metres on the sphere of radius 6371008.771415 m, so that the answers are geovor's.

Run: python3 -m uvicorn fastapi_service:app --app-dir bench/serve --host 127.0.0.1 --port 8081
"""
import csv
import json
import math
import os

import numpy as np
from fastapi import FastAPI, Query
from fastapi.responses import Response
from scipy.spatial import cKDTree

EARTH_RADIUS_M = 6371008.771415  # geovor's SiteEncoder::kEarthRadiusM (WGS84 mean radius R1)
WGS84_F = 1 / 298.257223563
WGS84_E2 = WGS84_F * (2 - WGS84_F)


def unit_vectors(lat_deg: np.ndarray, lon_deg: np.ndarray) -> np.ndarray:
    """Geocentric directions of geodetic (lat, lon) at height 0 on WGS84: ECEF / |ECEF|."""
    phi, lam = np.radians(lat_deg), np.radians(lon_deg)
    # ECEF is N(phi) * (cos phi cos lam, cos phi sin lam, (1 - e^2) sin phi); N cancels out.
    v = np.stack([np.cos(phi) * np.cos(lam), np.cos(phi) * np.sin(lam), (1 - WGS84_E2) * np.sin(phi)], axis=-1)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _load():
    path = os.environ.get("GEOVOR_BENCH_SITES", "datasets/weather_stations.csv")
    lat_field = os.environ.get("GEOVOR_BENCH_LAT", "lat_deg")
    lon_field = os.environ.get("GEOVOR_BENCH_LON", "lon_deg")
    id_field = os.environ.get("GEOVOR_BENCH_ID", "icao")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    lat = np.array([float(r[lat_field]) for r in rows])
    lon = np.array([float(r[lon_field]) for r in rows])
    return rows, lat, lon, id_field


ROWS, LAT, LON, ID_FIELD = _load()
TREE = cKDTree(unit_vectors(LAT, LON))

app = FastAPI(title="nearest site (cKDTree)")


@app.get("/nearest")
def nearest(lat: float = Query(..., ge=-90, le=90), lon: float = Query(..., ge=-180, le=180)) -> Response:
    chord, i = TREE.query(unit_vectors(np.array(lat), np.array(lon)))
    i = int(i)
    row = ROWS[i]
    properties = {
        "site_index": i,
        "site_id": row[ID_FIELD],
        "rank": 1,
        "distance_m": 2 * math.asin(min(1.0, float(chord) / 2)) * EARTH_RADIUS_M,
    }
    properties.update(row)
    body = {
        "type": "FeatureCollection",
        "features": [
            {
                "type": "Feature",
                "geometry": {"type": "Point", "coordinates": [float(LON[i]), float(LAT[i])]},
                "properties": properties,
            }
        ],
    }
    return Response(content=json.dumps(body), media_type="application/geo+json")


@app.get("/healthz")
def healthz() -> dict:
    return {"status": "ok", "sites": len(ROWS)}
