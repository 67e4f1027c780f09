"""geovor.dask.nearest on a dask.distributed LocalCluster of 2 worker processes: the same answers
as one process, the index loaded once per worker."""
import numpy as np
import pandas as pd
import pytest

import geovor
import geovor.dask

dd = pytest.importorskip("dask.dataframe")
distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def index_path(tmp_path_factory):
    rng = np.random.default_rng(11)
    lat = np.degrees(np.arcsin(rng.uniform(-1, 1, 3000)))
    lon = rng.uniform(-180, 180, 3000)
    path = tmp_path_factory.mktemp("index") / "sites.gvi"
    geovor.Index(lat, lon, ids=[f"st{i}" for i in range(3000)]).save(path)
    return path


def query_frame(n, seed):
    rng = np.random.default_rng(seed)
    return pd.DataFrame({
        "trip": np.arange(n),
        "pickup_latitude": np.clip(40 + np.cumsum(rng.normal(0, 0.3, n)), -90, 90),
        "pickup_longitude": ((np.cumsum(rng.normal(0, 0.3, n)) - 74 + 180) % 360) - 180,
    })


def test_cluster_matches_one_process(index_path):
    queries = query_frame(20000, 12)
    expected = geovor.dask.nearest_frame(queries, geovor.Index.load(index_path), lat="pickup_latitude",
                                         lon="pickup_longitude", site_columns=("id", "lat"))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        ddf = dd.from_pandas(queries, npartitions=8)
        joined = geovor.dask.nearest(ddf, index_path, lat="pickup_latitude", lon="pickup_longitude",
                                     site_columns=("id", "lat"))
        assert list(joined.columns) == ["trip", "pickup_latitude", "pickup_longitude", "site_index", "distance_m",
                                        "site_id", "site_lat"]
        result = joined.compute()
        # Both worker processes took part, each loading the index at most once.
        loads = client.run(lambda: len(geovor.dask._cache))
        assert len(loads) == 2 and all(v <= 1 for v in loads.values())
    pd.testing.assert_frame_equal(result.sort_values("trip").reset_index(drop=True),
                                  expected.reset_index(drop=True))
    # The joined site attributes are those of the site found (Index's tests check it is the nearest).
    sites = geovor.Index.load(index_path).sites()
    assert (result["site_id"].to_numpy() == sites["id"].to_numpy()[result["site_index"].to_numpy()]).all()
    assert (result["site_id"] == "st" + result["site_index"].astype(str)).all()


def test_k_nearest_and_radius_in_pandas(index_path):
    queries = query_frame(300, 13)
    index = geovor.Index.load(index_path)
    out = geovor.dask.nearest_frame(queries, index, lat="pickup_latitude", lon="pickup_longitude", k=3,
                                    max_distance_m=150e3)
    assert len(out) == 900 and out["rank"].tolist()[:3] == [1, 2, 3]
    far = out["site_index"] < 0
    assert np.all(np.isinf(out.loc[far, "distance_m"])) and out.loc[far, "site_id"].isna().all()
    assert np.all(out.loc[~far, "distance_m"] <= 150e3)
    with pytest.raises(ValueError, match="already has"):
        geovor.dask.nearest_frame(out, index, lat="pickup_latitude", lon="pickup_longitude")
    with pytest.raises(ValueError, match="not in the index"):
        geovor.dask.nearest_frame(queries, index, lat="pickup_latitude", lon="pickup_longitude",
                                  site_columns=("elevation",))
