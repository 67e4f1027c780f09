"""geovor.SphericalVoronoi vs scipy.spatial.SphericalVoronoi: construction plus areas, uniform
random points, in one run. Prints seconds and the ratio (target: at least 20x at 2^20).

Usage: python bench/python/spherical_voronoi_vs_scipy.py [log2_n ...]   (default: 16 20)
"""
import sys
import time

import numpy as np
from scipy.spatial import SphericalVoronoi as ScipyVoronoi

import geovor


def best_of(fn, repeat):
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def main():
    exponents = [int(a) for a in sys.argv[1:]] or [16, 20]
    print(f"{'n':>9} {'scipy s':>9} {'geovor s':>9} {'ratio':>7}  (construction + calculate_areas, best of runs)")
    for e in exponents:
        rng = np.random.default_rng(e)
        p = rng.normal(size=(2**e, 3))
        p /= np.linalg.norm(p, axis=1)[:, None]
        repeat = 3 if e <= 16 else 1
        # scipy's threshold (1e-6) also flags pairs of random points closer than that as duplicates.
        t_scipy = best_of(lambda: ScipyVoronoi(p, threshold=1e-10).calculate_areas(), repeat)
        t_ours = best_of(lambda: geovor.SphericalVoronoi(p).calculate_areas(), repeat)
        print(f"{2**e:>9} {t_scipy:>9.3f} {t_ours:>9.3f} {t_scipy / t_ours:>6.1f}x", flush=True)


if __name__ == "__main__":
    main()
