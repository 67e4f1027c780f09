"""geovor.Index.nearest vs scipy.spatial.cKDTree (on unit vectors, the same answers) and
sklearn.neighbors.BallTree(metric="haversine"), 2^20 sites, on a coherent query stream (a random
walk, as GPS tracks) and on uniform random queries, one thread each. Prints seconds and ratios
(targets: at least 2x cKDTree on coherent streams, not slower on random ones).

Usage: python bench/python/nearest_vs_kdtree.py [log2_sites] [log2_queries]   (default: 20 20)
"""
import sys
import time

import numpy as np
from scipy.spatial import cKDTree
from sklearn.neighbors import BallTree

import geovor


def unit(lat, lon):
    """Geocentric directions of WGS84 positions, as geovor's sites: the same nearest site."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    la, lo = np.radians(lat), np.radians(lon)
    n = a / np.sqrt(1 - e2 * np.sin(la) ** 2)
    xyz = np.column_stack([n * np.cos(la) * np.cos(lo), n * np.cos(la) * np.sin(lo), n * (1 - e2) * np.sin(la)])
    return xyz / np.linalg.norm(xyz, axis=1)[:, None]


def timed(fn):
    start = time.perf_counter()
    out = fn()
    return time.perf_counter() - start, out


def main():
    ns = 2 ** (int(sys.argv[1]) if len(sys.argv) > 1 else 20)
    nq = 2 ** (int(sys.argv[2]) if len(sys.argv) > 2 else 20)
    rng = np.random.default_rng(1)
    slat = np.degrees(np.arcsin(rng.uniform(-1, 1, ns)))
    slon = rng.uniform(-180, 180, ns)
    step = np.degrees(np.sqrt(4 * np.pi / ns)) / 4  # a quarter of the site spacing per query
    streams = {
        "coherent": (np.clip(20 + np.cumsum(rng.normal(0, step, nq)), -89, 89),
                     (np.cumsum(rng.normal(0, step, nq)) + 180) % 360 - 180),
        "random": (np.degrees(np.arcsin(rng.uniform(-1, 1, nq))), rng.uniform(-180, 180, nq)),
    }
    t_index, index = timed(lambda: geovor.Index(slat, slon))
    t_kd, kd = timed(lambda: cKDTree(unit(slat, slon)))
    t_ball, ball = timed(lambda: BallTree(np.radians(np.column_stack([slat, slon])), metric="haversine"))
    print(f"{ns} sites, {nq} queries; build: geovor {t_index:.2f} s, cKDTree {t_kd:.2f} s, BallTree {t_ball:.2f} s")
    print(f"{'stream':>9} {'geovor s':>9} {'cKDTree s':>10} {'BallTree s':>11} {'vs kd':>6} {'vs ball':>8}  agree")
    for name, (qlat, qlon) in streams.items():
        index.nearest(qlat[:1000], qlon[:1000], threads=1)  # warm up
        t_ours, (site, _) = timed(lambda: index.nearest(qlat, qlon, threads=1))
        q = unit(qlat, qlon)
        t_kdq, (_, kd_site) = timed(lambda: kd.query(q, workers=1))
        t_ballq, _ = timed(lambda: ball.query(np.radians(np.column_stack([qlat, qlon])), k=1))
        # The chord order is the great-circle order: the same sites but for exact ties.
        agree = np.mean(site == kd_site)
        print(f"{name:>9} {t_ours:>9.3f} {t_kdq:>10.3f} {t_ballq:>11.3f} {t_kdq / t_ours:>5.1f}x "
              f"{t_ballq / t_ours:>7.1f}x  {agree:.4f}", flush=True)


if __name__ == "__main__":
    main()
