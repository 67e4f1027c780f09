#!/usr/bin/env python3
"""Query points for bench/serve/run.sh: N points uniform on the sphere (uniform in area), fixed seed.

Usage: make_points.py N SEED OUT.csv
Writes a CSV with the header lat,lon and one point a line, each coordinate written with repr()
(the shortest text that reads back as the same double), so every service parses the same doubles.
"""
import sys

import numpy as np


def main() -> None:
    n, seed, out = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    rng = np.random.default_rng(seed)
    # Uniform in area: z uniform in [-1, 1] (Archimedes), longitude uniform.
    z = rng.uniform(-1.0, 1.0, n)
    lat = np.degrees(np.arcsin(z))
    lon = rng.uniform(-180.0, 180.0, n)
    with open(out, "w") as f:
        f.write("lat,lon\n")
        f.writelines(f"{a!r},{o!r}\n" for a, o in zip(lat.tolist(), lon.tolist()))


if __name__ == "__main__":
    main()
