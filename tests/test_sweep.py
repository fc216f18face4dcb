"""Sweeps: a batch of variants equals the variants run one by one, the result file is a labelled
N-D array, a failing variant spoils nothing else, and bad sweep files are refused with the
line, axis and value at fault.

Every sweep here runs the laws of models/wu2021-eq14.yaml (bilinear storeys, improved Kelvin
contacts) with the sweeps' default envelopes, so they share one kernel (compiled once);
the histories test records what tests/conftest.py's RECORDERS do, which shares that kernel.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import re
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
import yaml
from conftest import WU2021, runnable_model

import pframe
from pframe.assemble import assemble
from pframe.cli import main
from pframe.errors import InputError
from pframe.kernel import simulate
from pframe.model.load import _compose
from pframe.reader import parse_scene
from pframe.sweep import load_sweep, parse, parse_sweep, run_sweep
from pframe.sweep.variants import load_variant

REPO = Path(__file__).resolve().parents[1]

#: 2 + 2 floors, 7,500 steps; GAP and RESTITUTION are what the sweeps vary
BASE = """\
title: sweep test scene
buildings:
  - {name: A, floors: 2, mass: 250.0,
     story: {material: bilinear, stiffness: 197392.088, yield_drift: 0.0248, alpha: 0.1}}
  - {name: B, floors: 2, mass: [1000.0, 800.0],
     story: {material: bilinear, stiffness: 1973920.88, yield_drift: 0.0149, alpha: 0.1}}
contacts:
  - {name: floor-1, nodes: [A/1, B/1], gap: 0.01, law: improved_kelvin, stiffness: 2.0e+7,
     restitution: 0.4}
  - {name: floor-2, nodes: [A/2, B/2], gap: 0.01, law: improved_kelvin, stiffness: 2.0e+7,
     restitution: 0.6}
damping: {ratio: 0.05, modes: [1, 2]}
excitation: {kind: sine, amplitude: 9.81, frequency: 6.283185307179586}
analysis:
  integrator: {type: newmark, gamma: 0.5, beta: 0.25}
  dt: 2.0e-4
  duration: 1.5
"""

#: gap x restitution, 3 x 2 variants in chunks of 4 and 2
GRID = """\
base: base.yaml
axes:
  - {name: gap, path: contacts.*.gap, values: [0.0, 0.004, 0.02], units: m}
  - {name: restitution, path: contacts.floor-2.restitution, linspace: [0.4, 0.8, 2]}
chunk: 4
"""


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    path = tmp_path_factory.mktemp("sweep")
    (path / "base.yaml").write_text(BASE, encoding="utf-8")
    (path / "grid.yaml").write_text(GRID, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def grid(folder):
    out = folder / "grid.h5"
    assert main(["sweep", str(folder / "grid.yaml"), "-o", str(out), "-q"]) == 0
    return out


def _single(definition, index: int, recorders=None):
    """Variant ``index`` as its own scene: the text ``pframe sweep --variant`` prints, parsed
    by the scene loader, assembled alone and run (with the scene's recorders, or these)."""
    from pframe.sweep.variants import materialise, steps_override, variant_data

    spec = parse(definition)
    paths = {key: path for _, _, key, path in definition.records}
    steps = steps_override(spec, index, materialise(definition))
    text = yaml.safe_dump(variant_data(spec, index, record_path=lambda key: paths[key],
                                       steps=steps))
    expanded = parse_scene(text, base_dir=definition.base_dir).expanded
    if recorders is not None:
        expanded = dataclasses.replace(expanded, recorders=recorders)
    plan = assemble(expanded)
    return plan, simulate(plan)


@pytest.mark.slow
def test_sweep_file_is_a_labelled_array(grid):
    pytest.importorskip("xarray")
    with pframe.open(grid) as ds:
        assert ds.peak_contact_force.dims == ("gap", "restitution", "contact")
        assert ds.peak_displacement.dims == ("gap", "restitution", "node")
        assert ds.ductility.dims == ("gap", "restitution", "story")
        assert list(ds.gap.values) == [0.0, 0.004, 0.02]
        assert list(ds.restitution.values) == [0.4, 0.8]
        assert ds.gap.attrs["units"] == "m"
        assert list(ds.contact_name.values) == ["floor-1", "floor-2"]
        assert list(ds.node_name.values) == ["A/1", "A/2", "B/1", "B/2"]
        assert ds.peak_contact_force.attrs["units"] == "N"
        assert ds.attrs["sweep_axes"] == "gap restitution"
        assert ds.attrs["variants"] == 6 and ds.attrs["variants_failed"] == 0
        assert (ds.complete == 1).all() and (ds.status == "completed").all()
        assert (ds.steps_completed == 7500).all()
        assert float(ds.energy_balance_error.max()) < 1e-8
        force = ds.peak_contact_force.sel(contact_name="floor-2")
        assert float(force.sel(gap=0.0).min()) > 0  # floor-2 pounds with the gap closed
        assert float(ds.peak_contact_force.sel(gap=0.02).max()) == 0.0
        assert int(ds.impact_count.sel(gap=0.0).sum()) > int(ds.impact_count.sel(gap=0.004).sum())
        # floor-2's restitution changes what happens after its first impact
        assert not np.allclose(ds.peak_displacement.sel(gap=0.0, restitution=0.4),
                               ds.peak_displacement.sel(gap=0.0, restitution=0.8), rtol=1e-6)
        ductility = ds.ductility.values
        drift = ds.peak_story_drift.values
        assert np.allclose(ductility[..., :2], drift[..., :2] / 0.0248, rtol=1e-12)
        assert np.allclose(ductility[..., 2:], drift[..., 2:] / 0.0149, rtol=1e-12)


def test_batch_equals_single_runs(folder, grid):
    """Each variant of the sweep file holds, bit for bit, what its own scene gives when loaded
    from text and run alone (a batch of one): the sweep's batching, chunking, threading and
    data road through the loader change no number."""
    definition = load_sweep(folder / "grid.yaml")
    spec = parse(definition)
    with h5py.File(grid, "r") as f:
        for index in range(spec.count):
            position = np.unravel_index(index, spec.shape)
            plan, single = _single(definition, index)
            assert single.completed(0)
            dof = plan.node_dof
            assert np.array_equal(f["peak_displacement"][position],
                                  single.envelope["displacement"][0][dof])
            assert np.array_equal(f["peak_story_drift"][position],
                                  single.envelope["story_drift"][0])
            assert np.array_equal(f["peak_contact_force"][position],
                                  single.envelope["contact_force"][0])
            assert np.array_equal(f["impact_count"][position], single.impacts[0])
            assert f["newton_solves"][position] == single.iterations[0]
            assert f["energy_balance_error"][position] == single.energy_error(0)


@pytest.mark.slow
def test_variant_road_equals_the_scene_loader(tmp_path):
    """The sweep validates variants from YAML data composed once; for every shipped model it
    gives the scene pframe.reader.parse_scene gives from the text."""
    for model in sorted((REPO / "models").glob("*.yaml")):
        folder = tmp_path / model.stem
        folder.mkdir()
        try:
            model = runnable_model(model, folder)
        except pytest.skip.Exception:  # its record is not on this machine
            continue
        text = model.read_text(encoding="utf-8")
        data, lines = _compose(text, str(model))
        mine = load_variant(copy.deepcopy(data), lines, str(model), model.parent)
        theirs = parse_scene(text, str(model), model.parent)
        assert mine.scene == theirs.scene, model.name
        a, b = mine.expanded, theirs.expanded
        for field in a.__dataclass_fields__:
            assert _same(getattr(a, field), getattr(b, field)), (model.name, field)


def _same(x, y):
    """Equal to the bit (NaN where NaN), looking into the containers and dataclasses (a
    support's motion holds arrays) that == cannot compare whole."""
    if isinstance(x, np.ndarray):
        return (isinstance(y, np.ndarray)
                and np.array_equal(x, y, equal_nan=x.dtype.kind == "f"))
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return type(x) is type(y) and all(
            _same(getattr(x, f.name), getattr(y, f.name)) for f in dataclasses.fields(x))
    if isinstance(x, dict):
        return (isinstance(y, dict) and x.keys() == y.keys()
                and all(_same(x[k], y[k]) for k in x))
    if isinstance(x, (list, tuple)):
        return (type(x) is type(y) and len(x) == len(y)
                and all(_same(u, v) for u, v in zip(x, y)))
    if isinstance(x, float) and isinstance(y, float):
        return x == y or (math.isnan(x) and math.isnan(y))
    return x == y


@pytest.mark.slow
def test_a_failing_variant_does_not_spoil_its_chunk(folder, tmp_path):
    """Newmark linear acceleration is stable only below dt = sqrt(12) / w_max: the variant with
    a very stiff building B diverges and is marked failed with its reason; the other variants of
    its chunk complete with the numbers of their own runs. The command exits with 1."""
    (tmp_path / "base.yaml").write_text(
        BASE.replace("beta: 0.25", "beta: 0.16666666666666666"), encoding="utf-8")
    (tmp_path / "fail.yaml").write_text(
        "base: base.yaml\n"
        "axes:\n"
        "  - {name: stiffness, path: buildings.B.story.stiffness,\n"
        "     values: [1973920.88, 1.0e+12, 3.0e+6]}\n", encoding="utf-8")
    out = tmp_path / "fail.h5"
    assert main(["sweep", str(tmp_path / "fail.yaml"), "-o", str(out), "-q"]) == 1
    definition = load_sweep(tmp_path / "fail.yaml")
    with h5py.File(out, "r") as f:
        assert f["complete"][...].tolist() == [1, 0, 1]
        status = [b"".join(row).decode() for row in f["status"][...]]  # char arrays
        assert status[0] == status[2] == "completed"
        assert "diverged" in status[1] and "step" in status[1]
        assert 0 < f["steps_completed"][1] < 7500
        assert f.attrs["variants_failed"] == 1
        for index in (0, 2):
            plan, single = _single(definition, index)
            assert np.array_equal(f["peak_displacement"][index],
                                  single.envelope["displacement"][0][plan.node_dof])
            assert np.array_equal(f["impact_count"][index], single.impacts[0])


@pytest.mark.slow
def test_histories_when_asked(folder):
    """keep.histories adds (axes, time, entity) variables at the stride asked."""
    text = (GRID.replace("chunk: 4", "chunk: 3")
            + "keep:\n  histories: [displacement, velocity, story_force, story_drift, "
              "contact_force]\n  every: 10\n")
    (folder / "histories.yaml").write_text(text, encoding="utf-8")
    out = folder / "histories.h5"
    definition = load_sweep(folder / "histories.yaml")
    run = run_sweep(definition, out)
    assert run.completed
    with h5py.File(out, "r") as f:
        assert f["displacement"].shape == (3, 2, 751, 4)
        assert f["contact_force"].shape == (3, 2, 751, 2)
        assert f["t"][1] == pytest.approx(10 * 2.0e-4)
        plan, single = _single(definition, 5, parse(definition).recorders)
        assert np.array_equal(f["displacement"][2, 1],
                              single.history["displacement"][0][:, plan.node_dof])
        assert np.array_equal(f["contact_force"][2, 1], single.history["contact_force"][0])
        assert np.array_equal(f["peak_displacement"][2, 1],
                              single.envelope["displacement"][0][plan.node_dof])


@pytest.mark.slow
def test_zip_and_records_axis(tmp_path):
    """combine: zip gives one dimension 'variant' with the axes as coordinates along it; a
    records axis takes file names (relative to the sweep file), and the definition carries
    the files' contents, so the run needs them no more once the sweep is loaded."""
    t = np.arange(0, 1.6, 0.01)
    for name, scale in (("one.txt", 1.0), ("two.txt", 2.5)):
        rows = np.column_stack([t, scale * 9.81 * np.sin(2 * np.pi * t)])
        np.savetxt(tmp_path / name, rows)
    base = BASE.replace("excitation: {kind: sine, amplitude: 9.81, frequency: 6.283185307179586}",
                        "excitation: {kind: record, file: one.txt}")
    (tmp_path / "base.yaml").write_text(base, encoding="utf-8")
    (tmp_path / "records.yaml").write_text(
        "base: base.yaml\n"
        "combine: zip\n"
        "axes:\n"
        "  - {name: record, path: excitation.file, values: [one.txt, two.txt, two.txt]}\n"
        "  - {name: gap, path: contacts.*.gap, values: [0.01, 0.01, 0.03]}\n", encoding="utf-8")
    definition = load_sweep(tmp_path / "records.yaml")
    (tmp_path / "one.txt").unlink()
    (tmp_path / "two.txt").unlink()
    out = tmp_path / "records.h5"
    assert run_sweep(definition, out).completed
    xr = pytest.importorskip("xarray")
    with xr.open_dataset(out, engine="h5netcdf") as ds:
        assert ds.peak_displacement.dims == ("variant", "node")
        assert list(ds.record.values) == ["one.txt", "two.txt", "two.txt"]
        assert list(ds.gap.values) == [0.01, 0.01, 0.03]
        peaks = ds.peak_displacement.values
        assert peaks[1].max() > 1.5 * peaks[0].max()  # 2.5 times the shaking
        assert not np.array_equal(peaks[1], peaks[2])


def test_pi_form_base_and_dimensionless_output(tmp_path):
    """A Pi-form base scene: an axis over pi.Pi_d, and the file dimensionless like the base's."""
    text = (REPO / "models" / "wu2021-eq14-pi.yaml").read_text(encoding="utf-8")
    text = text.replace("tau: 50", "tau: 5")
    (tmp_path / "pi.yaml").write_text(text, encoding="utf-8")
    (tmp_path / "sweep.yaml").write_text(
        "base: pi.yaml\n"
        "axes: [{name: Pi_d, path: pi.Pi_d, values: [0.0, 5.0]}]\n"
        "keep: {envelopes: [building_peak_displacement, building_peak_ductility, "
        "peak_contact_force]}\n", encoding="utf-8")
    out = tmp_path / "pi.h5"
    assert run_sweep(load_sweep(tmp_path / "sweep.yaml"), out).completed
    with h5py.File(out, "r") as f:
        assert f.attrs["units_system"] == b"dimensionless"  # NC_CHAR: bytes in h5py
        assert f["building_peak_displacement"].attrs["units"] == b"1"
        assert [b"".join(row).decode() for row in f["building_name"][...]] == ["A", "B"]
        assert f["peak_contact_force"][1].max() == 0.0  # a gap of 5 l_e: no pounding
        assert f["peak_contact_force"][0].max() > 0.0
        assert "peak_displacement" not in f


# ---------------------------------------------------------------------------------------------
# bad sweep files
# ---------------------------------------------------------------------------------------------

def _error(folder, text: str) -> str:
    with pytest.raises(InputError) as info:
        parse_sweep(text, "bad.yaml", folder)
    return str(info.value)


@pytest.mark.parametrize("text, expected", [
    ("base: base.yaml\naxes:\n  - {name: gap, path: contacts.floor-9.gap, values: [0.1]}\n",
     ["bad.yaml, line 3", "no item named 'floor-9'", "floor-1, floor-2"]),
    ("base: base.yaml\naxes:\n  - {name: gap, path: contacts.*.law, values: [0.1]}\n",
     ["bad.yaml, line 3", "not a number"]),
    ("base: base.yaml\naxes:\n  - {name: gap, path: contacts.*.gap, values: [0.1, -0.2]}\n",
     ["bad.yaml, line 3", "axis 'gap'", "gap=-0.2", "base.yaml, line 8, contacts[0].gap",
      "greater than or equal to 0"]),
    ("base: base.yaml\naxes:\n  - {name: n, path: buildings.A.floors, values: [2, 3]}\n",
     ["axis 'n'", "n=3", "topology"]),
    ("base: base.yaml\naxes:\n  - {name: tol, path: analysis.dt, values: [2.0e-4, 1.0e-4]}\n",
     ["axis 'tol'", "number of steps"]),
    ("base: base.yaml\ncombine: zip\naxes:\n  - {name: a, path: contacts.*.gap, values: [0.1]}\n"
     "  - {name: b, path: damping.ratio, values: [0.01, 0.02]}\n",
     ["bad.yaml, line 2", "equal lengths"]),
    ("base: base.yaml\naxes:\n  - {name: node, path: contacts.*.gap, values: [0.1]}\n",
     ["bad.yaml, line 3", "taken by the result file"]),
    ("base: base.yaml\naxes:\n  - {name: gap, path: contacts.*.gap, linspace: [0, 1, 3],\n"
     "     values: [1]}\n", ["bad.yaml, line 3", "exactly one of values, linspace"]),
    ("base: missing.yaml\naxes:\n  - {name: gap, path: contacts.*.gap, values: [0.1]}\n",
     ["bad.yaml, line 1", "base scene", "not found"]),
    ("base: base.yaml\naxes:\n  - {name: gap, path: contacts.*.gap, values: [0.1, off]}\n",
     ["bad.yaml, line 3, axes[0]", "False is neither a finite number"]),
    ("base: base.yaml\nchunk: true\naxes:\n  - {name: gap, path: contacts.*.gap, values: [0.1]}\n",
     ["bad.yaml, line 2, chunk", "got the boolean true"]),
])
def test_bad_sweeps_are_refused_with_line_and_axis(folder, text, expected):
    message = _error(folder, text)
    for part in expected:
        assert part in message, message


def test_sweep_cli_refusals(folder, grid, tmp_path, capsys):
    """An existing output is replaced only with --overwrite (a complete file of the same
    sweep is left as it is); --variant prints a scene that pframe solve reads."""
    sweep = str(folder / "grid.yaml")
    assert main(["sweep", sweep, "-o", str(grid)]) == 0
    assert "already holds this sweep" in capsys.readouterr().out
    other = tmp_path / "other.h5"
    other.write_bytes(b"not a sweep")
    assert main(["sweep", sweep, "-o", str(other), "-q"]) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert main(["sweep", sweep, "--variant", "5"]) == 0
    printed = capsys.readouterr().out
    assert "restitution=0.8" in printed
    scene = parse_scene(printed, base_dir=folder)
    assert [c.gap for c in scene.scene.contacts] == [0.02, 0.02]
    assert main(["sweep", sweep, "--variant", "6"]) == 2


def test_resume_refuses_chunks_of_another_sweep(folder, tmp_path, capsys):
    out = tmp_path / "grid.h5"
    parts = tmp_path / "grid.h5.parts"
    parts.mkdir()
    (parts / "sweep.json").write_text('{"sweep_digest": "0", "source": "x.yaml", "variants": 9}')
    assert main(["sweep", str(folder / "grid.yaml"), "-o", str(out), "-q"]) == 2
    err = capsys.readouterr().err
    assert "chunks of another sweep (x.yaml, 9 variants)" in err and "--overwrite" in err
    assert not out.exists()


@pytest.mark.slow
def test_default_sweep_imports_no_dask(folder, tmp_path):
    import subprocess

    code = ("import sys; from pframe.cli import main; "
            f"rc = main(['sweep', {str(folder / 'grid.yaml')!r}, '-o', "
            f"{str(tmp_path / 'x.h5')!r}, '-q']); "
            "print(rc, 'dask' in sys.modules or 'distributed' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=600)
    assert done.stdout.split() == ["0", "False"], done.stderr


@pytest.mark.slow
def test_plot_draws_a_response_spectrum(grid, tmp_path, capsys):
    """pframe plot on a sweep file: a response against one axis, one curve per contact (the
    response's entity) or per value of another axis."""
    pytest.importorskip("matplotlib")
    figure = tmp_path / "spectrum.png"
    assert main(["plot", str(grid), "-o", str(figure), "--response", "peak_contact_force"]) == 0
    assert figure.stat().st_size > 10_000
    assert "largest over restitution" in capsys.readouterr().out
    from pframe.plot.spectrum import spectrum

    fig, notes = spectrum(grid, response="peak_contact_force", curves="restitution",
                          at={"contact": "floor-2"})
    ax = fig.axes[0]
    assert [line.get_label() for line in ax.get_lines()] == ["restitution = 0.4",
                                                             "restitution = 0.8"]
    assert notes == ["contact = floor-2"]
    with h5py.File(grid, "r") as f:
        expected = f["peak_contact_force"][:, 1, 1]
    assert np.array_equal(ax.get_lines()[1].get_ydata(), expected)
    assert main(["plot", str(grid), "-o", str(figure), "--x", "nothing"]) == 2
    assert "not a swept axis" in capsys.readouterr().err


def test_sweep_blocks_of_the_docs_are_sweeps():
    """Every sweep (a yaml block with axes) in docs/sweeps.md passes the sweep model, and the
    whole loader when its files exist; the Pi-spectrum block is the shipped example's."""
    import re

    from pframe.sweep import SweepFile

    page = (REPO / "docs" / "sweeps.md").read_text(encoding="utf-8")
    blocks = [b for b in re.findall(r"^```yaml\n(.*?)^```", page, re.M | re.S)
              if "axes" in (yaml.safe_load(b) or {})]
    assert len(blocks) >= 3
    example = REPO / "models" / "sweeps" / "wu2021-pi-d.yaml"
    assert yaml.safe_load(blocks[0]) == yaml.safe_load(example.read_text(encoding="utf-8"))
    for block in blocks[1:]:
        data = yaml.safe_load(block)
        SweepFile.model_validate(data)
        if (REPO / "docs" / data["base"]).exists() and "excitation.file" not in block:
            parse_sweep(block, "docs/sweeps.md", REPO / "docs")


def test_yaml_exponents_without_a_dot_are_numbers(folder):
    """YAML 1.1 reads 1e-3 as text; an axis setting a number takes it as 0.001."""
    definition = parse_sweep("base: base.yaml\naxes:\n"
                             "  - {name: gap, path: contacts.*.gap, values: [1e-3, 0.5, 2e-2]}\n",
                             "s.yaml", folder)
    assert parse(definition).axes[0].values == (0.001, 0.5, 0.02)
    message = _error(folder, "base: base.yaml\naxes:\n"
                             "  - {name: gap, path: contacts.*.gap, values: [0.1, wide]}\n")
    assert "s.yaml" not in message and "bad.yaml, line 3" in message and "'wide'" in message


def test_chunks_of_other_pframe_code_are_refused(folder):
    """A sweep started by one pframe is not computed by another (a worker with another
    version, or source edited before a resume): the digest covers the code, and a chunk
    refuses to run under code other than the sweep's."""
    from pframe.errors import PframeError
    from pframe.sweep import run_chunk

    definition = load_sweep(folder / "grid.yaml")
    other = dataclasses.replace(definition, code="0123456789abcdef")
    assert other.digest != definition.digest
    with pytest.raises(PframeError, match="other pframe code"):
        run_chunk(other, 0)


@pytest.mark.slow
def test_the_pi_d_spectrum_of_the_docs(tmp_path):
    """models/sweeps/wu2021-pi-d.yaml gives the spectrum docs/sweeps.md describes: A's peak
    1.04 l_e with the gap closed and its own 1.40 l_e once no floor pounds (Pi_d >= 1.4);
    B's peak 0.31 at Pi_d = 0.2 and its own 0.205 at Pi_d = 0.5 and from Pi_d = 1.1 on."""
    out = tmp_path / "pi-d.h5"
    assert main(["sweep", str(REPO / "models" / "sweeps" / "wu2021-pi-d.yaml"), "-o", str(out),
                 "-q"]) == 0
    with h5py.File(out, "r") as f:
        pi_d = f["Pi_d"][...]
        peak = f["building_peak_displacement"][...]  # (Pi_d, building A B)
        impacts = f["impact_count"][...].sum(axis=1)
        assert f["building_peak_displacement"].attrs["units"] == b"1"
    assert len(pi_d) == 41 and pi_d[-1] == 2.0
    free = pi_d >= 1.4 - 1e-9
    assert np.all(impacts[free] == 0) and np.all(impacts[~free] > 0)
    assert peak[0, 0] == pytest.approx(1.04, abs=0.005)
    assert np.allclose(peak[free, 0], 1.40, atol=0.005)
    assert peak[4, 1] == pytest.approx(0.31, abs=0.005) and pi_d[4] == pytest.approx(0.2)
    assert peak[10, 1] == pytest.approx(0.2055, abs=0.001) and pi_d[10] == pytest.approx(0.5)
    assert np.allclose(peak[pi_d >= 1.1 - 1e-9, 1], 0.2055, atol=0.001)
    assert np.all(peak[pi_d >= 0.5 - 1e-9, 1] < 0.22)
    assert peak[:, 1].max() == peak[4, 1]


@pytest.mark.slow
def test_a_records_axis_is_named_by_the_records(tmp_path):
    """A sweep over record files (in a folder): the Dataset's records axis has the records'
    names (``.sel(record="two")``), the files stay in ``record_file``, and the spectrum's
    legend names the records, not their relative paths."""
    import pframe

    (tmp_path / "rec").mkdir()
    t = np.arange(0, 1.6, 0.01)
    for name, scale in (("one.txt", 1.0), ("two.txt", 2.5)):
        np.savetxt(tmp_path / "rec" / name, np.column_stack([t, scale * 9.81 * np.sin(2 * np.pi * t)]))
    base = BASE.replace("excitation: {kind: sine, amplitude: 9.81, frequency: 6.283185307179586}",
                        "excitation: {kind: record, file: rec/one.txt}")
    (tmp_path / "base.yaml").write_text(base, encoding="utf-8")
    (tmp_path / "records.yaml").write_text(
        "base: base.yaml\n"
        "axes:\n"
        "  - {name: record, path: excitation.file, values: [rec/one.txt, rec/two.txt]}\n"
        "  - {name: gap, path: contacts.*.gap, values: [0.01, 0.03], units: m}\n",
        encoding="utf-8")
    out = tmp_path / "records.nc"
    assert run_sweep(load_sweep(tmp_path / "records.yaml"), out).completed
    with pframe.open(out) as ds:
        assert ds.record.values.tolist() == ["one", "two"]
        assert ds.record_file.values.tolist() == ["rec/one.txt", "rec/two.txt"]
        two = ds.peak_displacement.sel(record="two", gap=0.01)
        assert float(two.max()) > 1.5 * float(ds.peak_displacement.sel(record="one", gap=0.01).max())
    pytest.importorskip("matplotlib")
    from pframe.plot.spectrum import spectrum

    fig, _ = spectrum(out, response="peak_displacement", x="gap", curves="record")
    legend = fig.axes[0].get_legend()
    assert [text.get_text() for text in legend.get_texts()] == ["one", "two"]


def test_analytic_excitation_facts_are_shared_between_variants_not_aliased():
    """A sine's facts (its peak found by a search) are computed once per fields and duration
    for all the variants of a sweep: each call gets its own copy, equal to a fresh
    computation; another duration gets its own facts."""
    from pframe.excitation.describe import _applied_motion, applied_motion
    from pframe.reader import load_scene

    ex = load_scene(WU2021).scene.excitation
    first = applied_motion(ex, None, 3.0)
    first["pga"] = -1.0
    again = applied_motion(ex, None, 3.0)
    assert again == _applied_motion(ex, None, 3.0) and again["pga"] == pytest.approx(9.81)
    early = applied_motion(ex, None, 0.1)  # before the sine's first peak (t = 0.25 s)
    assert early["applied_peak"] == pytest.approx(9.81 * math.sin(2 * math.pi * 0.1), rel=1e-9)


@pytest.mark.parametrize("written, meant", [("contacts[0].gap", "contacts.0"),
                                            ("contacts['floor-1'].gap", "contacts.floor-1"),
                                            ("buildings[ 1 ].mass", "buildings.1")])
def test_a_bracketed_path_is_told_the_dotted_form(tmp_path, written, meant):
    """A path written as Python or JSONPath would index a list is told how pframe's paths
    name an item, not only that the key is missing."""
    from pframe.errors import InputError
    from pframe.sweep.paths import resolve

    data = yaml.safe_load(BASE)
    with pytest.raises(InputError, match=re.escape(f"after a dot: {meant},")):
        resolve(data, tuple(written.split(".")))


@pytest.mark.slow
def test_peaks_of_foundations_are_kept_along_them(tmp_path):
    """A response along the foundations of a scene on soil (``peak_foundation_sway``) is
    written along ``foundation``, labelled by its buildings, each variant its own run's."""
    data = yaml.safe_load((Path(__file__).parent.parent / "models" / "ssi-pair.yaml")
                          .read_text(encoding="utf-8"))
    data["analysis"]["duration"] = 400 * data["analysis"]["dt"]
    (tmp_path / "base.yaml").write_text(yaml.safe_dump(data), encoding="utf-8")
    (tmp_path / "sweep.yaml").write_text(
        "base: base.yaml\naxes:\n  - {name: gap, path: contacts.*.gap, values: [0.0, 0.1]}\n"
        "keep: {envelopes: [peak_foundation_sway, peak_foundation_rocking]}\n",
        encoding="utf-8")
    out = tmp_path / "sweep.h5"
    assert main(["sweep", str(tmp_path / "sweep.yaml"), "-o", str(out), "-q"]) == 0
    definition = load_sweep(tmp_path / "sweep.yaml")
    with pframe.open(out) as ds:
        assert ds.peak_foundation_sway.dims == ("gap", "foundation")
        assert list(ds.foundation_name.values) == ["A", "B"]
        for index in range(2):
            _, single = _single(definition, index, recorders=parse(definition).recorders)
            np.testing.assert_array_equal(ds.peak_foundation_sway.values[index],
                                          single.envelope["foundation_sway"][0])
