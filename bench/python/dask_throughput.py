"""geovor.dask.nearest throughput on a dask.distributed LocalCluster with 1 and 2 worker processes
(one thread each), 2^18 sites and 2^22 coherent queries in 16 partitions. Prints queries per
second and the 2-worker speed-up (bounded by the cores this machine has).

Usage: python bench/python/dask_throughput.py [log2_queries]   (default: 22)
"""
import os
import sys
import tempfile
import time

import dask.dataframe as dd
import distributed
import numpy as np
import pandas as pd

import geovor
import geovor.dask


def main():
    nq = 2 ** (int(sys.argv[1]) if len(sys.argv) > 1 else 22)
    rng = np.random.default_rng(2)
    ns = 2**18
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "sites.gvi")
        geovor.Index(np.degrees(np.arcsin(rng.uniform(-1, 1, ns))), rng.uniform(-180, 180, ns)).save(path)
        queries = pd.DataFrame({"lat": np.clip(np.cumsum(rng.normal(0, 0.01, nq)), -89, 89),
                                "lon": (np.cumsum(rng.normal(0, 0.01, nq)) + 180) % 360 - 180})
        rates = {}
        for workers in (1, 2):
            with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                          dashboard_address=None) as cluster, distributed.Client(cluster) as client:
                ddf = dd.from_pandas(queries, npartitions=16).persist()
                distributed.wait(ddf)
                client.run(lambda p: geovor.dask._load(p) and None, path)  # every worker loads the index first
                start = time.perf_counter()
                n = len(geovor.dask.nearest(ddf, path).compute())
                rates[workers] = n / (time.perf_counter() - start)
            print(f"{workers} worker(s): {rates[workers] / 1e6:.2f} M queries/s", flush=True)
        print(f"2 workers / 1: {rates[2] / rates[1]:.2f}x on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()
