"""``pframe plot``: the figures hold the file's data, files and pages come out as documented,
and bad input fails with one message naming the file.

The scene has the structure of models/wu2021-eq14.yaml (bilinear storeys, improved Kelvin
contacts, the same recorders), so it reuses that scene's compiled kernel. Its buildings differ
in height (3 and 2 floors) and its contacts are declared top first under names that do not
say their nodes, so the level of a contact must come from the scene text, not from its index.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

pytest.importorskip("matplotlib")

from pframe.cli import main  # noqa: E402
from pframe.plot import figures, read_result  # noqa: E402

SCENE = """\
title: plot test, 3 + 2 storeys
buildings:
  - name: L
    floors: 3
    mass: 1000.0
    story: {material: bilinear, stiffness: 4.0e5, yield_drift: 0.01, alpha: 0.1}
  - name: R
    floors: 2
    mass: [2000.0, 1500.0]
    story: {material: bilinear, stiffness: 8.0e6, yield_drift: 0.03, alpha: 0.1}
contacts:
  - {name: upper, nodes: [L/2, R/2], gap: 0.001, law: improved_kelvin, stiffness: 1.0e7,
     restitution: 0.5}
  - {name: lower, nodes: [L/1, R/1], gap: 0.001, law: improved_kelvin, stiffness: 1.0e7,
     restitution: 0.5}
excitation: {kind: sine, amplitude: 3.0, frequency: 6.0}
analysis:
  dt: 0.002
  duration: 1.0
recorders:
  - kind: history
    quantities: [displacement, velocity, story_force, story_drift, contact_force]
  - kind: envelope
    quantities: [displacement, story_drift, contact_force]
"""
A_P, W_P, M_B = 3.0, 6.0, 2000.0  # m_b: the first floor mass of the second building, R/1
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("plot")
    scene = folder / "scene.yaml"
    scene.write_text(SCENE, encoding="utf-8")
    out = folder / "scene.h5"
    assert main(["solve", str(scene), "-o", str(out), "-q"]) == 0
    return out


@pytest.fixture
def copy(result_file, tmp_path):
    """A writable copy of the result file, to damage."""
    path = tmp_path / "copy.h5"
    shutil.copy(result_file, path)
    return path


#: names the tests use -> the file's variables (names are label variables, time is t)
_IN_FILE = {"time": "t", "node": "node_name", "story": "story_name", "contact": "contact_name"}


def read(path, name):
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        values = ds[_IN_FILE.get(name, name)].values
        return [str(v) for v in values] if values.dtype == object else values


def axes_by_label(fig):
    return {ax.get_label(): ax for ax in fig.axes}


def lines_by_label(ax):
    return {line.get_label(): line for line in ax.get_lines()}


def pdf_pages(path) -> int:
    return len(re.findall(rb"/Type\s*/Page\b", path.read_bytes()))


@pytest.mark.slow
def test_png_per_level_and_pdf_pages(result_file, tmp_path, capsys):
    assert main(["plot", str(result_file), "-o", str(tmp_path / "fig.png")]) == 0
    pngs = sorted(tmp_path.glob("fig-*.png"))
    assert [p.name for p in pngs] == ["fig-1.png", "fig-2.png", "fig-3.png"]
    assert all(p.read_bytes()[:8] == PNG_MAGIC for p in pngs)
    assert "wrote" in capsys.readouterr().out

    pdf = tmp_path / "fig.pdf"
    assert main(["plot", str(result_file), "-o", str(pdf), "-q"]) == 0
    assert pdf.read_bytes()[:5] == b"%PDF-"
    assert pdf_pages(pdf) == 3
    assert capsys.readouterr() == ("", "")


@pytest.mark.slow
def test_default_output_is_a_pdf_beside_the_input(copy):
    assert main(["plot", str(copy), "--story", "3", "--kind", "hysteresis", "-q"]) == 0
    assert pdf_pages(copy.with_suffix(".pdf")) == 1


@pytest.mark.slow
def test_one_level_to_one_png_of_the_given_name(result_file, tmp_path):
    out = tmp_path / "level2.png"
    assert main(["plot", str(result_file), "--story", "2", "-o", str(out), "-q"]) == 0
    assert out.read_bytes()[:8] == PNG_MAGIC
    assert list(tmp_path.iterdir()) == [out]


@pytest.mark.slow
def test_figures_hold_the_file_data(result_file):
    time, nodes = read(result_file, "time"), read(result_file, "node")
    stories, contacts = read(result_file, "story"), read(result_file, "contact")
    figs = figures(result_file)
    assert list(figs) == ["1", "2", "3"]

    panels = axes_by_label(figs["2"])
    assert set(panels) == {"displacement", "contact_force", "velocity",
                           "hysteresis L/2", "hysteresis R/2"}
    for quantity in ("displacement", "velocity"):
        lines = lines_by_label(panels[quantity])
        assert set(lines) == {"L/2", "R/2"}
        for node, line in lines.items():
            np.testing.assert_array_equal(line.get_xdata(), time)
            np.testing.assert_array_equal(line.get_ydata(),
                                          read(result_file, quantity)[:, nodes.index(node)])
    # 'upper' is declared first, but joins the floors of level 2
    force = lines_by_label(panels["contact_force"])
    assert set(force) == {"upper"}
    np.testing.assert_array_equal(force["upper"].get_ydata(),
                                  read(result_file, "contact_force")[:, contacts.index("upper")])
    assert force["upper"].get_ydata().max() > 0, "the scene must pound at level 2"
    loop = panels["hysteresis L/2"].get_lines()[0]
    np.testing.assert_array_equal(loop.get_xdata(), read(result_file, "story_drift")[:, 1])
    np.testing.assert_array_equal(loop.get_ydata(), read(result_file, "story_force")[:, 1])
    assert stories[1] == "L/2"
    assert panels["displacement"].get_ylabel() == "displacement (m)"
    assert panels["velocity"].get_xlabel() == "time (s)"
    assert panels["hysteresis L/2"].get_ylabel() == "storey shear (N)"

    # the title says what ran: the scene's title and level, then its excitation
    assert figs["2"].get_suptitle() == ("plot test, 3 + 2 storeys: level 2\n"
                                        "sine, amplitude 3 m/s^2, frequency 6 rad/s")

    # level 3: building L only, no contact there
    assert set(axes_by_label(figs["3"])) == {"displacement", "velocity", "hysteresis L/3"}
    assert set(lines_by_label(axes_by_label(figs["1"])["contact_force"])) == {"lower"}


@pytest.mark.slow
def test_units_and_svg_from_the_command_line(result_file, tmp_path, capsys):
    """``--units engineering`` draws mm and kN (the numbers scaled, the labels saying so),
    as ``pframe.plot(..., units="engineering")`` does; ``-o FIG.svg`` writes SVG."""
    figs = figures(result_file, levels=[2], units="engineering")
    panels = axes_by_label(figs["2"])
    nodes = read(result_file, "node")
    line = lines_by_label(panels["displacement"])["L/2"]
    np.testing.assert_allclose(line.get_ydata(),
                               1000 * read(result_file, "displacement")[:, nodes.index("L/2")],
                               rtol=1e-12)
    assert panels["displacement"].get_ylabel() == "displacement (mm)"
    assert panels["hysteresis L/2"].get_ylabel() == "storey shear (kN)"
    out = tmp_path / "level2.svg"
    assert main(["plot", str(result_file), "--story", "2", "--units", "engineering", "-o",
                 str(out), "-q"]) == 0
    text = out.read_text(encoding="utf-8")
    assert text.lstrip().startswith("<?xml") and "<svg" in text
    assert f"<title>pframe plot {result_file}</title>" in text
    assert main(["plot", str(result_file), "--units", "furlong"]) == 2
    assert "furlong" in capsys.readouterr().err


def test_the_help_names_the_formats_and_units(capsys):
    with pytest.raises(SystemExit):
        main(["plot", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "(.nc)" in text and ".svg" in text and "--units" in text and "(.h5)" not in text


@pytest.mark.slow
def test_kinds_and_time_range(result_file):
    time = read(result_file, "time")
    histories = figures(result_file, kind="histories", levels=[1], time_range=(0.2, 0.5))
    panels = axes_by_label(histories["1"])
    assert set(panels) == {"displacement", "contact_force", "velocity"}
    keep = (time >= 0.2) & (time <= 0.5)
    np.testing.assert_array_equal(panels["displacement"].get_lines()[0].get_xdata(), time[keep])
    loops = figures(result_file, kind="hysteresis")
    assert {level: set(axes_by_label(fig)) for level, fig in loops.items()} == {
        "1": {"hysteresis L/1", "hysteresis R/1"}, "2": {"hysteresis L/2", "hysteresis R/2"},
        "3": {"hysteresis L/3"}}


@pytest.mark.slow
def test_dimensionless_uses_the_scene_scales(result_file):
    time, l_e = read(result_file, "time"), A_P / W_P**2
    panels = axes_by_label(figures(result_file, levels=["1"], dimensionless=True)["1"])
    displacement = lines_by_label(panels["displacement"])["L/1"]
    np.testing.assert_allclose(displacement.get_xdata(), W_P * time, rtol=1e-15)
    np.testing.assert_allclose(displacement.get_ydata(),
                               read(result_file, "displacement")[:, 0] / l_e, rtol=1e-14)
    velocity = lines_by_label(panels["velocity"])["L/1"]
    np.testing.assert_allclose(velocity.get_ydata(),
                               read(result_file, "velocity")[:, 0] * W_P / A_P, rtol=1e-14)
    force = lines_by_label(panels["contact_force"])["lower"]
    np.testing.assert_allclose(force.get_ydata(),
                               read(result_file, "contact_force")[:, 1] / (M_B * A_P), rtol=1e-14)
    assert "tau" in panels["velocity"].get_xlabel()
    assert panels["displacement"].get_ylabel() == r"$x = X / l_e$"


@pytest.mark.slow
def test_dimensionless_takes_the_scales_the_scene_gives(copy):
    """The scales the file stores (those of the scene's output.scales, when it gives them)."""
    with h5py.File(copy, "r+") as f:
        for key, value in (("m_b", 10.0), ("a_p", 2.0), ("w_p", 4.0), ("l_e", 2.0 / 16.0)):
            f.attrs[f"reference_{key}"] = value
    panels = axes_by_label(figures(copy, levels=[2], dimensionless=True)["2"])
    force = lines_by_label(panels["contact_force"])["upper"]
    np.testing.assert_allclose(force.get_xdata(), 4.0 * read(copy, "time"), rtol=1e-15)
    np.testing.assert_allclose(force.get_ydata(), read(copy, "contact_force")[:, 0] / 20.0,
                               rtol=1e-14)


@pytest.mark.slow
def test_a_dimensionless_file_is_labelled_so(copy):
    with h5py.File(copy, "r+") as f:
        for name in ("t", "displacement", "velocity", "contact_force", "story_drift",
                     "story_force"):
            f[name].attrs["units"] = "1"
    panels = axes_by_label(figures(copy, levels=[2])["2"])
    assert "tau" in panels["velocity"].get_xlabel()
    assert panels["contact_force"].get_ylabel() == r"$F_p / (m_b a_p)$"
    assert panels["hysteresis R/2"].get_xlabel() == r"$\Delta x = \Delta X / l_e$"
    # already dimensionless: --dimensionless changes nothing
    again = axes_by_label(figures(copy, levels=[2], dimensionless=True)["2"])
    np.testing.assert_array_equal(again["displacement"].get_lines()[0].get_ydata(),
                                  panels["displacement"].get_lines()[0].get_ydata())


def _solved(tmp_path, text: str, name: str) -> Path:
    scene = tmp_path / f"{name}.yaml"
    scene.write_text(text, encoding="utf-8")
    out = tmp_path / f"{name}.nc"
    assert main(["solve", str(scene), "-o", str(out), "-q"]) == 0
    return out


@pytest.mark.slow
def test_missing_histories_leave_panels_out(tmp_path, capsys):
    copy = _solved(tmp_path, SCENE.replace(
        "quantities: [displacement, velocity, story_force, story_drift, contact_force]",
        "quantities: [displacement, story_drift, contact_force]"), "partial")
    out = tmp_path / "fig.pdf"
    assert main(["plot", str(copy), "-o", str(out)]) == 0
    err = capsys.readouterr().err
    assert "no velocity history: panel (c) left out" in err
    assert "no story_force history" in err
    assert str(copy) in err
    assert pdf_pages(out) == 3
    assert set(axes_by_label(figures(copy)["1"])) == {"displacement", "contact_force"}
    assert main(["plot", str(copy), "--kind", "hysteresis"]) == 2
    assert "nothing to plot for --kind hysteresis" in capsys.readouterr().err


def sweep(path):
    """Give the file's displacement a leading sweep dimension, as sweep files have."""
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        ds = ds.load()
    ds["displacement"] = ds.displacement.expand_dims(case=2)
    path.unlink()
    ds.to_netcdf(path, engine="h5netcdf")


def envelopes_only(path):
    scene = path.with_name("envelopes.yaml")
    scene.write_text(SCENE.replace(
        "  - kind: history\n    quantities: [displacement, velocity, story_force, story_drift, "
        "contact_force]\n", ""), encoding="utf-8")
    path.unlink()
    assert main(["solve", str(scene), "-o", str(path), "-q"]) == 0


def not_pframe(path):
    path.unlink()
    with h5py.File(path, "w") as f:
        f["x"] = np.arange(3)


def not_hdf5(path):
    path.write_text("time,displacement\n0,0\n", encoding="utf-8")


@pytest.mark.slow
@pytest.mark.parametrize(("damage", "message"), [
    (lambda path: path.unlink(), "no such result file"),
    (not_hdf5, "not a netCDF-4/HDF5 file"),
    (not_pframe, "not a pframe result"),
    (envelopes_only, "nothing to plot"),
    (sweep, "holds a sweep (displacement has the dimensions case=2, t="),
], ids=["missing", "not-hdf5", "not-pframe", "nothing-plottable", "sweep"])
def test_bad_files_exit_2_naming_the_file(copy, capsys, damage, message):
    damage(copy)
    assert main(["plot", str(copy)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"pframe: {copy}: ") and message in err
    assert "Traceback" not in err and err.count("\n") == 1
    assert not copy.with_suffix(".pdf").exists()


@pytest.mark.slow
@pytest.mark.parametrize(("args", "message"), [
    (["-o", "figure.tiff"], "must end in .png, .svg or .pdf"),
    (["--story", "7"], "no floor level 7; the levels are 1, 2, 3"),
    (["--time-range", "3", "4"], "no recorded time in --time-range 3 4"),
    (["--time-range", "0.5", "0.1"], "the start must be before the end"),
], ids=["format", "level", "empty-range", "reversed-range"])
def test_bad_arguments_exit_2(result_file, tmp_path, capsys, args, message):
    args = [a if a != "figure.tiff" else str(tmp_path / a) for a in args]
    assert main(["plot", str(result_file), *args]) == 2
    assert message in capsys.readouterr().err


@pytest.mark.slow
def test_dimensionless_needs_a_sine(copy, capsys):
    """A file without stored reference scales (written before they were stored) falls back
    on its scene, which needs a sine or output.scales."""
    with h5py.File(copy, "r+") as f:
        for key in ("m_b", "a_p", "w_p", "l_e"):
            del f.attrs[f"reference_{key}"]
        f.attrs["input_yaml"] = SCENE.replace(
            "excitation: {kind: sine, amplitude: 3.0, frequency: 6.0}",
            "excitation: {kind: record, file: quake.at2}")
    assert main(["plot", str(copy), "--dimensionless"]) == 2
    assert "no sine excitation" in capsys.readouterr().err


def test_without_matplotlib_the_message_says_how_to_install(result_file, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.figure", None)
    assert main(["plot", str(result_file)]) == 2
    err = capsys.readouterr().err
    assert 'pip install "pframe[plot]"' in err and "Traceback" not in err
    assert err.count("\n") == 1


@pytest.mark.slow
def test_other_commands_never_import_matplotlib(tmp_path):
    scene = tmp_path / "scene.yaml"
    scene.write_text(SCENE, encoding="utf-8")
    code = ("import sys; from pframe.cli import main; "
            f"assert main(['validate', {str(scene)!r}]) == 0; "
            "assert 'matplotlib' not in sys.modules, 'matplotlib imported'")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr


@pytest.mark.slow
def test_levels_reads_the_result(result_file):
    levels = read_result(result_file).levels
    assert levels.order == ("1", "2", "3")
    assert levels.buildings == ("L", "R")
    assert levels.contacts == {"2": ["upper"], "1": ["lower"]}
    assert levels.stories["3"] == {"L": "L/3"}


def test_levels_of_a_pi_form_scene():
    """A Pi-form scene names its contacts only once expanded; their levels are still found."""
    from pathlib import Path

    from pframe.plot.levels import group_by_level

    text = (Path(__file__).parents[1] / "models" / "wu2021-eq14-pi.yaml").read_text()
    names = [f"{b}/{i}" for b in "AB" for i in (1, 2, 3)]
    levels = group_by_level(names, names, ["floor-1", "floor-2", "floor-3"], text)
    assert levels.contacts == {"1": ["floor-1"], "2": ["floor-2"], "3": ["floor-3"]}
    assert not levels.unplaced
