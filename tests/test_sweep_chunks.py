"""Finished chunks kept beside a sweep's output carry their index and their sweep's digest: a
file put under another chunk's name (another index's valid chunk, another sweep's chunk) is
never merged into the result: it is removed with a note and its chunk runs again, so the
resumed file equals an uninterrupted run's."""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from pframe.sweep import load_sweep, run_sweep

SCENE = """\
buildings:
  - {name: A, floors: 1, mass: 1000.0, story: {material: elastic, stiffness: 1.0e6}}
  - {name: B, floors: 1, mass: 1000.0, story: {material: elastic, stiffness: 4.0e6}}
contacts:
  - {nodes: [A/1, B/1], gap: 0.01, law: linear, stiffness: 1.0e7}
excitation: {kind: sine, amplitude: 3.0, frequency: 6.0}
analysis: {dt: 0.002, duration: 0.5}
"""


def _sweep(folder, values, name="sweep.yaml"):
    (folder / "scene.yaml").write_text(SCENE, encoding="utf-8")
    (folder / name).write_text(
        "base: scene.yaml\naxes:\n  - {name: gap, path: contacts.*.gap, values: "
        f"{list(values)}}}\nchunk: 1\n", encoding="utf-8")
    return load_sweep(folder / name)


def _stopped_after(definition, out, chunks: int) -> None:
    """Run the sweep on one thread and stop it once ``chunks`` chunks are saved."""
    def stop(done, total, failed):
        if done >= chunks:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(definition, out, threads=1, progress=stop)


def _peaks(path):
    import h5py

    with h5py.File(path, "r") as f:
        return f["peak_displacement"][...]


@pytest.mark.slow
@pytest.mark.parametrize("intruder", ["another index", "another sweep"])
def test_a_misplaced_chunk_is_not_merged(tmp_path, capfd, intruder):
    definition = _sweep(tmp_path, [0.0, 0.01, 0.05])
    whole = tmp_path / "whole.h5"
    run_sweep(definition, whole, threads=1)
    out = tmp_path / "resumed.h5"
    _stopped_after(definition, out, 2)
    parts = tmp_path / "resumed.h5.parts"
    assert (parts / "chunk-00001.npz").exists()
    if intruder == "another index":
        source = parts / "chunk-00000.npz"
    else:  # the same chunk of a sweep of other gaps
        other = _sweep(tmp_path, [0.2, 0.3, 0.4], "other.yaml")
        _stopped_after(other, tmp_path / "other.h5", 2)
        source = tmp_path / "other.h5.parts" / "chunk-00001.npz"
    shutil.copyfile(source, parts / "chunk-00001.npz")
    capfd.readouterr()
    run_sweep(definition, out, threads=1)
    err = capfd.readouterr().err
    expected = ("holds chunk 0, not chunk 1" if intruder == "another index"
                else "holds a chunk of another sweep")
    assert "chunk-00001.npz" in err and expected in err and "runs again" in err
    assert np.array_equal(_peaks(out), _peaks(whole))
    assert not parts.exists()
