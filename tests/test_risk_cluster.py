"""A risk study's batches on a real Dask cluster (a scheduler and two workers on loopback,
as tests/test_sweep_cluster.py): the file equals the local run's; a stopped study resumed
on the cluster runs only the missing batches. Skipped without dask.distributed (the
``cluster`` extra)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("distributed")

from test_risk import pulse_study  # noqa: E402

from pframe.errors import InputError  # noqa: E402


@pytest.mark.slow
def test_a_study_on_dask_equals_the_local_run_and_resumes(tmp_path, cluster):
    import warnings

    import xarray as xr

    from pframe.risk import risk

    study = pulse_study(tmp_path, chunk=3, uncertain={
        "gap": {"distribution": "lognormal", "median": 0.12, "dispersion": 0.2}})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        risk(study, output=tmp_path / "local.nc", threads=1)

        def stop(done, total):
            raise KeyboardInterrupt

        with pytest.raises(KeyboardInterrupt):
            risk(study, output=tmp_path / "dask.nc", progress=stop, threads=1)
        seen = []
        risk(study, output=tmp_path / "dask.nc", scheduler=cluster,
             progress=lambda done, total: seen.append(done))
    assert len(seen) == 2  # batches 1 and 2 of 3 ran on the cluster; batch 0 was kept
    local, remote = xr.open_dataset(tmp_path / "local.nc"), xr.open_dataset(tmp_path / "dask.nc")
    for name in ("critical_gap", "peak_story_drift", "impact_count", "fragility_median"):
        assert np.array_equal(local[name].values, remote[name].values, equal_nan=True), name


def test_hunt_and_subset_refuse_a_scheduler(tmp_path):
    from pframe.risk import risk

    study = pulse_study(tmp_path, design={"kind": "ida", "hunt": {"start": 0.1, "step": 0.1},
                                          "resolution": 0.05})
    with pytest.raises(InputError, match="hunt and fill"):
        risk(study, scheduler="tcp://127.0.0.1:1")
