"""A record's displacement and velocity files, and what a run says of the displacements it
integrates (docs/supports.md#displacements-from-a-record)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import run_text
from test_supports import pair

from pframe.errors import InputError
from pframe.excitation.records import G
from pframe.model.support_motion import integrated
from pframe.reader import parse_scene

SUPPORTS = [{"name": "west", "position": [0.0, 0.0]}, {"name": "east", "position": [60.0, 0.0]}]
D, W, STEP, CYCLES = 0.05, 2.0 * math.pi, 0.005, 2  # m, rad/s, s


def _peer(path, kind: str, units: str, values) -> str:
    """A PEER NGA file of ``values`` every STEP s (header as PEER writes it)."""
    lines = ["PEER NGA STRONG MOTION DATABASE RECORD", "SYNTHETIC 1-COSINE, 000",
             f"{kind} TIME SERIES IN UNITS OF {units}",
             f"NPTS=  {len(values)}, DT=   {STEP:.4f} SEC"]
    lines += [" ".join(f"{float(v)!r}" for v in values[i:i + 5])
              for i in range(0, len(values), 5)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path.name


def _files(tmp_path, amplitude: float = D) -> tuple[str, str, str]:
    """A ground displacement d = D (1 - cos w t)^2 / 4 over two cycles, then at rest (from
    rest to rest: v = D w (1 - cos) sin / 2, a = D w^2 (sin^2 + cos - cos^2) / 2): its
    acceleration (g), displacement (cm) and velocity (cm/s) as PEER files."""
    t = np.arange(int(round(CYCLES * 2 * math.pi / W / STEP)) + 1) * STEP
    c, s = np.cos(W * t), np.sin(W * t)
    a = 0.5 * D * W**2 * (s**2 + c - c**2)
    return (_peer(tmp_path / "pulse.AT2", "ACCELERATION", "G", a / G),
            _peer(tmp_path / "pulse.DT2", "DISPLACEMENT", "CM", 100 * amplitude / D * _d(t)),
            _peer(tmp_path / "pulse.VT2", "VELOCITY", "CM/S", 100 * 0.5 * D * W * (1 - c) * s))


def _d(time):
    """The pulse's displacement (m) at ``time`` (s): zero before and after it."""
    inside = (time >= 0) & (time <= CYCLES * 2 * math.pi / W + 1e-9)
    return np.where(inside, 0.25 * D * (1 - np.cos(W * time)) ** 2, 0.0)


def _scene(tmp_path, record: dict) -> dict:
    scene = pair(SUPPORTS, {"kind": "wave_passage", "velocity": 150.0, "motion": record},
                 contacts=[{"nodes": ["A/3", "B/3"], "gap": 10.0, "law": "linear",
                            "stiffness": 1e9}], dt=STEP, duration=3.0,
                 quantities=("displacement", "contact_ground_displacement"))
    return scene


def _ground(tmp_path, scene):
    loaded = parse_scene(json.dumps(scene), base_dir=tmp_path)
    plan, result = run_text(json.dumps(scene), base_dir=tmp_path)
    return loaded, result.history["contact_ground_displacement"][0][:, 0]


def test_a_displacement_file_moves_the_supports(tmp_path):
    """The supports 60 m apart under a wave passage (0.4 s) of the pulse: with its
    displacement and velocity files, the contact's ground part is the files' d(t) -
    d(t - 0.4 s) to round-off; without, the acceleration integrated twice from rest, within
    the trapezoid rule's error (of order (2 w h)^2 / 12 of the peak, 2 w the pulse's highest
    frequency: 3e-4 here); the files agree
    with the acceleration, and nothing is warned."""
    at2, dt2, vt2 = _files(tmp_path)
    plain = {"kind": "record", "file": at2}
    files = plain | {"displacement": dt2, "velocity": vt2}
    loaded, read = _ground(tmp_path, _scene(tmp_path, files))
    _, integrated_ = _ground(tmp_path, _scene(tmp_path, plain))
    t = np.arange(read.size) * STEP

    exact = _d(t) - _d(t - 0.4)
    assert np.max(np.abs(read - exact)) < 1e-12
    assert np.max(np.abs(integrated_ - exact)) < 5e-4 * D
    assert np.max(np.abs(integrated_ - exact)) > 0  # the two ways differ
    assert not [w for w in loaded.expanded.warnings if "displacement file" in w]


def test_a_displacement_file_of_another_record_is_warned(tmp_path):
    """A displacement file twice the acceleration's double integral: the run says by how
    much they differ and that the supports move by the file's."""
    at2, dt2, _ = _files(tmp_path, amplitude=2 * D)
    scene = _scene(tmp_path, {"kind": "record", "file": at2, "displacement": dt2})
    warnings = parse_scene(json.dumps(scene), base_dir=tmp_path).expanded.warnings
    said = [w for w in warnings if "displacement file pulse.DT2" in w]
    assert len(said) == 1 and "50 % of the file's peak" in said[0]


def test_the_run_states_how_it_had_the_displacements(tmp_path, capsys):
    """Without files, pframe validate, solve and the file's ground_displacement_method say
    no baseline correction is applied and how far each support drifts: the velocity and
    displacement at the end of the acceleration integrated from rest; with a baseline
    correction to rest, the record ends at rest; with the files, the files."""
    import pframe
    from pframe.cli import main

    at2, dt2, vt2 = _files(tmp_path)
    scene = _scene(tmp_path, {"kind": "record", "file": at2})
    path = tmp_path / "s.yaml"
    path.write_text(json.dumps(scene), encoding="utf-8")
    assert main(["validate", str(path)]) == 0
    out = capsys.readouterr().out
    ex = parse_scene(json.dumps(scene), base_dir=tmp_path).expanded
    v, d = integrated(ex.support_samples[1], STEP)
    assert (f"support east along x: no baseline correction: displacement the acceleration "
            f"integrated twice from rest (the trapezoid rule); at t = 3 s its velocity is "
            f"{v[-1]:.4g} m/s and its displacement {d[-1]:.4g} m") in out
    ds = pframe.solve(path, progress=False)
    assert ds.attrs["ground_displacement_method"].splitlines() == [
        line.strip() for line in out.splitlines() if line.strip().startswith("support ")
        and " along x: " in line]
    rest = _scene(tmp_path, {"kind": "record", "file": at2, "baseline": {"fit": "rest"}})
    ex = parse_scene(json.dumps(rest), base_dir=tmp_path).expanded
    v, d = integrated(ex.support_samples[0], STEP)
    assert abs(v[-1]) < 1e-12 and abs(d[-1]) < 1e-12  # the whole record is inside
    from pframe.model.support_motion import displacement_lines

    assert displacement_lines(ex)[0].startswith(
        "support west along x: the record's acceleration baseline-corrected (fit rest, "
        "degree 1): displacement the acceleration integrated twice")
    given = _scene(tmp_path, {"kind": "record", "file": at2, "displacement": dt2,
                              "velocity": vt2})
    lines = displacement_lines(parse_scene(json.dumps(given), base_dir=tmp_path).expanded)
    assert lines[1].startswith("support east along x: displacement from pulse.DT2 (cm), "
                               "within ")
    assert "velocity from pulse.VT2 (cm/s)" in lines[1]


def test_a_result_with_a_displacement_file_reproduces(tmp_path):
    """The file holds the displacement and velocity files' text: pframe.load of the result
    runs the same bits with the files gone."""
    import shutil

    import pframe

    folder = tmp_path / "in"
    folder.mkdir()
    at2, dt2, vt2 = _files(folder)
    scene = _scene(folder, {"kind": "record", "file": at2, "displacement": dt2,
                            "velocity": vt2})
    (folder / "s.yaml").write_text(json.dumps(scene), encoding="utf-8")
    first = pframe.solve(folder / "s.yaml", output=tmp_path / "run.nc", progress=False)
    expected = first.contact_ground_displacement.values.copy()
    shutil.rmtree(folder)
    again = pframe.solve(pframe.load(tmp_path / "run.nc"), progress=False)
    np.testing.assert_array_equal(again.contact_ground_displacement.values, expected)


def test_displacement_files_are_checked(tmp_path):
    """A velocity without a displacement, a baseline with a displacement file, a file that
    is not there, a displacement in two components: refused with the field."""
    at2, dt2, vt2 = _files(tmp_path)

    def refused(record, match, components=False):
        motion = ({"kind": "components", "x": record, "y": {"kind": "record", "file": at2}}
                  if components else record)
        scene = _scene(tmp_path, motion)
        with pytest.raises(InputError, match=match):
            parse_scene(json.dumps(scene), base_dir=tmp_path)

    base = {"kind": "record", "file": at2}
    refused(base | {"velocity": vt2}, r"excitation\.motion: .*velocity comes with displacement")
    refused(base | {"displacement": dt2, "baseline": {"fit": "rest"}},
            r"excitation\.motion: .*give no baseline with it")
    refused(base | {"displacement": "none.DT2"},
            r"excitation\.motion\.displacement: displacement file .*none\.DT2' not found")
    refused(base | {"displacement": dt2}, r"excitation\.motion\.x\.displacement: a record's "
                                          r"displacement file", components=True)



@pytest.mark.slow
def test_a_sweep_carries_the_displacement_files(tmp_path):
    """A sweep over the apparent velocity of a scene whose record names its displacement and
    velocity files: each variant's contact ground displacement is its single run's, to the
    bit (the sweep carries the files as it carries records)."""
    import pframe

    at2, dt2, vt2 = _files(tmp_path)
    scene = _scene(tmp_path, {"kind": "record", "file": at2, "displacement": dt2,
                              "velocity": vt2})
    (tmp_path / "b.yaml").write_text(json.dumps(scene), encoding="utf-8")
    (tmp_path / "sw.yaml").write_text(
        "base: b.yaml\naxes:\n  - {name: v, path: excitation.velocity, values: [150, 300]}\n"
        "keep: {histories: [contact_ground_displacement]}\n", encoding="utf-8")
    ds = pframe.sweep(tmp_path / "sw.yaml", progress=False)
    for i, velocity in enumerate((150.0, 300.0)):
        scene["excitation"]["velocity"] = velocity
        _, alone = _ground(tmp_path, scene)
        np.testing.assert_array_equal(
            ds.contact_ground_displacement.isel(v=i).values.ravel(), alone)


@pytest.mark.slow
def test_the_supports_figure_draws_what_the_file_holds(tmp_path):
    """pframe plot --kind supports: a panel per ground history the file holds, each line the
    file's values (each support's acceleration and displacement, the contact's relative
    ground displacement, in the file's units), how the displacements were had below; a
    scene on one ground is refused."""
    import pframe
    from pframe.plot import figures

    at2, dt2, _ = _files(tmp_path)
    scene = _scene(tmp_path, {"kind": "record", "file": at2})
    scene["recorders"] = [{"kind": "history", "quantities": [
        "displacement", "ground_acceleration", "ground_displacement",
        "contact_ground_displacement"]}]
    path = tmp_path / "s.yaml"
    path.write_text(json.dumps(scene), encoding="utf-8")
    ds = pframe.solve(path, output=tmp_path / "s.nc", progress=False)
    fig = figures(tmp_path / "s.nc", kind="supports")["supports"]
    panels = {ax.get_gid(): ax for ax in fig.axes if ax.get_gid()}
    assert list(panels) == ["ground_acceleration", "ground_displacement",
                            "contact_ground_displacement"]
    for quantity, ax in panels.items():
        lines = ax.get_lines()[:len(ds[quantity][ds[quantity].dims[1]])]
        for i, line in enumerate(lines):
            np.testing.assert_array_equal(line.get_ydata(), ds[quantity].values[:, i])
        assert f"({ds[quantity].attrs['units']})" in ax.get_ylabel()
    assert "no baseline correction" in fig.get_supxlabel()
    assert "not drawn" not in fig.get_supxlabel()
    # a file without the supports' own histories: its panel (c) alone, and the two left out
    # named below it with what to record
    scene["recorders"] = [{"kind": "history", "quantities": ["contact_ground_displacement"]}]
    path.write_text(json.dumps(scene), encoding="utf-8")
    pframe.solve(path, output=tmp_path / "c.nc", progress=False)
    fig = figures(tmp_path / "c.nc", kind="supports")["supports"]
    assert [ax.get_gid() for ax in fig.axes if ax.get_gid()] == ["contact_ground_displacement"]
    said = " ".join(fig.get_supxlabel().split())
    assert ("not drawn: (a) ground_acceleration, (b) ground_displacement, which the file does "
            "not record") in said
    one = json.loads(json.dumps(scene))
    del one["supports"]
    for b in one["buildings"]:
        del b["support"]
    one["excitation"] = one["excitation"]["motion"]
    path.write_text(json.dumps(one), encoding="utf-8")
    pframe.solve(path, output=tmp_path / "one.nc", progress=False)
    with pytest.raises(InputError, match="stands on one ground: --kind supports"):
        figures(tmp_path / "one.nc", kind="supports")
