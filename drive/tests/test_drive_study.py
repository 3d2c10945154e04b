"""Sweeps run through the standard executor interface: the same cases give the same numbers
serially, in the default process pool, and on a Dask distributed cluster (a local one here)."""

import distributed

from mdfqm_drive.modulator import IpSettings
from mdfqm_drive.study import Case, run_case, sweep

CASES = [
    Case("hurst_x5", 200, IpSettings(period=2400, osr=4, dead=96, mode="mdfqm", adc_offset=1256),
         settle=0.01, window=0.02),
    Case("hurst", 100, IpSettings(period=9600, osr=1, dead=96, mode="svpwm", bits=8,
                                  adc_offset=19), load="const", load_fraction=0.5,
         settle=0.01, window=0.02),
]


def numbers(result):
    return {k: v for k, v in result.items() if isinstance(v, (int, float))
            and k != "cpu_s"}


def test_the_process_pool_and_a_dask_cluster_give_the_serial_numbers():
    serial = [numbers(run_case(c)) for c in CASES]
    assert all(s["events_per_s"] > 0 for s in serial)
    pooled = [numbers(r) for r in sweep(CASES)]
    assert pooled == serial
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        on_cluster = [numbers(r) for r in sweep(CASES, client.get_executor())]
    assert on_cluster == serial
