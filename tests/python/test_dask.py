"""`locate` spread with Dask over a two-worker `distributed.LocalCluster` (loopback only) answers exactly
what the in-process call answers."""

import pandas as pd
import pytest

import sweetspot

import dask.dataframe as dd
import distributed


def test_locate_on_two_dask_workers_equals_the_in_process_call(repo):
    one = pd.read_csv(repo / "tests/data/statcast_search.csv")
    # Four copies, so each of the two partitions holds swings of every kind (located, not measured).
    savant = pd.concat([one] * 4, ignore_index=True)
    expected = sweetspot.locate(savant)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster, distributed.Client(cluster):
        frame = dd.from_pandas(savant, npartitions=2)
        assert frame.npartitions == 2
        located = frame.map_partitions(sweetspot.locate, meta=sweetspot.locate_meta()).compute()
    located.attrs, expected.attrs = {}, {}
    assert len(expected) == 12  # three of the five rows are swings
    pd.testing.assert_frame_equal(located, expected, check_exact=True)
