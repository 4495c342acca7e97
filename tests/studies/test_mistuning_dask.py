"""The mistuning study on a real dask.distributed scheduler (harness/studies/mistuning_dask.py):
a LocalCluster of 2 worker processes, one killed (SIGKILL) while it computes a sweep. The study
completes with every record, the lost sweep is started again on the other worker, and the numbers
equal the in-process run's to the last bit; a rerun on the cluster computes nothing."""

from __future__ import annotations

import numpy as np
import pytest

from harness.analysis.executor import Runner
from harness.studies import mistuning, mistuning_dask
from harness.studies.mistuning import Study

# 5 sweeps of 3 blades over the band, about 1 s each: long enough to be killed inside one
SMALL = Study(n=3, levels=(0.05,), patterns=4, points=3, variants=("friction",))


@pytest.mark.slow  # 22 s: a dask cluster with a killed worker
def test_a_killed_worker_loses_one_sweep_and_the_study_completes(tmp_path):
    k = mistuning_dask.killed(SMALL, tmp_path / "cache", wait_s=300)
    assert k["completed"] and k["records"] == k["sweeps"] == 5
    assert k["lost"] in k["started_twice"]  # the sweep the killed worker was in ran again elsewhere
    with Runner(workers=1, progress=False) as r:
        ref = mistuning.run_study(SMALL, r, None)
    assert np.array_equal(k["amplification"], ref["variants"]["friction"]["amplification"], equal_nan=True)

    lc, client = mistuning_dask.cluster(1)  # the same study again: every sweep from the cache
    try:
        with Runner(scheduler=client, progress=False) as r:
            again = mistuning.run_study(SMALL, r, tmp_path / "cache")
    finally:
        client.close()
        lc.close()
    assert again["computed"] == 0 and again["cached"] == 5
