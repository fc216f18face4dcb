"""Beyond one machine: a real ``dask scheduler`` and two ``dask worker`` processes on loopback
run a sweep's chunks, and the result file equals the local run's, byte for byte. The sweep's
record files are deleted after it is loaded: the definition carries their contents to the
workers. Skipped when dask.distributed is not installed (the ``cluster`` extra)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("distributed")

from conftest import assert_same_result_file  # noqa: E402
from test_sweep import BASE  # noqa: E402

from pframe.sweep import load_sweep, run_sweep  # noqa: E402

SWEEP = """\
base: base.yaml
axes:
  - {name: record, path: excitation.file, values: [one.txt, two.txt]}
  - {name: gap, path: contacts.*.gap, linspace: [0.0, 0.02, 5], units: m}
chunk: 3
"""


@pytest.mark.slow
def test_dask_run_equals_local_run(tmp_path, cluster):
    t = np.arange(0, 1.6, 0.01)
    for name, scale in (("one.txt", 1.0), ("two.txt", 2.0)):
        np.savetxt(tmp_path / name, np.column_stack([t, scale * 9.81 * np.sin(2 * np.pi * t)]))
    (tmp_path / "base.yaml").write_text(BASE.replace(
        "excitation: {kind: sine, amplitude: 9.81, frequency: 6.283185307179586}",
        "excitation: {kind: record, file: one.txt}"), encoding="utf-8")
    (tmp_path / "sweep.yaml").write_text(SWEEP, encoding="utf-8")
    definition = load_sweep(tmp_path / "sweep.yaml")
    for name in ("one.txt", "two.txt"):
        (tmp_path / name).unlink()

    local = run_sweep(definition, tmp_path / "local.h5")
    remote = run_sweep(definition, tmp_path / "dask.h5", scheduler=cluster)
    assert local.completed and remote.completed
    assert remote.count == 10 and remote.chunks == 4
    assert_same_result_file(tmp_path / "dask.h5", tmp_path / "local.h5")

    import h5py

    with h5py.File(tmp_path / "dask.h5", "r") as f:
        force = f["peak_contact_force"][...]
        assert force.shape == (2, 5, 2)
        assert force[:, 0, 1].min() > 0 and force[1].max() > force[0].max()


@pytest.mark.slow
def test_unreachable_scheduler_is_an_input_error(tmp_path, monkeypatch):
    import socket

    from pframe.errors import InputError
    from pframe.sweep import cluster

    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", "2s")

    (tmp_path / "base.yaml").write_text(BASE, encoding="utf-8")
    (tmp_path / "sweep.yaml").write_text(
        "base: base.yaml\naxes: [{name: gap, path: contacts.*.gap, values: [0.01]}]\n",
        encoding="utf-8")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]  # free: nothing listens there once closed
    with pytest.raises(InputError, match="nothing listens at"):
        run_sweep(load_sweep(tmp_path / "sweep.yaml"), tmp_path / "x.h5",
                  scheduler=f"tcp://127.0.0.1:{port}")
