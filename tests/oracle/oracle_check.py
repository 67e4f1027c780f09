#!/usr/bin/python3
"""Independent randomized oracle for `geovor cells`, `geovor delaunay` and `geovor relax` (issue 14).

Generates degenerate-but-ordinary site sets (rows, columns, grids at every spacing, at the poles and
across +-180, co-circular and nearly co-circular rings, clusters around the merge distance, one
hemisphere, tiny sets), runs geovor on them and checks what it writes against oracles that share no
code with geovor: GEOS validity (shapely), WGS84 polygon areas (pyproj's GeographicLib C port and
python geographiclib), spherical areas by our own formula, brute-force nearest sites, brute-force
convex hull of the unit vectors, shared-segment matching of the tiling, row accounting.

Usage: /usr/bin/python3 oracle_check.py --geovor build/tools/geovor --seed 1 [--cases K] [--quick]
Exit 0 when every check passes, 1 otherwise (each failure listed); last line `oracle: N passed, M failed`.
See README.md beside this file for the tolerances.
"""
import argparse
import csv
import io
import json
import re
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
import traceback

try:
    import numpy as np
    import shapely
    from shapely.geometry import shape, Point, Polygon
    from shapely.validation import explain_validity
    from shapely.ops import unary_union
    from shapely.prepared import prep
    from pyproj import Geod
    from geographiclib.geodesic import Geodesic
except ImportError as exc:  # pragma: no cover
    print(f"oracle: cannot run: {exc}; install python3-shapely python3-pyproj python3-numpy "
          f"python3-geographiclib (scripts/install-deps.sh) and run with /usr/bin/python3", file=sys.stderr)
    print("oracle: 0 passed, 1 failed")
    sys.exit(1)

try:
    from osgeo import ogr  # optional: GDAL's python bindings
    ogr.UseExceptions()
except Exception:  # noqa: BLE001
    ogr = None

# ---------------------------------------------------------------- constants (WGS84, not from geovor)
E2 = 0.0066943799901413165                 # WGS84 first eccentricity squared
ELLIPSOID_AREA = 510065621724088.4         # m^2, GeographicLib's Geodesic.WGS84 EllipsoidArea
_A, _F = 6378137.0, 1 / 298.257223563
R_MEAN = (2 * _A + _A * (1 - _F)) / 3        # m, R1 = (2a+b)/3 = 6371008.7714: the sphere geovor measures on
MERGE_CHORD = 2.0 ** -24                    # merge distance, in Earth radii (unit sphere chord)
MERGE_M = MERGE_CHORD * R_MEAN              # ~0.38 m
FOUR_PI = 4.0 * math.pi
THIN_DECIMALS = 7                           # the grid thin cells are snap rounded to at finer precisions (docs/design.md)
POLE_SNAP_M = 0.18                          # geovor draws a triangle's site this close to a pole at the pole (docs/user-guide.md)
SNAP_RAD = 2.0 ** -36                        # CellGeometry::kSnapRad: points this close to the antimeridian are moved onto it
SNAP_RAD = 2.0 ** -36                       # points this close to a pole or the antimeridian are moved onto it (cell_geometry.hpp)
TIMEOUT_S = 30
GEOD = Geod(ellps="WGS84")
DEG = math.pi / 180.0


# ---------------------------------------------------------------- geometry helpers (our own)
def geocentric_lat(lat_deg):
    """Geodetic latitude (deg, array ok) -> geocentric latitude (rad): tan(gc) = (1-e^2) tan(gd)."""
    phi = np.radians(lat_deg)
    return np.arctan2((1.0 - E2) * np.sin(phi), np.cos(phi))


def unit_vectors(lat_deg, lon_deg):
    lat_deg = np.asarray(lat_deg, dtype=float)
    lon_deg = np.asarray(lon_deg, dtype=float)
    pc = geocentric_lat(lat_deg)
    lam = np.radians(lon_deg)
    return np.stack([np.cos(pc) * np.cos(lam), np.cos(pc) * np.sin(lam), np.sin(pc)], axis=-1)


def to_latlon(u):
    """Unit vectors (n,3) -> geodetic lat, lon in degrees."""
    u = np.asarray(u, dtype=float)
    pc = np.arctan2(u[:, 2], np.hypot(u[:, 0], u[:, 1]))
    lat = np.degrees(np.arctan2(np.sin(pc), (1.0 - E2) * np.cos(pc)))
    lon = np.degrees(np.arctan2(u[:, 1], u[:, 0]))
    return lat, lon


def angle_between(a, b):
    cr = np.cross(a, b)
    return np.arctan2(np.linalg.norm(cr, axis=-1), np.sum(a * b, axis=-1))


def ring_sphere_terms(coords):
    """Signed spherical area (sr, counter-clockwise in lon/lat positive) of a written ring, edges being
    great-circle arcs between the written vertices on the sphere of geocentric directions, by Green's
    theorem in the equal-area coordinates (lon, sin(geocentric lat)). Returns (area, perimeter_rad,
    sum_abs_terms). The ring is planar in [-180,180]x[-90,90]: a side along lat=+-90 is the pole
    (contributes dlon*sin(lat)), a side of constant longitude is a meridian (contributes 0)."""
    c = np.asarray(coords, dtype=float)
    if len(c) < 2:
        return 0.0, 0.0, 0.0
    lon1, lat1 = c[:-1, 0], c[:-1, 1]
    lon2, lat2 = c[1:, 0], c[1:, 1]
    p1 = geocentric_lat(lat1)
    p2 = geocentric_lat(lat2)
    dl = np.radians(lon2 - lon1)
    terms = np.zeros(len(dl))
    pole = (lat1 == lat2) & (np.abs(lat1) == 90.0)
    meridian = (lon1 == lon2) & ~pole
    gen = ~pole & ~meridian
    terms[pole] = dl[pole] * np.sign(lat1[pole])
    t1 = np.tan(p1[gen] / 2)
    t2 = np.tan(p2[gen] / 2)
    d = dl[gen]
    big = np.abs(d) >= math.pi
    e = 2.0 * np.arctan(np.tan(d / 2) * (t1 + t2) / (1.0 + t1 * t2))
    if big.any():  # not a great-circle arc inside its own lon span: integrate the straight lon/lat side
        idx = np.nonzero(big)[0]
        for k in idx:
            s = np.linspace(0, 1, 2049)
            lats = np.radians(lat1[gen][k] + (lat2[gen][k] - lat1[gen][k]) * s)
            f = np.sin(np.arctan2((1 - E2) * np.sin(lats), np.cos(lats)))
            e[k] = d[k] * float(np.mean((f[1:] + f[:-1]) / 2))
    terms[gen] = e
    u1 = unit_vectors(lat1, lon1)
    u2 = unit_vectors(lat2, lon2)
    seglen = angle_between(u1, u2)
    seglen[pole] = 0.0
    return float(-terms.sum()), float(seglen.sum()), float(np.abs(terms).sum())


def ring_area_estimate_m2(coords):
    """Rough ellipsoidal area of a ring (only to pick the representative of GeographicLib's mod-A result)."""
    a, _, _ = ring_sphere_terms(coords)
    return a * ELLIPSOID_AREA / FOUR_PI


def geod_ring_area(coords, geod_fn="pyproj"):
    """GeographicLib area of a written ring (signed, counter-clockwise positive), made unambiguous."""
    c = coords[:-1] if len(coords) > 1 and tuple(coords[0]) == tuple(coords[-1]) else coords
    if geod_fn == "pyproj":
        x, _ = GEOD.polygon_area_perimeter([p[0] for p in c], [p[1] for p in c])
    else:
        poly = Geodesic.WGS84.Polygon()
        for p in c:
            poly.AddPoint(p[1], p[0])
        _, _, x = poly.Compute(False, True)
    est = ring_area_estimate_m2(coords)
    k = round((est - x) / ELLIPSOID_AREA)
    return x + k * ELLIPSOID_AREA


def rings_of(geom):
    """[(coords list, is_exterior)] of a Polygon/MultiPolygon."""
    polys = list(geom.geoms) if geom.geom_type == "MultiPolygon" else [geom]
    out = []
    for p in polys:
        out.append((list(p.exterior.coords), True))
        for h in p.interiors:
            out.append((list(h.coords), False))
    return out


def tri_sr(a, b, c):
    """Signed area of the spherical triangle (a, b, c) (Oosterom & Strackee)."""
    num = np.dot(a, np.cross(b - a, c - a))   # differences first: accurate for tiny triangles
    den = 1.0 + np.dot(a, b) + np.dot(b, c) + np.dot(c, a)
    return 2.0 * math.atan2(num, den)


def tri_sr_accurate(a, b, c):
    """tri_sr taken at the corner where the two shorter sides meet: from a far corner the two
    differences are long and nearly parallel (a site near the antipode of two close ones: 1e-12
    sr off on a triangle of 3.9e-6 sr)."""
    sides = (np.linalg.norm(c - b), np.linalg.norm(a - c), np.linalg.norm(b - a))  # opposite a, b, c
    k = int(np.argmax(sides))
    return tri_sr(*[(a, b, c), (b, c, a), (c, a, b)][k])


def tri_sr_gradient(a, b, c, h=1e-7):
    """Sum over the corners and two tangent directions at each of |d area / d move| (central
    differences): moving the corners by d moves the area by at most d times this. About the sum of
    the chords for a small triangle; far more for one with a corner near another's antipode, where
    the direction to it turns fast (365 with a corner 0.7 degree from the antipode of two others)."""
    tri = [a, b, c]
    g = 0.0
    for i in range(3):
        v = tri[i]
        e = np.array([1.0, 0.0, 0.0]) if abs(v[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        t1 = np.cross(v, e)
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(v, t1)
        for t in (t1, t2):
            plus, minus = list(tri), list(tri)
            plus[i] = (v + h * t) / np.linalg.norm(v + h * t)
            minus[i] = (v - h * t) / np.linalg.norm(v - h * t)
            g += abs(tri_sr_accurate(*plus) - tri_sr_accurate(*minus)) / (2 * h)
    return g


INPUT_ULPS = 4e-16   # how far our unit vector of a site and geovor's may each be from the exact one (2 ulps)


def circumradius(a, b, c):
    """(circumradius in metres, its conditioning in metres) of the triangle of unit vectors a, b, c:
    the pole of the plane through them, in 50-digit arithmetic when a sliver's plane is
    ill-conditioned in doubles. Moving a corner by INPUT_ULPS tilts that plane by up to
    INPUT_ULPS x perimeter / |(b - a) x (c - a)| radians: the conditioning."""
    n = np.cross(b - a, c - a)
    nn = float(np.linalg.norm(n))
    if nn == 0.0:
        return None, 0.0
    perim = float(np.linalg.norm(b - a) + np.linalg.norm(c - b) + np.linalg.norm(a - c))
    cond = perim / nn
    if cond < 1e6:
        r = float(angle_between(a, n / nn))
    else:
        import mpmath as mp
        with mp.workdps(50):
            A, B, C = (mp.matrix([mp.mpf(float(x)) for x in v]) for v in (a, b, c))
            u, w = B - A, C - A
            m = mp.matrix([u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]])
            m = m / mp.norm(m)
            cr = mp.matrix([A[1] * m[2] - A[2] * m[1], A[2] * m[0] - A[0] * m[2], A[0] * m[1] - A[1] * m[0]])
            r = float(mp.atan2(mp.norm(cr), A[0] * m[0] + A[1] * m[1] + A[2] * m[2]))
    return r * R_MEAN, 2.0 * INPUT_ULPS * cond * R_MEAN


def moved_rad(precision):
    """Bound (radians) of how far a written vertex may lie from the exact cell's boundary, besides
    densification: snap rounding of thin cells (half a diagonal of a step of the output's
    decimals, or of THIN_DECIMALS at finer or full precision)."""
    decimals = THIN_DECIMALS if precision is None else min(precision, THIN_DECIMALS)
    return math.radians(0.5 * math.sqrt(2) * 10.0 ** (-decimals))


def round_err_deg(precision):
    """Largest coordinate error (deg) of a vertex written with `precision` decimals (or as a double)."""
    return max(0.5 * 10.0 ** (-precision), 3e-14) if precision is not None else 3e-14


# ---------------------------------------------------------------- generators
def wrap_lon(lon):
    lon = math.fmod(lon + 180.0, 360.0)
    if lon < 0:
        lon += 360.0
    return lon - 180.0


def log_uniform(rng, lo, hi):
    return float(10 ** rng.uniform(math.log10(lo), math.log10(hi)))


def rand_point(rng):
    v = rng.normal(size=3)
    v /= np.linalg.norm(v)
    return float(math.degrees(math.asin(max(-1, min(1, v[2]))))), float(math.degrees(math.atan2(v[1], v[0])))


def destination(lat, lon, dist_deg, bearing_deg):
    """Point at `dist_deg` from (lat, lon) along `bearing_deg`, in spherical lat/lon math."""
    if abs(lat) == 90.0:  # from a pole: the bearing is the longitude
        return lat - math.copysign(dist_deg, lat), wrap_lon(bearing_deg)
    p, l, d, b = (math.radians(x) for x in (lat, lon, dist_deg, bearing_deg))
    sp = math.sin(p) * math.cos(d) + math.cos(p) * math.sin(d) * math.cos(b)
    p2 = math.asin(max(-1.0, min(1.0, sp)))
    l2 = l + math.atan2(math.sin(b) * math.sin(d) * math.cos(p), math.cos(d) - math.sin(p) * sp)
    return math.degrees(p2), wrap_lon(math.degrees(l2))


def interesting_lat(rng):
    r = rng.random()
    if r < 0.15:
        return float(rng.choice([0.0, -30.0, 45.0, 60.0, -89.9, 89.99, 89.999999, -89.9999999]))
    return float(rng.uniform(-89.0, 89.0))


def interesting_lon(rng):
    r = rng.random()
    if r < 0.2:
        return float(rng.choice([179.99, -179.99, 179.9999999, 180.0, -180.0, 0.0, 20.0]))
    return float(rng.uniform(-180.0, 180.0))


def gen_row(rng, quick):
    n = int(rng.integers(2, 25 if quick else 41))
    sp = log_uniform(rng, 1e-7, 10.0)
    n = max(2, min(n, int(359.0 / sp)))
    lat = interesting_lat(rng)
    lon0 = interesting_lon(rng)
    return f"row n={n} spacing={sp:.3g} lat={lat}", [(lat, wrap_lon(lon0 + i * sp)) for i in range(n)]


def gen_column(rng, quick):
    n = int(rng.integers(2, 25 if quick else 41))
    sp = log_uniform(rng, 1e-7, 10.0)
    n = max(2, min(n, int(180.0 / sp) + 1))
    lat0 = float(rng.choice([90.0, -90.0 + (n - 1) * sp])) if rng.random() < 0.3 else \
        float(rng.uniform(-90.0 + (n - 1) * sp, 90.0)) if (n - 1) * sp < 180 else 90.0
    lon = interesting_lon(rng)
    return f"column n={n} spacing={sp:.3g} lon={lon}", \
        [(max(-90.0, lat0 - i * sp), wrap_lon(lon)) for i in range(n)]


def gen_grid(rng, quick):
    cap = 15 if quick else 40
    nlat = int(rng.integers(2, cap + 1))
    nlon = int(rng.integers(2, cap + 1))
    if nlat * nlon > (225 if quick else 900):
        nlon = max(2, (225 if quick else 900) // nlat)
    dlat = log_uniform(rng, 1e-7, 10.0)
    dlon = dlat if rng.random() < 0.5 else log_uniform(rng, 1e-7, 10.0)
    nlat = max(2, min(nlat, int(180.0 / dlat) + 1))
    nlon = max(2, min(nlon, int(359.9 / dlon)))
    where = rng.choice(["anywhere", "north_pole", "south_pole", "antimeridian", "pole_antimeridian"])
    span = (nlat - 1) * dlat
    if where in ("north_pole", "pole_antimeridian"):
        lat0 = 90.0 - (0.0 if rng.random() < 0.6 else float(rng.uniform(0, min(5 * dlat, 1.0))))
    elif where == "south_pole":
        lat0 = -90.0 + span + (0.0 if rng.random() < 0.6 else float(rng.uniform(0, min(5 * dlat, 1.0))))
    else:
        lat0 = float(rng.uniform(-90.0 + span, 90.0)) if span < 180 else 90.0
    if where in ("antimeridian", "pole_antimeridian"):
        lon0 = 180.0 - dlon * (nlon // 2) + float(rng.choice([0.0, dlon / 2, -1e-7]))
    else:
        lon0 = interesting_lon(rng)
    pts = []
    for i in range(nlat):
        la = max(-90.0, min(90.0, lat0 - i * dlat))
        for j in range(nlon):
            pts.append((la, wrap_lon(lon0 + j * dlon)))
    return f"grid {nlat}x{nlon} dlat={dlat:.3g} dlon={dlon:.3g} {where} lat0={lat0} lon0={lon0}", pts


def circle_points(rng, noise, quick):
    n = int(rng.integers(3, 25 if quick else 41))
    r = log_uniform(rng, 1e-6, 89.0)
    if rng.random() < 0.3:
        clat, clon = float(rng.choice([90.0, -90.0])), 0.0
    else:
        clat, clon = interesting_lat(rng), interesting_lon(rng)
    b0 = float(rng.uniform(0, 360))
    pts = []
    for i in range(n):
        if abs(clat) == 90.0:  # exactly one latitude: co-circular in every sense
            la, lo = clat - math.copysign(r, clat), wrap_lon(b0 + 360.0 * i / n)
        else:
            la, lo = destination(clat, clon, r, b0 + 360.0 * i / n)
        if noise:
            la = max(-90.0, min(90.0, la + float(rng.normal()) * noise))
            lo = wrap_lon(lo + float(rng.normal()) * noise)
        pts.append((la, lo))
    centre = rng.random() < 0.4
    if centre:
        pts.append((clat, clon))
    name = "ring" if noise else "circle"
    extra = f" noise={noise:.3g}" if noise else ""
    return f"{name} n={n} r={r:.3g} centre=({clat},{clon}) with_centre={centre}{extra}", pts


def gen_circle(rng, quick):
    return circle_points(rng, 0.0, quick)


def gen_ring(rng, quick):
    return circle_points(rng, log_uniform(rng, 1e-9, 1e-5), quick)


def gen_cluster(rng, quick):
    k = int(rng.integers(1, 6))
    pts = []
    for _ in range(k):
        lat, lon = (interesting_lat(rng), interesting_lon(rng))
        m = int(rng.integers(2, 8))
        for _ in range(m):
            d = MERGE_M * float(rng.uniform(0.5, 2.0))
            b = float(rng.uniform(0, 360))
            dlat = d * math.cos(math.radians(b)) / 111320.0
            dlon = d * math.sin(math.radians(b)) / (111320.0 * max(1e-9, math.cos(math.radians(lat))))
            pts.append((max(-90.0, min(90.0, lat + dlat)), wrap_lon(lon + dlon)))
            if rng.random() < 0.5:
                lat, lon = pts[-1]  # a chain
    extra = int(rng.integers(0, 20))
    pts += [rand_point(rng) for _ in range(extra)]
    return f"cluster k={k} +{extra} random", pts


def gen_hemisphere(rng, quick):
    n = int(rng.integers(3, 60 if quick else 300))
    clat, clon = rand_point(rng) if rng.random() < 0.8 else (90.0, 0.0)
    cap = float(rng.choice([30.0, log_uniform(rng, 1e-4, 89.0)]))
    pts = []
    for _ in range(n):
        d = cap * math.sqrt(rng.random())
        pts.append(destination(clat, clon, d, float(rng.uniform(0, 360))))
    return f"hemisphere n={n} cap={cap:.3g} centre=({clat:.6g},{clon:.6g})", pts


def gen_tiny(rng, quick):
    kind = rng.choice(["random", "collinear", "antipodal", "two", "one"])
    if kind == "random":
        n = int(rng.integers(1, 11))
        return f"tiny random n={n}", [rand_point(rng) for _ in range(n)]
    if kind == "collinear":
        lat, lon = rand_point(rng)
        b = float(rng.uniform(0, 360))
        n = int(rng.integers(3, 6))
        ds = sorted(float(rng.uniform(0, 170)) for _ in range(n))
        return f"tiny {n} on a great circle", [destination(lat, lon, d, b) for d in ds]
    if kind == "antipodal":
        n = int(rng.integers(1, 4))
        pts = []
        for _ in range(n):
            lat, lon = rand_point(rng) if rng.random() < 0.7 else (90.0, 0.0)
            pts += [(lat, lon), (-lat, wrap_lon(lon + 180.0))]
        return f"tiny {n} antipodal pairs", pts
    if kind == "two":
        return "tiny two", [rand_point(rng), rand_point(rng)]
    return "tiny one", [rand_point(rng)]


def gen_random(rng, quick):
    n = int(rng.integers(4, 80 if quick else 400))
    pts = [rand_point(rng) for _ in range(n)]
    dups = int(rng.integers(0, 4))
    for _ in range(dups):
        pts.append(pts[int(rng.integers(0, len(pts)))])
    return f"random n={n} dups={dups}", pts


def gen_repro3(rng, quick):
    return "repro3 A,-30,20/B,-30,20.001/C,-30,20.002", [(-30.0, 20.0), (-30.0, 20.001), (-30.0, 20.002)]


def gen_repro5(rng, quick):
    return "repro5 a,0,10/b,10,10/c,5,3/d,5,-2/e,0,0", [(0.0, 10.0), (10.0, 10.0), (5.0, 3.0), (5.0, -2.0), (0.0, 0.0)]


def gen_great_circle(rng, quick):
    """A run of sites 1e-7 to 1e-2 degree apart on one great circle of the sphere, at any
    inclination, every other one perhaps 10 to 170 degrees on along it, perhaps with random sites:
    the lunes' tips braid at the circle's poles, and the vertex of two close sites and a far one
    must be computed from the close pair (a far corner had put it 3 mm off, across the braid)."""
    n = int(rng.integers(3, 25 if quick else 41))
    sp = log_uniform(rng, 1e-7, 1e-2)
    start = unit_vectors(*rand_point(rng))
    v = rng.normal(size=3)
    along = v - start * float(np.dot(start, v))
    along /= np.linalg.norm(along)
    far = float(rng.uniform(10.0, 170.0)) if rng.random() < 0.6 else 0.0
    angles = np.radians([i * sp + (far if i % 2 else 0.0) for i in range(n)])
    lat, lon = to_latlon(np.cos(angles)[:, None] * start + np.sin(angles)[:, None] * along)
    pts = [(float(la), float(lo)) for la, lo in zip(lat, lon)]
    extra = int(rng.integers(0, 4))
    pts += [rand_point(rng) for _ in range(extra)]
    return f"great circle n={n} spacing={sp:.3g} far={far:.4g} +{extra} random", pts


RECIPES = [gen_row, gen_column, gen_grid, gen_circle, gen_ring, gen_cluster, gen_hemisphere,
           gen_tiny, gen_grid, gen_random, gen_repro3, gen_repro5, gen_great_circle]


def fmt(x):
    r = repr(float(x))
    return r[:-2] if r.endswith(".0") else r


def write_csv(path, pts):
    with open(path, "w") as f:
        f.write("id,lat,lon\n")
        for i, (la, lo) in enumerate(pts):
            f.write(f"r{i},{fmt(la)},{fmt(lo)}\n")


# ---------------------------------------------------------------- running geovor


class Case:
    def __init__(self, seed, index, quick, tmp):
        self.seed, self.index, self.quick = seed, index, quick
        self.rng = np.random.default_rng([seed, index])
        gen = RECIPES[index % len(RECIPES)] if index < len(RECIPES) else RECIPES[int(self.rng.integers(0, len(RECIPES)))]
        self.recipe, self.pts = gen(self.rng, quick)
        self.dir = os.path.join(tmp, f"seed{seed}_case{index}")
        os.makedirs(self.dir, exist_ok=True)
        self.csv = os.path.join(self.dir, "sites.csv")
        write_csv(self.csv, self.pts)
        self.failures = []
        self.passed = 0
        self.notes = []

    def label(self):
        return f"seed {self.seed} case {self.index} [{self.recipe}] ({len(self.pts)} rows, {self.csv})"

    def check(self, ok, cmd, what, detail=""):
        if ok:
            self.passed += 1
        else:
            self.failures.append((cmd, what, detail))
        return ok

    def run(self, geovor, args, allow_error=None):
        cmd = [geovor] + args
        shown = " ".join(cmd)
        t0 = time.time()
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.check(False, shown, "geovor ran past the timeout", f"{TIMEOUT_S} s")
            return None, shown
        if allow_error and p.returncode == 3 and allow_error in p.stderr:
            return p, shown
        if not self.check(p.returncode == 0, shown, "geovor exit status",
                          f"exit {p.returncode} after {time.time() - t0:.2f} s; stderr: {p.stderr.strip()[-1500:]}"):
            return None, shown
        return p, shown


def read_features(path):
    """Features of a GeoJSON / GeoPackage / FlatGeobuf file as [(properties dict, geometry dict or None)]."""
    if path.endswith(".geojson"):
        with open(path) as f:
            fc = json.load(f)
        return [(ft.get("properties") or {}, ft.get("geometry")) for ft in fc["features"]]
    if ogr is not None:
        ds = ogr.Open(path)
        lyr = ds.GetLayer(0)
        out = []
        for ft in lyr:
            g = ft.GetGeometryRef()
            out.append((ft.items(), json.loads(g.ExportToJson()) if g is not None and not g.IsEmpty() else None))
        # ExportToJson writes 15 significant digits: re-read the coordinates exactly from WKB
        lyr.ResetReading()
        exact = []
        for ft in lyr:
            g = ft.GetGeometryRef()
            exact.append(shapely.wkb.loads(bytes(g.ExportToWkb())) if g is not None and not g.IsEmpty() else None)
        return [(p, shapely.geometry.mapping(e) if e is not None else None) for (p, _), e in zip(out, exact)]
    tmp = path + ".as.geojson"
    subprocess.run(["ogr2ogr", "-f", "GeoJSON", "-lco", "RFC7946=NO", "-lco", "SIGNIFICANT_FIGURES=17",
                    "-lco", "WRITE_BBOX=NO", tmp, path], check=True, capture_output=True, timeout=60)
    return read_features(tmp)


import shapely.wkb  # noqa: E402  (used by read_features)


def as_list(v):
    if v is None:
        return []
    if isinstance(v, list):
        return v
    if isinstance(v, str):
        try:
            x = json.loads(v)
            return x if isinstance(x, list) else [x]
        except ValueError:
            return [v]
    return [v]


def coords_of(geom_json):
    """Exterior/hole rings as lists of (lon, lat) from a GeoJSON geometry (exact floats)."""
    out = []
    t = geom_json["type"]
    polys = geom_json["coordinates"] if t == "MultiPolygon" else [geom_json["coordinates"]] if t == "Polygon" else []
    for poly in polys:
        for k, ring in enumerate(poly):
            out.append(([(float(p[0]), float(p[1])) for p in ring], k == 0))
    return out


def read_report(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


# ---------------------------------------------------------------- cell checks
def check_cells(case, feats, cmd, precision, densify_m, sites, row_site, collapsed, full=True, ref_area=None):
    """feats: [(props, geometry json)]; sites: (lat, lon) arrays of the sites by site_index;
    row_site: row id -> site_index (None when unknown, e.g. relax); collapsed: cells reported collapsed."""
    n_sites = len(sites[0])
    U = unit_vectors(sites[0], sites[1])
    rerr = round_err_deg(precision)
    tag = f"p={precision}" if precision is not None else "binary"
    ok_count = case.check(len(feats) == n_sites, cmd, "one cell per site", f"{len(feats)} cells for {n_sites} sites")
    geoms, cells_by_site, props_by_site = [], {}, {}
    bad_geom, orient = [], []
    for props, gj in feats:
        si = props.get("site_index")
        try:
            si = int(si)
        except (TypeError, ValueError):
            case.check(False, cmd, "site_index property", repr(si))
            continue
        props_by_site[si] = props
        if gj is None or not gj.get("coordinates"):
            # geovor writes a cell it cannot write valid at the precision with an empty geometry
            # and area_m2 0, and reports it (stderr, --report): allowed when reported.
            if not collapsed or float(props.get("area_m2") or 0) != 0:
                bad_geom.append(f"site {si} ({props.get('site_id')}): EMPTY geometry (area_m2 {props.get('area_m2')}, area_sr {props.get('area_sr')})")
            continue
        if gj["type"] != "MultiPolygon":
            bad_geom.append(f"site {si}: geometry type {gj['type']}")
        g = shape(gj)
        if g.is_empty:
            bad_geom.append(f"site {si}: empty")
            continue
        if not g.is_valid:
            bad_geom.append(f"site {si} ({props.get('site_id')}): invalid: {explain_validity(g)}")
        for poly in (g.geoms if g.geom_type == "MultiPolygon" else [g]):
            if poly.exterior.is_ccw is False and Polygon(poly.exterior).area > 0:
                orient.append(f"site {si} ({props.get('site_id')}): exterior ring clockwise")
            for h in poly.interiors:
                if h.is_ccw and Polygon(h).area > 0:
                    orient.append(f"site {si}: hole counter-clockwise")
        minx, miny, maxx, maxy = g.bounds
        if minx < -180 or maxx > 180 or miny < -90 or maxy > 90:
            bad_geom.append(f"site {si}: bounds {g.bounds} outside [-180,180]x[-90,90]")
        cells_by_site[si] = (g, gj)
        props_by_site[si] = props
    case.check(not bad_geom, cmd, f"cells valid, non-empty MultiPolygons in range ({tag})",
               f"{len(bad_geom)} bad: " + "; ".join(bad_geom[:6]))
    case.check(not orient, cmd, f"exterior rings counter-clockwise, holes clockwise ({tag})", "; ".join(orient[:5]))
    if not cells_by_site:
        return

    # 2 + 3: areas
    worst_rel, worst_m2, sum_m2_written, sum_sr, sum_m2_prop = 0.0, None, 0.0, 0.0, 0.0
    area_fail, sr_fail, gl_fail, unrounded = [], [], [], []
    n_gl = 0
    for si, (g, gj) in cells_by_site.items():
        props = props_by_site[si]
        a_m2 = 0.0
        a_sr, perim, absterms = 0.0, 0.0, 0.0
        rings = coords_of(gj)
        for coords, _ext in rings:
            a_m2 += geod_ring_area(coords)
            s, p, t = ring_sphere_terms(coords)
            a_sr += s
            perim += p
            absterms += t
        if n_gl < 2 and sum(len(c) for c, _ in rings) < 3000:
            n_gl += 1
            a_gl = sum(geod_ring_area(c, "geographiclib") for c, _ in rings)
            if abs(a_gl - a_m2) > max(1e-9 * abs(a_gl), 0.25):
                gl_fail.append(f"site {si}: pyproj {a_m2!r} vs geographiclib {a_gl!r} (oracle disagreement)")
        sum_m2_written += a_m2
        try:
            got = float(props.get("area_m2"))
            got_sr = float(props.get("area_sr"))
        except (TypeError, ValueError):
            area_fail.append(f"site {si}: area_m2/area_sr not numbers: {props.get('area_m2')!r}, {props.get('area_sr')!r}")
            continue
        sum_m2_prop += got
        diff = abs(got - a_m2)
        rel = diff / max(abs(a_m2), 1e-300)
        ref = (ref_area or {}).get(si)
        if diff > max(1e-9 * abs(a_m2), 0.25) and ref is not None and abs(got - ref) <= max(1e-9 * abs(ref), 0.25):
            unrounded.append(f"site {si} ({props.get('site_id')}): area_m2 {got!r} = the precision-17 polygon's {ref!r}, "
                             f"but the written (rounded) polygon's is {a_m2!r} (diff {diff:.3g} m2, rel {rel:.3g})")
        elif diff > max(1e-9 * abs(a_m2), 0.25):
            area_fail.append(f"site {si} ({props.get('site_id')}): area_m2 {got!r} vs GeographicLib of the written ring "
                             f"{a_m2!r} (diff {diff:.3g} m2, rel {rel:.3g})")
        if diff > 0.25 or a_m2 > 1e6:
            worst_rel = max(worst_rel, rel)
        if precision is None or precision >= 5:
            # area_sr is the exact cell's: the written ring's vertices are off it by rounding,
            # collapsing and the snap rounding of thin cells (moved_rad)
            tol = 2.0 * perim * (math.radians(rerr) * math.sqrt(2) + moved_rad(precision)) + 1e-14 * absterms + 1e-13 * abs(a_sr) + 1e-18
            if abs(got_sr - a_sr) > tol and si not in collapsed:
                sr_fail.append(f"site {si} ({props.get('site_id')}): area_sr {got_sr!r} vs spherical area of the written "
                               f"ring {a_sr!r} (diff {abs(got_sr - a_sr):.3g} sr, tol {tol:.3g})")
    case.check(not area_fail, cmd, f"area_m2 = GeographicLib area of the written polygon ({tag})",
               f"{len(area_fail)} cells; max rel {worst_rel:.3g}; " + "; ".join(area_fail[:5]))
    case.check(not unrounded, cmd, f"area_m2 is the written polygon's, not the unrounded cell's ({tag})",
               f"{len(unrounded)} cells: " + "; ".join(unrounded[:3]))
    case.check(not sr_fail, cmd, f"area_sr = spherical area of the written polygon ({tag})",
               f"{len(sr_fail)} cells: " + "; ".join(sr_fail[:5]))
    if gl_fail:
        case.notes.append("; ".join(gl_fail))
    # area_sr is the exact cell's, written for collapsed and unwritable cells too
    sum_sr = sum(float(p.get("area_sr") or 0) for p in props_by_site.values())
    if full:
        case.check(abs(sum_sr - FOUR_PI) <= 1e-9 * FOUR_PI, cmd, "sum of area_sr = 4 pi",
                   f"sum {sum_sr!r}, 4pi {FOUR_PI!r}, rel diff {abs(sum_sr - FOUR_PI) / FOUR_PI:.3g}")
        if collapsed:
            case.notes.append(f"{cmd}: {len(collapsed)} cells reported collapsed; area sums skipped")
        else:
            case.check(abs(sum_m2_prop - ELLIPSOID_AREA) <= 1e-9 * ELLIPSOID_AREA, cmd, "sum of area_m2 = ellipsoid area",
                       f"sum {sum_m2_prop!r} vs {ELLIPSOID_AREA!r} (rel {abs(sum_m2_prop - ELLIPSOID_AREA) / ELLIPSOID_AREA:.3g})")
            case.check(abs(sum_m2_written - ELLIPSOID_AREA) <= 1e-9 * ELLIPSOID_AREA, cmd,
                       "written polygons' GeographicLib areas sum to the ellipsoid area",
                       f"sum {sum_m2_written!r} (rel {abs(sum_m2_written - ELLIPSOID_AREA) / ELLIPSOID_AREA:.3g})")

    # 6: shared segments, antimeridian and pole lines, planar tiling, neighbours
    seg_owner = {}
    amer = {180.0: {}, -180.0: {}}
    pole_len = {90.0: 0.0, -90.0: 0.0}
    for si, (g, gj) in cells_by_site.items():
        for coords, _ext in coords_of(gj):
            for (x1, y1), (x2, y2) in zip(coords[:-1], coords[1:]):
                if (x1, y1) == (x2, y2):
                    continue
                if x1 == x2 and abs(x1) == 180.0:
                    amer[x1].setdefault(si, []).append((min(y1, y2), max(y1, y2)))
                    continue
                if y1 == y2 and abs(y1) == 90.0:
                    pole_len[y1] += abs(x2 - x1)
                    continue
                seg_owner.setdefault((x1, y1, x2, y2), []).append(si)
    unmatched, multi, pairs, pair_mid = [], [], set(), {}
    for (x1, y1, x2, y2), owners in seg_owner.items():
        if len(owners) > 1:
            multi.append(f"segment ({x1},{y1})->({x2},{y2}) written {len(owners)} times in the same direction (cells {owners[:4]})")
        rev = seg_owner.get((x2, y2, x1, y1), [])
        if len(rev) == 0:
            unmatched.append(f"cell {owners[0]} segment ({x1!r},{y1!r})->({x2!r},{y2!r}) in no other ring")
        elif len(rev) > 1:
            multi.append(f"segment ({x1},{y1})->({x2},{y2}) reversed in {len(rev)} rings")
        for o in owners:
            for r in rev:
                if o != r:
                    pairs.add((min(o, r), max(o, r)))
                    pair_mid.setdefault((min(o, r), max(o, r)), ((x1 + x2) / 2, (y1 + y2) / 2))
    case.check(not unmatched and not multi, cmd, f"every shared segment written once by each side ({tag})",
               f"{len(unmatched)} unmatched, {len(multi)} repeated of {len(seg_owner)}: " + "; ".join((unmatched + multi)[:5]))
    am_bad = []
    for side in (180.0, -180.0):
        total = sum(b - a for iv in amer[side].values() for a, b in iv)
        if full and n_sites > 0 and abs(total - 180.0) > 1e-9:
            am_bad.append(f"segments on lon {side:+g} cover {total!r} deg of latitude, not 180")
    for si in set(amer[180.0]) | set(amer[-180.0]):
        def merged(iv):
            out = []
            for a, b in sorted(iv):
                if out and a <= out[-1][1] + 1e-12:
                    out[-1][1] = max(out[-1][1], b)
                else:
                    out.append([a, b])
            return out
        e, w = merged(amer[180.0].get(si, [])), merged(amer[-180.0].get(si, []))
        if e != w:
            # A cut cell has the same extent on both lines, except where one of its edges lies on
            # the antimeridian (rounded or snapped onto it): there another cell faces it across.
            def minus(a_iv, b_iv):
                out = []
                for a, b in a_iv:
                    cur = a
                    for c, d in b_iv:
                        if d <= cur or c >= b:
                            continue
                        if c > cur:
                            out.append((cur, c))
                        cur = max(cur, d)
                    if cur < b:
                        out.append((cur, b))
                return out
            def covered(piece, line):
                others = merged([iv for o, ivs in amer[line].items() if o != si for iv in ivs])
                return not minus([piece], others)
            lone = [(x, -180.0) for x in minus(e, w)] + [(x, 180.0) for x in minus(w, e)]
            if not all(covered(x, line) for x, line in lone):
                am_bad.append(f"cell {si}: on +180 {e[:3]} but on -180 {w[:3]}, not faced by another cell")
    if full:
        for pl in (90.0, -90.0):
            if abs(pole_len[pl] - 360.0) > 1e-9:
                am_bad.append(f"sides along lat {pl:+g} span {pole_len[pl]!r} deg of longitude, not 360")
    case.check(not am_bad, cmd, f"the cut at +-180 and the pole lines are consistent ({tag})", "; ".join(am_bad[:5]))
    if full:
        planar = sum(g.area for g, _ in cells_by_site.values())
        case.check(abs(planar - 64800.0) <= 1e-6, cmd, f"planar areas sum to 64800 deg2 ({tag})", f"sum {planar!r}")
        nverts = sum(len(c) for _, gj in cells_by_site.values() for c, _ in coords_of(gj))
        if nverts < 150000 and not bad_geom:
            try:
                u = unary_union([g for g, _ in cells_by_site.values()]).area
                case.check(abs(u - 64800.0) <= 1e-6 and abs(planar - u) <= 1e-6, cmd, f"cells cover the plate carree once ({tag})",
                           f"union {u!r}, sum {planar!r}")
            except Exception as exc:  # noqa: BLE001
                case.check(False, cmd, "union of the cells", repr(exc))
    # neighbours
    site_id_to_index = {str(p.get("site_id")): si for si, p in props_by_site.items()}
    nb = {}
    bad_nb = []
    for si, p in props_by_site.items():
        ids = as_list(p.get("neighbors"))
        s = set()
        for i in ids:
            if str(i) not in site_id_to_index:
                bad_nb.append(f"cell {si} lists unknown neighbour {i!r}")
            else:
                s.add(site_id_to_index[str(i)])
        nb[si] = s
    # `neighbors` are the exact diagram's. Where thin parts of cells collapsed (rounding, snap
    # rounding), cells that are not neighbours may share a written segment: both must then be
    # nearly nearest at its midpoint m, d(m, a) - d(m, nearest) <= 2 * (how far the written
    # boundary may lie from the exact one), by brute force over the sites.
    slack = 2.0 * (moved_rad(precision) + math.radians(rerr) * math.sqrt(2) + densify_m / R_MEAN + 1e-12)
    for a, b in pairs:
        if b not in nb.get(a, ()) or a not in nb.get(b, ()):
            m = pair_mid[(a, b)]
            mu = unit_vectors([m[1]], [m[0]])[0]
            d = np.arccos(np.clip(U @ mu, -1.0, 1.0))
            if max(d[a], d[b]) - d.min() > slack:
                bad_nb.append(f"cells {a} and {b} share a written segment around ({m[0]!r}, {m[1]!r}) but are not "
                              f"neighbours, and are {d[a] - d.min():.3g}, {d[b] - d.min():.3g} rad from nearest there")
    for a, s in nb.items():
        for b in s:
            if a not in nb.get(b, ()):
                bad_nb.append(f"cell {a} lists {b} but not the reverse")
    case.check(not bad_nb, cmd, f"neighbors consistent with the shared segments ({tag})",
               f"{len(bad_nb)}: " + "; ".join(bad_nb[:5]))

    # 7: accounting (ids)
    if row_site is not None:
        seen = {}
        bad = []
        for si, p in props_by_site.items():
            ids = [str(x) for x in as_list(p.get("ids"))]
            try:
                if int(p.get("n_rows")) != len(ids):
                    bad.append(f"cell {si}: n_rows {p.get('n_rows')} but {len(ids)} ids")
            except (TypeError, ValueError):
                bad.append(f"cell {si}: n_rows {p.get('n_rows')!r}")
            for i in ids:
                if i in seen:
                    bad.append(f"row {i} in cells {seen[i]} and {si}")
                seen[i] = si
        for rid, si in row_site.items():
            if si is None:
                continue
            if rid not in seen:
                bad.append(f"row {rid} (site {si}) in no cell's ids")
            elif seen[rid] != si:
                bad.append(f"row {rid} in cell {seen[rid]}, report says site {si}")
        case.check(not bad, cmd, f"every row in exactly one cell's ids ({tag})", f"{len(bad)}: " + "; ".join(bad[:5]))

    # 5: random points in the cell of their nearest site
    if not full or n_sites == 0:
        return
    rng = np.random.default_rng([case.seed, case.index, 77, precision or 0])
    m = 100 if case.quick else 200
    P = rng.normal(size=(m, 3))
    near = []
    if n_sites >= 1:
        idx = rng.integers(0, n_sites, size=m)
        G = U[idx] @ U.T
        G[np.arange(m), idx] = -2
        dmin = np.arccos(np.clip(G.max(axis=1), -1, 1)) if n_sites > 1 else np.full(m, 1.0)
        t = rng.normal(size=(m, 3))
        t -= np.sum(t * U[idx], axis=1)[:, None] * U[idx]
        t /= np.linalg.norm(t, axis=1)[:, None]
        ang = dmin * rng.uniform(0, 1.5, size=m)
        near = np.cos(ang)[:, None] * U[idx] + np.sin(ang)[:, None] * t
        P = np.vstack([P, near])
    P /= np.linalg.norm(P, axis=1)[:, None]
    plat, plon = to_latlon(P)
    D = P @ U.T                                  # (k, n)
    a = np.argmax(D, axis=1)
    if n_sites > 1:
        Ga = U[a] @ U.T
        den = np.sqrt(np.maximum(2.0 - 2.0 * Ga, 1e-300))
        num = D[np.arange(len(P)), a][:, None] - D
        marg = num / den
        marg[np.arange(len(P)), a] = np.inf
        marg = marg.min(axis=1) * R_MEAN
    else:
        marg = np.full(len(P), np.inf)
    need = 2.0 * (densify_m + math.radians(rerr) * math.sqrt(2) * R_MEAN) + 1e-3
    prepared = {si: prep(g) for si, (g, _) in cells_by_site.items()}
    wrong, checked = [], 0
    for k in range(len(P)):
        if marg[k] < need or a[k] in collapsed:
            continue
        si = int(a[k])
        if si not in prepared:
            continue
        checked += 1
        pt = Point(float(plon[k]), float(plat[k]))
        if not prepared[si].covers(pt):
            holder = [s for s, pg in prepared.items() if pg.covers(pt)]
            wrong.append(f"point ({plat[k]!r},{plon[k]!r}) nearest site {si} (margin {marg[k]:.3g} m) "
                         f"not in its cell; in cell(s) {holder[:3]}")
    case.check(not wrong, cmd, f"random points lie in their nearest site's cell ({tag}, {checked} checked)",
               f"{len(wrong)} wrong: " + "; ".join(wrong[:4]))


def collapsed_from_stderr(text):
    return [ln for ln in text.splitlines() if "collaps" in ln.lower()]


# ---------------------------------------------------------------- delaunay checks
def check_delaunay(case, geovor, sites, collinear_all):
    d = case.dir
    n = len(sites[0])
    U = unit_vectors(sites[0], sites[1])
    if n >= 3:  # every site on one great circle: True, False, or None within rounding
        sv = np.linalg.svd(U, compute_uv=False)
        collinear_all = True if sv[-1] < 1e-14 * sv[0] else (None if sv[-1] < 1e-9 * sv[0] else False)
    prec = int(case.rng.choice([7, 9, 12, 17]))
    tri, edg = os.path.join(d, "tri.geojson"), os.path.join(d, "edges.geojson")
    p, cmd = case.run(geovor, ["delaunay", case.csv, "-o", tri, "--edges", edg, "--precision", str(prec), "--overwrite", "-q"])
    if p is None:
        return
    tris = read_features(tri)
    edges = read_features(edg)
    rerr = round_err_deg(prec)
    if n >= 3:
        case.check(len(tris) == 2 * n - 4, cmd, "2n-4 triangles", f"{len(tris)} triangles for {n} sites")
    faces, bad, empty, area_bad, sr_bad, cr_bad, vert_bad, orient = [], [], [], [], [], [], [], []
    ghosts = reported_empty = 0
    sum_m2 = sum_sr = 0.0
    for props, gj in tris:
        try:
            t = (int(props["site_a"]), int(props["site_b"]), int(props["site_c"]))
        except (KeyError, TypeError, ValueError):
            bad.append(f"triangle {props.get('tri_index')}: bad site_a/b/c")
            continue
        kind = props.get("kind")
        ghost = int(props.get("ghost", 0))
        ghosts += ghost
        faces.append((t, kind, ghost))
        if len(set(t)) != 3 or max(t) >= n or min(t) < 0:
            bad.append(f"triangle {props.get('tri_index')}: sites {t}")
            continue
        if gj is None or not gj.get("coordinates"):
            # geovor writes a triangle it cannot write valid at the precision with an empty
            # geometry and lists it on stderr ("triangle N (sites ...)"): allowed when listed.
            reported_empty += 1
            empty.append(f"triangle {props.get('tri_index')} {kind} sites {t} ({[props.get(k) for k in ('id_a', 'id_b', 'id_c')]}) EMPTY")
            continue
        g = shape(gj)
        if g.is_empty:
            empty.append(f"triangle {props.get('tri_index')} sites {t} EMPTY")
            continue
        if not g.is_valid:
            bad.append(f"triangle {props.get('tri_index')} {kind} sites {t}: invalid: {explain_validity(g)}")
        for poly in (g.geoms if g.geom_type == "MultiPolygon" else [g]):
            if poly.exterior.is_ccw is False and Polygon(poly.exterior).area > 1e-18:
                orient.append(f"{kind} {t} ({[props.get(k) for k in ('id_a', 'id_b', 'id_c')]}): exterior ring clockwise")
        a, b, c = U[list(t)]
        det = float(np.dot(a, np.cross(b - a, c - a)))
        # Our unit vectors differ from geovor's by ulps: moving one corner by e moves det by
        # e times a side, so a sliver of sites on a great circle (det 1e-20 for sides of 1e-4
        # radians) cannot be judged below that.
        sides = np.linalg.norm(b - a) + np.linalg.norm(c - a) + np.linalg.norm(c - b)
        scale = max(1e-13 * np.linalg.norm(b - a) * np.linalg.norm(c - a), 2e-15 * sides) + 1e-30
        if kind == "proper" and det < -scale:
            bad.append(f"triangle {t} 'proper' but clockwise (det {det:.3g})")
        if kind == "great_circle" and abs(det) > 1e-12:
            bad.append(f"triangle {t} 'great_circle' but det {det:.3g}")
        if kind not in ("proper", "ghost", "great_circle"):
            bad.append(f"triangle {t}: kind {kind!r}")
        # ghost = 1 for the faces outside the hull's triangulation: ghosts, and great_circle
        # faces bounding a hull whose other sites are off their great circle (docs/user-guide.md)
        if kind == "great_circle" and collinear_all is None:
            pass  # all sites within rounding of one great circle: either answer
        elif bool(ghost) != (kind == "ghost" or (kind == "great_circle" and not collinear_all)):
            bad.append(f"triangle {t}: kind {kind} but ghost={ghost}")
        # written polygon areas
        rings = coords_of(gj)
        a_m2 = sum(geod_ring_area(cc) for cc, _ in rings)
        s_sr, perim, absterms = 0.0, 0.0, 0.0
        for cc, _ in rings:
            s, pp, tt = ring_sphere_terms(cc)
            s_sr += s
            perim += pp
            absterms += tt
        got, got_sr = float(props["area_m2"]), float(props["area_sr"])
        round_m2 = 0.0 if prec >= 17 else 2.0 * perim * math.radians(rerr) * math.sqrt(2) * R_MEAN ** 2
        if abs(got - a_m2) > max(1e-9 * abs(a_m2), 0.25) + round_m2:
            area_bad.append(f"{kind} {t}: area_m2 {got!r} vs written {a_m2!r} (rel {abs(got - a_m2) / max(a_m2, 1e-300):.3g})")
        if kind == "proper":
            exact = tri_sr_accurate(a, b, c)
            # Our unit vectors and geovor's are each within an ulp or two of the sites; moving a
            # corner by d moves the area by at most d x its opposite chord, which for a sliver (two
            # sites a metre apart, one far) is 1e-9 of the area (conditioning, not an error), and
            # by far more with a corner near the antipode of the others (tri_sr_gradient).
            chords = float(np.linalg.norm(b - a) + np.linalg.norm(c - b) + np.linalg.norm(a - c))
            cond = max(chords, tri_sr_gradient(a, b, c))
            if abs(got_sr - exact) > 1e-9 * abs(exact) + INPUT_ULPS * cond + 1e-18:
                sr_bad.append(f"proper {t}: area_sr {got_sr!r} vs spherical triangle {exact!r}")
            sum_m2 += got
            sum_sr += got_sr
            r_exp, r_tol = circumradius(a, b, c)
            if r_exp is not None:
                rgot = float(props.get("circumradius_m"))
                if abs(rgot - r_exp) > 1e-7 * r_exp + 1e-6 + r_tol:
                    cr_bad.append(f"{t}: circumradius_m {rgot!r} vs {r_exp!r} (conditioning {r_tol:.3g} m)")
        elif kind == "great_circle":
            sum_m2 += got
            sum_sr += got_sr
        if prec >= 5 and kind != "ghost":
            # a site within POLE_SNAP_M of a pole is drawn at the pole (docs/user-guide.md)
            snapped = max((d for d in (math.radians(90.0 - abs(sites[0][s_])) * R_MEAN for s_ in t) if d <= POLE_SNAP_M * 1.01), default=0.0)
            # and one within SNAP_RAD of the antimeridian on it (a site 1e-7 degree from it 6 km
            # from the north pole moved by 11 um: seed 3 case 41)
            for s_ in t:
                am = math.asin(min(1.0, abs(math.cos(math.radians(sites[0][s_])) * math.sin(math.radians(sites[1][s_])))))
                if abs(sites[1][s_]) > 90 and am <= SNAP_RAD * 1.01:
                    snapped = max(snapped, am * R_MEAN)
            tol = (2.0 * perim * math.radians(rerr) * math.sqrt(2) + 1e-14 * absterms + 1e-13 * abs(s_sr) + 1e-18 +
                   perim * snapped / R_MEAN)
            if abs(got_sr - s_sr) > tol and not (kind == "great_circle"):
                sr_bad.append(f"{kind} {t}: area_sr {got_sr!r} vs written polygon {s_sr!r} (tol {tol:.3g})")
        # the three sites are vertices of the written ring
        allc = np.array([p_ for cc, _ in rings for p_ in cc])
        for s in t:
            la, lo = sites[0][s], sites[1][s]
            dlat = np.abs(allc[:, 1] - la)
            dlon = np.abs((allc[:, 0] - lo + 180.0) % 360.0 - 180.0)
            polar = abs(la) > 89.99999 and np.any(np.abs(allc[:, 1]) == 90.0) and np.any(dlat < 1e-5)
            # geovor moves a site within SNAP_RAD of the antimeridian onto it (cell_geometry.hpp)
            to_cut = math.radians(180.0 - abs(lo)) * math.cos(math.radians(la))
            on_cut = (np.abs(allc[:, 0]) == 180.0) if to_cut <= SNAP_RAD * 1.01 else np.zeros(len(allc), bool)
            if not polar and not np.any((dlat <= rerr * 1.01 + 1e-12) & ((dlon <= rerr * 1.01 + 1e-12) | on_cut)):
                vert_bad.append(f"{kind} {t}: site {s} ({la!r},{lo!r}) not a vertex of its ring")
    case.check(not bad, cmd, f"triangles valid, well-formed (p={prec})", f"{len(bad)}: " + "; ".join(bad[:5]))
    case.check(not orient, cmd, "triangle exterior rings counter-clockwise", f"{len(orient)}: " + "; ".join(orient[:5]))
    # Empty triangles are allowed when geovor reported exactly that many on stderr.
    m = re.search(r"(\d+) triangle\(s\) written with an empty geometry", p.stderr)
    if m and int(m.group(1)) == reported_empty and len(empty) == reported_empty:
        case.notes.append(f"{cmd}: {reported_empty} triangles reported and written empty")
        empty = []
    case.check(not empty, cmd, "no EMPTY triangle of three distinct sites", f"{len(empty)}: " + "; ".join(empty[:5]))
    case.check(not area_bad, cmd, "triangle area_m2 = GeographicLib area of the written polygon", f"{len(area_bad)}: " + "; ".join(area_bad[:4]))
    case.check(not sr_bad, cmd, "triangle area_sr = spherical triangle", f"{len(sr_bad)}: " + "; ".join(sr_bad[:4]))
    case.check(not cr_bad, cmd, "circumradius_m", f"{len(cr_bad)}: " + "; ".join(cr_bad[:4]))
    case.check(not vert_bad, cmd, "triangle rings pass through their sites", f"{len(vert_bad)}: " + "; ".join(vert_bad[:4]))
    if not faces:
        return
    # convex hull of the unit vectors (brute force): closed oriented surface, every site behind every face
    directed = {}
    for t, kind, ghost in faces:
        for i in range(3):
            e = (t[i], t[(i + 1) % 3])
            directed[e] = directed.get(e, 0) + 1
    surf_bad = [f"edge {e} in {c} faces" for e, c in directed.items() if c != 1] + \
               [f"edge {e} has no reverse" for e in directed if (e[1], e[0]) not in directed]
    if n >= 3:
        case.check(not surf_bad, cmd, "triangles form a closed oriented surface", f"{len(surf_bad)}: " + "; ".join(surf_bad[:5]))
    hull_bad = []
    F = np.array([t for t, _, _ in faces])
    if n >= 4 and len(F):
        A, B, C = U[F[:, 0]], U[F[:, 1]], U[F[:, 2]]
        N = np.cross(B - A, C - A)
        for k0 in range(0, len(F), 256):
            Nk, Ak = N[k0:k0 + 256], A[k0:k0 + 256]
            val = Nk @ U.T - np.sum(Nk * Ak, axis=1)[:, None]       # > 0: site in front of the face
            Fk = F[k0:k0 + 256]
            lens = np.linalg.norm(B[k0:k0 + 256] - Ak, axis=1) * np.linalg.norm(C[k0:k0 + 256] - Ak, axis=1)
            sumlen = np.linalg.norm(B[k0:k0 + 256] - Ak, axis=1) + np.linalg.norm(C[k0:k0 + 256] - Ak, axis=1)
            tol = 1e-14 * (sumlen[:, None] * np.linalg.norm(U[None, :, :] - Ak[:, None, :], axis=2) + lens[:, None]) + 1e-300
            rows_ = np.arange(len(Fk))
            for j in range(3):
                val[rows_, Fk[:, j]] = -1.0
            viol = np.argwhere(val > tol)
            for fi, s in viol[:5]:
                hull_bad.append(f"site {s} in front of face {tuple(F[k0 + fi])} ({faces[k0 + fi][1]}): {val[fi, s]:.3g}")
            if len(hull_bad) > 5:
                break
        case.check(not hull_bad, cmd, "Delaunay: no site inside a triangle's circumcircle (convex hull of unit vectors)",
                   "; ".join(hull_bad[:5]))
    if reported_empty:
        case.notes.append(f"{cmd}: {reported_empty} triangles reported empty: area sums skipped")
    if ghosts == 0 and n >= 3 and not reported_empty and not any(k == "great_circle" for _, k, _ in faces):
        case.check(abs(sum_m2 - ELLIPSOID_AREA) <= 1e-9 * ELLIPSOID_AREA, cmd, "non-ghost triangles' area_m2 sum to the ellipsoid",
                   f"sum {sum_m2!r} (rel {abs(sum_m2 - ELLIPSOID_AREA) / ELLIPSOID_AREA:.3g})")
        case.check(abs(sum_sr - FOUR_PI) <= 1e-9 * FOUR_PI, cmd, "non-ghost triangles' area_sr sum to 4 pi", f"sum {sum_sr!r}")
    # edges
    sides = set()
    for t, _, _ in faces:
        for i in range(3):
            sides.add(frozenset((t[i], t[(i + 1) % 3])))
    e_bad, len_bad, hull_flag_bad = [], [], []
    epairs = []
    eset = set()
    for props, gj in edges:
        try:
            ab = (int(props["site_a"]), int(props["site_b"]))
        except (KeyError, TypeError, ValueError):
            e_bad.append(f"edge {props.get('edge_index')}: bad sites")
            continue
        if frozenset(ab) in eset:
            e_bad.append(f"edge {ab} written twice")
        eset.add(frozenset(ab))
        if (gj is None or not gj.get("coordinates")) and "edge(s) written with an empty geometry" not in p.stderr:
            e_bad.append(f"edge {ab} EMPTY geometry")
        epairs.append((ab, props))
    if faces and n >= 3:
        missing = sides - eset
        extra = eset - sides
        if missing or extra:
            e_bad.append(f"edges file differs from the triangles' sides: {len(missing)} missing, {len(extra)} extra")
    if epairs:
        ia = np.array([e[0][0] for e in epairs])
        ib = np.array([e[0][1] for e in epairs])
        ok_ = (ia >= 0) & (ia < n) & (ib >= 0) & (ib < n)
        ia, ib = ia[ok_], ib[ok_]
        ep = [e for e, o in zip(epairs, ok_) if o]
        ang = angle_between(U[ia], U[ib])
        _, _, gd = GEOD.inv(np.asarray(sites[1])[ia], np.asarray(sites[0])[ia],
                            np.asarray(sites[1])[ib], np.asarray(sites[0])[ib])
        for k, ((a_, b_), props) in enumerate(ep):
            lm, gm = float(props["length_m"]), float(props["geodesic_m"])
            if abs(lm - ang[k] * R_MEAN) > 1e-9 * lm + 1e-6:
                len_bad.append(f"edge {(a_, b_)}: length_m {lm!r} vs {ang[k] * R_MEAN!r}")
            if abs(gm - gd[k]) > 1e-9 * gm + 1e-6:
                len_bad.append(f"edge {(a_, b_)}: geodesic_m {gm!r} vs GeographicLib {gd[k]!r}")
        # hull flags: brute force: all other sites strictly on one side of the great circle through a, b
        Nab = np.cross(U[ia], U[ib])
        nn = np.linalg.norm(Nab, axis=1)
        for k0 in range(0, len(ep), 256):
            S = Nab[k0:k0 + 256] @ U.T
            tol = 1e-14 + 4e-16 * nn[k0:k0 + 256, None]
            for k in range(S.shape[0]):
                (a_, b_), props = ep[k0 + k]
                s = S[k].copy()
                s[[a_, b_]] = 0
                others = np.delete(s, [a_, b_]) if a_ != b_ else s
                if len(others) == 0:
                    continue
                pos, neg = np.any(others > tol[k]), np.any(others < -tol[k])
                amb = np.any(np.abs(others) <= tol[k])
                flag = int(props.get("hull", 0))
                if amb:
                    continue
                expected = 0 if (pos and neg) else 1
                if flag != expected:
                    hull_flag_bad.append(f"edge ({a_},{b_}) ids ({props.get('id_a')},{props.get('id_b')}): hull={flag}, brute force {expected}")
    case.check(not e_bad, cmd, "edges: well-formed, = the triangles' sides", "; ".join(e_bad[:5]))
    case.check(not len_bad, cmd, "edges: length_m and geodesic_m", f"{len(len_bad)}: " + "; ".join(len_bad[:4]))
    case.check(not hull_flag_bad, cmd, "edges: hull flag = brute-force convex hull edge",
               f"{len(hull_flag_bad)}: " + "; ".join(hull_flag_bad[:5]))
    # --no-ghosts
    tri2, edg2 = os.path.join(d, "tri_ng.geojson"), os.path.join(d, "edges_ng.geojson")
    p, cmd2 = case.run(geovor, ["delaunay", case.csv, "-o", tri2, "--edges", edg2, "--no-ghosts", "--overwrite", "-q"])
    if p is None:
        return
    t2 = read_features(tri2)
    e2 = read_features(edg2)

    def rot(t):
        k = t.index(min(t))
        return t[k:] + t[:k]
    proper_full = {rot(t) for t, kind, g in faces if not g}
    got2 = set()
    ng_bad = []
    for props, gj in t2:
        t = (int(props["site_a"]), int(props["site_b"]), int(props["site_c"]))
        if int(props.get("ghost", 0)):
            ng_bad.append(f"ghost triangle {t} written with --no-ghosts")
        got2.add(rot(t))
    if got2 != proper_full:
        ng_bad.append(f"--no-ghosts triangles differ from the full run's non-ghost ones: {len(got2 - proper_full)} extra, "
                      f"{len(proper_full - got2)} missing")
    psides = set()
    for t in got2:
        for i in range(3):
            psides.add(frozenset((t[i], t[(i + 1) % 3])))
    extra = []
    for props, gj in e2:
        ab = frozenset((int(props["site_a"]), int(props["site_b"])))
        if ab not in psides:
            extra.append(f"({props.get('id_a')},{props.get('id_b')}) hull={props.get('hull')}")
    if extra:
        ng_bad.append(f"{len(extra)} edges not sides of any written triangle: " + ", ".join(extra[:5]))
    case.check(not ng_bad, cmd2, "--no-ghosts: no ghost, only the proper triangles' edges", "; ".join(ng_bad[:4]))


# ---------------------------------------------------------------- relax checks
def _offsets(psi, lam, psi0, lam0):
    """Unit vectors at geocentric (psi, lam) minus the one at (psi0, lam0), by half-angle products:
    accurate to an ulp of the offset, not of 1, so both ends stay exactly on the sphere."""
    dl = (lam - lam0 + math.pi) % (2 * math.pi) - math.pi
    sl, cl = np.sin(dl / 2), lam0 + dl / 2
    dcos_l, dsin_l = -2.0 * np.sin(cl) * sl, 2.0 * np.cos(cl) * sl
    sp, cp = np.sin((psi - psi0) / 2), psi0 + (psi - psi0) / 2
    dcos_p, dsin_p = -2.0 * np.sin(cp) * sp, 2.0 * np.cos(cp) * sp
    c = np.cos(psi)
    return np.stack([c * dcos_l + math.cos(lam0) * dcos_p, c * dsin_l + math.sin(lam0) * dcos_p, dsin_p], axis=-1)


def spherical_centroid(gj):
    """Integral of x over the written polygon (unit sphere, geodesic edges) and half its perimeter.
    M = 1/2 sum over the edges (a, b) of (a x b) theta / sin(theta), written about the ring's first
    vertex c: a = c + d_a, and since the d_b - d_a sum to zero around a ring,
      M = 1/2 [sum (d_a x d_b) f + c x sum (d_b - d_a) (f - 1)],  f = theta / sin(theta).
    The offsets d come from the latitudes and longitudes by half-angle products, so no term is
    larger than the cell: the sum 1/2 sum theta n_e of unit normals cancelled to the mass of a small
    cell, and its centroid erred by ~ 1e-16 / size^2 radians (kilometres for a cell of a metre)."""
    M = np.zeros(3)
    S = 0.0
    for coords, _ in coords_of(gj):
        pts = []
        for (x1, y1), (x2, y2) in zip(coords[:-1], coords[1:]):
            pts.append((x1, y1))
            if x1 == x2 and abs(y2 - y1) > 10:  # long meridian sides: subdivide (antipodal ends)
                k = int(abs(y2 - y1) // 10) + 1
                for j in range(1, k):
                    pts.append((x1, y1 + (y2 - y1) * j / k))
        pts.append(coords[-1])
        c = np.array(pts, dtype=float)
        psi, lam = geocentric_lat(c[:, 1]), np.radians(c[:, 0])
        d = _offsets(psi, lam, psi[0], lam[0])
        c0 = np.array([math.cos(psi[0]) * math.cos(lam[0]), math.cos(psi[0]) * math.sin(lam[0]), math.sin(psi[0])])
        da, db = d[:-1], d[1:]
        e = db - da
        chord = np.minimum(np.linalg.norm(e, axis=1), 2.0)
        th = 2.0 * np.arcsin(chord / 2.0)
        small = th < 1e-3
        fm1 = np.where(small, th * th / 6.0 + 7.0 * th ** 4 / 360.0,
                       th / np.where(small, 1.0, np.sin(np.where(small, 1.0, th))) - 1.0)
        M += 0.5 * (np.sum(np.cross(da, db) * (1.0 + fm1)[:, None], axis=0) + np.cross(c0, np.sum(e * fm1[:, None], axis=0)))
        S += 0.5 * float(th.sum())
    return M, S


def check_relax(case, geovor, sites, cells17):
    d = case.dir
    n = len(sites[0])
    iters = 3
    prec = 17   # full precision: the rounding classes are the cells' checks; here byte identity and centroids
    outs = {}
    for mode in ("filtered", "naive", "rebuild"):
        c, s = os.path.join(d, f"relax_{mode}.geojson"), os.path.join(d, f"relax_{mode}_sites.geojson")
        p, cmd = case.run(geovor, ["relax", case.csv, "-o", c, "-n", str(iters), "--relocation", mode,
                                   "--sites-output", s, "--precision", str(prec), "--overwrite"])
        if p is None:
            return
        outs[mode] = (c, s, cmd, p.stderr)
    base = outs["filtered"]
    for mode in ("naive", "rebuild"):
        for k, what in ((0, "cells"), (1, "sites")):
            with open(base[k], "rb") as f1, open(outs[mode][k], "rb") as f2:
                same = f1.read() == f2.read()
            case.check(same, outs[mode][2], f"relax --relocation {mode} {what} byte-identical to filtered",
                       f"{base[k]} vs {outs[mode][k]}")
    # energy decreases
    en = []
    for ln in base[3].splitlines():
        f = ln.split()
        if len(f) >= 2 and f[0].isdigit():
            try:
                en.append(float(f[1]))
            except ValueError:
                pass
    inc = [(i, en[i], en[i + 1]) for i in range(len(en) - 1) if en[i + 1] > en[i] * (1 + 1e-12)]
    case.check(not inc, base[2], "relax energy decreases", f"energies {en}")
    sf = read_features(base[1])
    fin_lat = np.zeros(n)
    fin_lon = np.zeros(n)
    moved_bad = []
    U0 = unit_vectors(sites[0], sites[1])
    for props, gj in sf:
        si = int(props["site_index"])
        fin_lat[si], fin_lon[si] = float(props["lat_deg"]), float(props["lon_deg"])
        mv = float(angle_between(U0[si], unit_vectors([fin_lat[si]], [fin_lon[si]])[0])) * R_MEAN
        if abs(mv - float(props["moved_m"])) > 1e-9 * mv + 1e-6:
            moved_bad.append(f"site {si}: moved_m {props['moved_m']} vs {mv!r}")
    case.check(len(sf) == n and not moved_bad, base[2], "relax sites: one per site, moved_m", "; ".join(moved_bad[:4]) or f"{len(sf)} sites for {n}")
    feats = read_features(base[0])
    check_cells(case, feats, base[2], prec, 100.0, (fin_lat, fin_lon), None, {-1} if "empty geometry" in base[3] else set(), full=True)
    # one Lloyd step against our own centroids of the exact (precision 17) cells
    if cells17 is None or n < 2:
        return
    c1, s1 = os.path.join(d, "relax1.geojson"), os.path.join(d, "relax1_sites.geojson")
    p, cmd = case.run(geovor, ["relax", case.csv, "-o", c1, "-n", "1", "--sites-output", s1, "--overwrite", "-q"])
    if p is None:
        return
    bad = []
    U = unit_vectors(sites[0], sites[1])
    moved = read_features(s1)
    # where every site went: a centroid within the merge distance of another site's new position
    # (or old one, if it stayed) is refused, and that site stays (docs/user-guide.md)
    U1 = unit_vectors([float(pp["lat_deg"]) for pp, _ in moved], [float(pp["lon_deg"]) for pp, _ in moved])
    cents = {}
    for si, cell in cells17.items():
        M, S = spherical_centroid(cell)
        if np.linalg.norm(M) >= 1e-300:
            cents[si] = (M, S, M / np.linalg.norm(M))
    C = np.array([c for _, _, c in cents.values()]) if cents else np.zeros((0, 3))
    for props, gj in moved:
        si = int(props["site_index"])
        if si not in cents:
            continue
        M, S, cexp = cents[si]
        got = unit_vectors([float(props["lat_deg"])], [float(props["lon_deg"])])[0]
        err = float(angle_between(cexp, got))
        # the closed form cancels: conditioning S/|M|. And the written cell's boundary is off the
        # exact cell's (whose centroid relax takes) by up to moved_rad: that moves M across its
        # direction by at most perimeter (2 S) * moved_rad * (the largest sine of the angle from
        # the centroid to the boundary: r_max, bounded by the vertices' plus the longest side's)
        r_max = 0.0
        for coords, _ in coords_of(cells17[si]):
            V = unit_vectors([c[1] for c in coords], [c[0] for c in coords])
            ang = angle_between(V, np.broadcast_to(cexp, V.shape))
            side = angle_between(V[:-1], V[1:]) if len(V) > 1 else np.zeros(1)
            r_max = max(r_max, float(ang.max()) + float(side.max()))
        tol = 1e-9 + (3e-13 * S + 2.0 * 2.0 * S * moved_rad(None) * min(1.0, r_max)) / np.linalg.norm(M)
        if err > tol:
            # a centroid within the merge distance of another site stays: accept
            stays = float(angle_between(got, U[si])) < 1e-12
            near = MERGE_CHORD * 1.001 + 2 * tol
            near_other = (np.any(np.linalg.norm(U - cexp, axis=1) < near) or
                          np.any(np.linalg.norm(U1 - cexp, axis=1) < near) or
                          np.sum(np.linalg.norm(C - cexp, axis=1) < near) > 1)
            if not (stays and near_other):
                clat, clon = to_latlon(cexp[None])
                bad.append(f"site {si} ({props.get('site_id')}): relax -n 1 gives ({props['lat_deg']},{props['lon_deg']}), "
                           f"centroid of its cell ({float(clat[0])!r},{float(clon[0])!r}) ({err * R_MEAN:.3g} m off, tol {tol * R_MEAN:.3g} m)")
    case.check(not bad, cmd, "relax -n 1 moves every site to its cell's spherical centroid", f"{len(bad)}: " + "; ".join(bad[:4]))


# ---------------------------------------------------------------- one case
def run_case(args_tuple):
    seed, index, geovor, quick, tmp = args_tuple
    case = Case(seed, index, quick, tmp)
    t0 = time.time()
    try:
        run_case_body(case, geovor)
    except Exception:  # noqa: BLE001  a checker crash is a failure too, with its traceback
        case.failures.append(("(checker)", "oracle crashed", traceback.format_exc()[-2000:]))
    keep = bool(case.failures)
    if not keep:
        shutil.rmtree(case.dir, ignore_errors=True)
    return dict(label=case.label(), failures=case.failures, passed=case.passed, notes=case.notes,
                seconds=time.time() - t0, index=index)


def run_case_body(case, geovor):
    d = case.dir
    rng = case.rng
    precisions = sorted({17, int(rng.integers(1, 17)), int(rng.choice([5, 7, 9, 12]))})
    densify = 100.0 if rng.random() < 0.7 else float(rng.choice([10.0, 1000.0, 30.0]))
    report = os.path.join(d, "report.csv")
    results = {}
    for k, prec in enumerate(precisions):
        out = os.path.join(d, f"cells_p{prec}.geojson")
        args = ["cells", case.csv, "-o", out, "--precision", str(prec), "--overwrite", "--densify-m", repr(densify)]
        if k == 0:
            args += ["--report", report]
        p, cmd = case.run(geovor, args)
        if p is None:
            return
        results[prec] = (out, cmd, p.stderr)
    # accounting from the report
    rep = read_report(report)
    with open(case.csv) as f:
        rows = list(csv.DictReader(f))
    cmd0 = results[precisions[0]][1]
    bad = []
    if len(rep) != len(rows):
        bad.append(f"report has {len(rep)} rows for {len(rows)} input rows")
    site_rows = {}
    row_site = {}
    for r in rep:
        st = r.get("status")
        if st == "rejected":
            bad.append(f"valid row {r.get('id')} rejected: {r.get('detail')}")
            continue
        try:
            si = int(r["site_index"])
        except (KeyError, TypeError, ValueError):
            bad.append(f"row {r.get('id')}: site_index {r.get('site_index')!r}")
            continue
        row_site[r["id"]] = si
        if st == "site":
            if si in site_rows:
                bad.append(f"site {si} has two 'site' rows")
            site_rows[si] = int(r["row"]) - 1
        elif st != "merged":
            bad.append(f"row {r.get('id')}: status {st!r}")
    n = len(site_rows)
    if sorted(site_rows) != list(range(n)):
        bad.append(f"site indices not 0..{n - 1}")
    case.check(not bad, cmd0, "report: every row a site or merged, indices 0..n-1", "; ".join(bad[:5]))
    if bad:
        return
    lat = np.array([float(rows[site_rows[i]]["lat"]) for i in range(n)])
    lon = np.array([float(rows[site_rows[i]]["lon"]) for i in range(n)])
    sites = (lat, lon)
    # merge distance, independently: sites pairwise >= 2^-24 apart, merged rows within it of their site
    U = unit_vectors(lat, lon)
    mbad = []
    if 1 < n <= 3000:
        G = np.linalg.norm(U[:, None, :] - U[None, :, :], axis=2) if n <= 1000 else None
        if G is not None:
            np.fill_diagonal(G, np.inf)
            i, j = np.unravel_index(np.argmin(G), G.shape)
            if G[i, j] < MERGE_CHORD * (1 - 1e-6):
                mbad.append(f"sites {i} and {j} are {G[i, j] * R_MEAN:.4g} m apart (< merge distance {MERGE_M:.4g} m), not merged")
    for r in rep:
        if r.get("status") == "merged":
            k = int(r["row"]) - 1
            si = int(r["site_index"])
            u = unit_vectors([float(rows[k]["lat"])], [float(rows[k]["lon"])])[0]
            dist = float(np.min(np.linalg.norm(U - u, axis=1)))
            if dist >= MERGE_CHORD * (1 + 1e-6):
                mbad.append(f"row {r['id']} merged into site {si} but {dist * R_MEAN:.4g} m from every site")
    case.check(not mbad, cmd0, "merge distance 2^-24 R respected", "; ".join(mbad[:4]))
    cells17 = None
    area17 = {}
    for prec in sorted(precisions, reverse=True):
        out, cmd, err = results[prec]
        coll = collapsed_from_stderr(err) + [ln for ln in err.splitlines() if "empty geometry" in ln]
        feats = read_features(out)
        collapsed = set()
        if coll:
            collapsed = {-1}
            case.notes.append(f"{cmd}: stderr mentions collapse: {coll[:2]}")
        check_cells(case, feats, cmd, prec, densify, sites, row_site, collapsed, ref_area=area17)
        if prec == 17:
            area17 = {int(p_["site_index"]): sum(geod_ring_area(c) for c, _ in coords_of(gj)) for p_, gj in feats if gj}
            cells17 = {int(p["site_index"]): gj for p, gj in feats if gj}
            base17 = feats
    # binary outputs: GeoPackage and FlatGeobuf, same cells to the double
    for ext in ("gpkg", "fgb"):
        out = os.path.join(d, f"cells.{ext}")
        p, cmd = case.run(geovor, ["cells", case.csv, "-o", out, "--overwrite", "--densify-m", repr(densify)],
                          allow_error="FlatGeobuf cannot hold")
        if p is None:
            continue
        if p.returncode != 0:
            case.notes.append(f"{cmd}: refused (an empty cell, which FlatGeobuf cannot hold)")
            continue
        bin_collapsed = {-1} if "empty geometry" in p.stderr else set()
        feats = read_features(out)
        check_cells(case, feats, cmd, None, densify, sites, row_site, bin_collapsed, full=(ext == "gpkg"))
        # the same vertices as the precision-17 GeoJSON
        diffs = []
        g17 = {int(p_["site_index"]): gj for p_, gj in base17}
        for props, gj in feats:
            si = int(props["site_index"])
            a_ = [c for c, _ in coords_of(gj)] if gj else []
            b_ = [c for c, _ in coords_of(g17[si])] if g17.get(si) else []
            if len(a_) != len(b_) or any(len(x) != len(y) for x, y in zip(a_, b_)):
                diffs.append(f"site {si}: ring sizes {[len(x) for x in a_]} vs {[len(x) for x in b_]}")
                continue
            mx = max((max(abs(p1[0] - p2[0]), abs(p1[1] - p2[1])) for x, y in zip(a_, b_) for p1, p2 in zip(x, y)), default=0.0)
            if mx > 1e-12:
                diffs.append(f"site {si}: vertices differ by {mx:.3g} deg")
        case.check(not diffs, cmd, f"{ext} cells = precision-17 GeoJSON cells", "; ".join(diffs[:4]))
    if n >= 1:
        check_delaunay(case, geovor, sites, False)
    if n <= (60 if case.quick else 400):
        check_relax(case, geovor, sites, cells17)


# ---------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--geovor", required=True, help="the geovor executable (geovor-gdal beside it)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cases", type=int, default=None, help="cases to generate (default 48, --quick 14)")
    ap.add_argument("--first", type=int, default=0, help="index of the first case (to rerun one case)")
    ap.add_argument("--tmp", default=None, help="work folder (kept for failing cases)")
    ap.add_argument("--quick", action="store_true", help="smaller sites sets and fewer cases")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args()
    geovor = os.path.abspath(args.geovor)
    if not os.access(geovor, os.X_OK):
        print(f"oracle: {geovor} is not an executable", file=sys.stderr)
        print("oracle: 0 passed, 1 failed")
        return 1
    cases = args.cases if args.cases is not None else (14 if args.quick else 48)
    tmp = args.tmp or tempfile.mkdtemp(prefix="geovor-oracle-")
    os.makedirs(tmp, exist_ok=True)
    work = [(args.seed, i, geovor, args.quick, tmp) for i in range(args.first, args.first + cases)]
    t0 = time.time()
    if args.jobs > 1 and len(work) > 1:
        import multiprocessing
        with multiprocessing.Pool(args.jobs) as pool:
            results = pool.map(run_case, work, chunksize=1)
    else:
        results = [run_case(w) for w in work]
    passed = sum(r["passed"] for r in results)
    failed = 0
    for r in sorted(results, key=lambda r: r["index"]):
        for cmd, what, detail in r["failures"]:
            failed += 1
            print(f"FAIL {r['label']}\n  command: {cmd}\n  check:   {what}\n  detail:  {detail}\n")
        for note in r["notes"]:
            print(f"note {r['label']}: {note}")
    slow = max(results, key=lambda r: r["seconds"]) if results else None
    print(f"oracle: {len(results)} cases in {time.time() - t0:.1f} s (slowest {slow['seconds']:.1f} s: {slow['label']})"
          if slow else "oracle: no cases")
    if failed == 0 and args.tmp is None:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"oracle: {passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
