#!/usr/bin/env python3
"""Correctness check of bench/serve/run.sh: the nearest station of the first N query points from
geovor serve, the FastAPI service and PostGIS, against each other and against brute force.

Usage: check.py SITES.csv POINTS.csv N GEOVOR_URL FASTAPI_URL POSTGIS.csv
  POSTGIS.csv: i,id lines (i the 1-based point number), PostGIS's nearest station of each point.

Two spheres are in play. geovor (and the FastAPI service, written to match it) place a point at
the geocentric direction of its WGS84 position; PostGIS's geography KNN (<->) works on a sphere
that takes the geodetic latitude as the spherical one. Each service is checked against brute force
on its own sphere; where geovor and PostGIS name different stations, the pair is an agreement when
the two stations are at the same distance (relative 1e-9: ties, such as stations at the same
position), else it is counted as a difference of the spheres when PostGIS's station is the exact
nearest on PostGIS's sphere. Prints the counts; exits 1 when a service is wrong on its own sphere.
"""
import csv
import http.client
import json
import sys
import urllib.parse

import numpy as np

RTOL = 1e-9
WGS84_F = 1 / 298.257223563
WGS84_E2 = WGS84_F * (2 - WGS84_F)
EARTH_RADIUS_M = 6371008.771415


def geocentric(lat, lon):
    phi, lam = np.radians(lat), np.radians(lon)
    v = np.stack([np.cos(phi) * np.cos(lam), np.cos(phi) * np.sin(lam), (1 - WGS84_E2) * np.sin(phi)], axis=-1)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def naive(lat, lon):
    phi, lam = np.radians(lat), np.radians(lon)
    return np.stack([np.cos(phi) * np.cos(lam), np.cos(phi) * np.sin(lam), np.sin(phi)], axis=-1)


def angles(q, s):
    """Great-circle angles (radians) between unit vectors q (n x 3) and s (m x 3), n x m, from the
    chord (accurate at small angles)."""
    chord = np.linalg.norm(q[:, None, :] - s[None, :, :], axis=-1)
    return 2 * np.arcsin(np.minimum(1.0, chord / 2))


def ask(url, points):
    """site_id and distance_m of GET /nearest for each point, over one keep-alive connection."""
    u = urllib.parse.urlsplit(url)
    conn = http.client.HTTPConnection(u.hostname, u.port, timeout=30)
    ids, dists = [], []
    for lat, lon in points:
        conn.request("GET", f"/nearest?lat={lat!r}&lon={lon!r}")
        r = conn.getresponse()
        body = r.read()
        if r.status != 200:
            raise SystemExit(f"check: {url}/nearest?lat={lat!r}&lon={lon!r}: HTTP {r.status}: {body[:200]!r}")
        p = json.loads(body)["features"][0]["properties"]
        ids.append(str(p["site_id"]))
        dists.append(float(p["distance_m"]))
    conn.close()
    return ids, np.array(dists)


def main() -> None:
    sites_path, points_path, n, geovor_url, fastapi_url, postgis_path = sys.argv[1:7]
    n = int(n)
    with open(sites_path, newline="") as f:
        rows = list(csv.DictReader(f))
    site_ids = [r["icao"] for r in rows]
    column = {s: j for j, s in enumerate(site_ids)}
    slat = np.array([float(r["lat_deg"]) for r in rows])
    slon = np.array([float(r["lon_deg"]) for r in rows])
    with open(points_path) as f:
        next(f)
        points = [tuple(float(v) for v in line.split(",")) for _, line in zip(range(n), f)]
    qlat = np.array([p[0] for p in points])
    qlon = np.array([p[1] for p in points])

    a_geo = angles(geocentric(qlat, qlon), geocentric(slat, slon))  # geovor's sphere
    a_naive = angles(naive(qlat, qlon), naive(slat, slon))  # PostGIS's geography sphere
    best_geo, best_naive = a_geo.min(axis=1), a_naive.min(axis=1)

    def nearest_on(a, best, i, sid):
        return a[i, column[sid]] <= best[i] * (1 + RTOL)

    g_ids, g_dist = ask(geovor_url, points)
    f_ids, f_dist = ask(fastapi_url, points)
    p_ids = [None] * n
    with open(postgis_path) as f:
        for line in f:
            i, sid = line.rstrip("\n").split(",", 1)
            if int(i) <= n:
                p_ids[int(i) - 1] = sid
    if None in p_ids:
        raise SystemExit(f"check: PostGIS answered {n - p_ids.count(None)} of {n} points")

    ok = True

    def own(name, ids, a, best, sphere):
        nonlocal ok
        good = sum(nearest_on(a, best, i, s) for i, s in enumerate(ids))
        ok = ok and good == n
        print(f"  {name:8s} = brute force on {sphere}: {good}/{n}")

    own("geovor", g_ids, a_geo, best_geo, "geovor's sphere (geocentric directions)")
    own("FastAPI", f_ids, a_geo, best_geo, "geovor's sphere (geocentric directions)")
    own("PostGIS", p_ids, a_naive, best_naive, "PostGIS's sphere (geodetic latitude as spherical)")

    def pair(name, ids):
        same = sum(g == o for g, o in zip(g_ids, ids))
        ties = sum(g != o and abs(a_geo[i, column[g]] - a_geo[i, column[o]]) <= RTOL * a_geo[i, column[g]]
                   for i, (g, o) in enumerate(zip(g_ids, ids)))
        differ = n - same - ties
        line = f"  geovor = {name}: {same + ties}/{n} ({same} same station, {ties} ties at the same distance)"
        if differ:
            spheres = sum(g != o and abs(a_geo[i, column[g]] - a_geo[i, column[o]]) > RTOL * a_geo[i, column[g]]
                          and nearest_on(a_naive, best_naive, i, o) and nearest_on(a_geo, best_geo, i, g)
                          for i, (g, o) in enumerate(zip(g_ids, ids)))
            line += f"; {differ} differ, {spheres} of them by the spheres alone (each the exact nearest on its own sphere)"
        print(line)

    pair("FastAPI", f_ids)
    pair("PostGIS", p_ids)
    brute_m = np.array([a_geo[i, column[s]] for i, s in enumerate(g_ids)]) * EARTH_RADIUS_M
    rel = np.abs(g_dist - brute_m) / np.maximum(brute_m, 1e-300)
    print(f"  geovor distance_m vs brute force: max relative difference {rel.max():.2e}")
    rel = np.abs(f_dist - brute_m) / np.maximum(brute_m, 1e-300)
    print(f"  FastAPI distance_m vs geovor's brute force: max relative difference {rel.max():.2e}")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
