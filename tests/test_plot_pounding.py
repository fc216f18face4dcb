"""The pounding figure (``pframe plot --kind pounding``, ``pframe.plot(..., kind="pounding")``):
per contact, the relative displacement of its two nodes against its gap, the closed stretches
shaded, the impacts marked on the time axis, and the contact force. The figure's content is
checked against the file read independently (xarray), and the impacts against the kernel's
own count (``impact_count``) and its force history, not against pixels."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")

import pframe  # noqa: E402
from pframe.cli import main  # noqa: E402
from pframe.plot import figures  # noqa: E402

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def eq14(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("pounding") / "eq14.nc"
    assert main(["solve", str(REPO / "models" / "wu2021-eq14.yaml"), "-o", str(path), "-q"]) == 0
    return path


@pytest.fixture(scope="module")
def data(eq14):
    with pframe.open(eq14) as ds:
        return ds.load()


def _axes(fig) -> dict:
    return {ax.get_label(): ax for ax in fig.axes}


def _line(ax, label):
    return next(line for line in ax.get_lines() if line.get_label() == label)


def _impact_times(ax) -> np.ndarray:
    return np.asarray(_line(ax, "impacts").get_xdata(), dtype=float)


@pytest.mark.slow
def test_every_contact_of_a_level_has_its_gap_panel_with_the_file_data(eq14, data):
    figs = figures(eq14, kind="pounding")
    assert list(figs) == ["1", "2", "3"]  # every level of the paper's example pounds
    for level, fig in figs.items():
        contact = f"floor-{level}"
        ax = _axes(fig)[f"gap {contact}"]
        left = str(data.contact_left.sel(contact=contact).values)
        right = str(data.contact_right.sel(contact=contact).values)
        relative = _line(ax, "relative")
        expected = (data.displacement.sel(node=left) - data.displacement.sel(node=right)).values
        np.testing.assert_array_equal(relative.get_xdata(), data.t.values)
        np.testing.assert_array_equal(relative.get_ydata(), expected)
        gap = float(data.contact_gap.sel(contact=contact))
        assert set(_line(ax, "gap").get_ydata()) == {gap}
        # the shading covers the closed stretches, and only them
        (shade,) = [c for c in ax.collections if c.get_label() == "closed"]
        closed_y = np.concatenate([p.vertices[:, 1] for p in shade.get_paths()])
        assert closed_y.min() >= gap - 1e-12 and closed_y.max() == pytest.approx(expected.max())
        assert f"{left} - {right}" in [t.get_text() for t in ax.get_legend().get_texts()]
        assert "force " + contact in _axes(fig)


@pytest.mark.slow
def test_impacts_are_the_kernels_impacts(eq14, data):
    """The markers are where the relative displacement rises past the gap: as many as the
    kernel counted (``impact_count``: 8 per contact, as the paper reports), and at each
    the contact force history is compressive one step on (the force starts with the
    contact: an independent record of the same events)."""
    figs = figures(eq14, kind="pounding")
    for level, fig in figs.items():
        contact = f"floor-{level}"
        times = _impact_times(_axes(fig)[f"gap {contact}"])
        assert len(times) == int(data.impact_count.sel(contact=contact)) == 8
        force = data.contact_force.sel(contact=contact).values
        index = np.searchsorted(data.t.values, times)
        assert np.all(force[np.minimum(index + 1, len(force) - 1)] > 0)
        assert np.all(force[index - 1] == 0)  # open just before
        np.testing.assert_array_equal(_impact_times(_axes(fig)[f"force {contact}"]), times)


@pytest.mark.slow
def test_units_and_dimensionless_move_the_gap_with_the_displacement(eq14, data):
    mm = figures(eq14, kind="pounding", levels=["3"], units="engineering")["3"]
    ax = _axes(mm)["gap floor-3"]
    gap = float(data.contact_gap.sel(contact="floor-3"))
    assert _line(ax, "gap").get_ydata()[0] == pytest.approx(1e3 * gap, rel=1e-12)
    assert "(mm)" in ax.get_ylabel()
    pi = figures(eq14, kind="pounding", levels=["3"], dimensionless=True)["3"]
    ax = _axes(pi)["gap floor-3"]
    l_e = float(data.attrs["reference_l_e"])
    assert _line(ax, "gap").get_ydata()[0] == pytest.approx(gap / l_e, rel=1e-12)
    relative = _line(ax, "relative").get_ydata()
    assert (relative > gap / l_e).any()  # the closing is the same in either variables
    assert len(_impact_times(ax)) == 8


def test_from_python_on_a_dataset(data):
    fig = pframe.plot(data, kind="pounding")  # default level: the top one with a contact
    assert set(_axes(fig)) == {"gap floor-3", "force floor-3"}
    assert "pounding at level 3" in fig._suptitle.get_text()
    import matplotlib.pyplot as plt

    plt.close(fig)


@pytest.mark.slow
def test_the_command_writes_one_figure_per_pounding_level(eq14, tmp_path, capsys):
    out = tmp_path / "pound.svg"
    assert main(["plot", str(eq14), "--kind", "pounding", "-o", str(out)]) == 0
    assert sorted(p.name for p in tmp_path.glob("pound-*.svg")) == [
        "pound-1.svg", "pound-2.svg", "pound-3.svg"]
    assert "3 figures" in capsys.readouterr().out


def test_a_scene_without_contacts_has_nothing_to_pound(tmp_path, capsys):
    scene = tmp_path / "single.yaml"
    scene.write_text("""\
title: one building
buildings:
  - {name: A, floors: 2, mass: 1000.0, story: {material: elastic, stiffness: 1.0e6}}
excitation: {kind: sine, amplitude: 1.0, frequency: 6.0}
analysis: {dt: 0.01, duration: 0.5}
recorders:
  - {kind: history, quantities: [displacement]}
""", encoding="utf-8")
    out = tmp_path / "single.nc"
    assert main(["solve", str(scene), "-o", str(out), "-q"]) == 0
    assert main(["plot", str(out), "--kind", "pounding", "-o", str(tmp_path / "f.png")]) == 2
    err = capsys.readouterr().err
    assert "nothing to plot for --kind pounding" in err and "no contacts" in err


@pytest.mark.slow
def test_a_coarse_history_that_misses_impacts_says_so(tmp_path):
    """Recorded every 200th step (32 ms), the history misses most of the 8.6 ms impacts:
    the panel does not pass its count off as the run's, it gives both."""
    import yaml

    scene = yaml.safe_load((REPO / "models" / "wu2021-eq14.yaml").read_text(encoding="utf-8"))
    scene["recorders"] = [{"kind": "history", "quantities": ["displacement", "contact_force"],
                           "every": 200}]
    path = tmp_path / "coarse.yaml"
    path.write_text(yaml.safe_dump(scene), encoding="utf-8")
    out = tmp_path / "coarse.nc"
    assert main(["solve", str(path), "-o", str(out), "-q"]) == 0
    ax = _axes(figures(out, kind="pounding", levels=["3"])["3"])["gap floor-3"]
    seen = len(_impact_times(ax))
    assert seen < 8
    assert ax.get_title(loc="left").endswith(f"{seen} impact{'s' if seen != 1 else ''} seen "
                                             "in the history; the run counted 8")
    # a time window counts its own impacts: no comparison with the whole run's
    window = figures(out, kind="pounding", levels=["3"], time_range=(0.0, 4.0))["3"]
    assert "the run counted" not in _axes(window)["gap floor-3"].get_title(loc="left")


@pytest.mark.slow
def test_a_window_without_impacts_keeps_its_panels(eq14):
    """A contact without impacts in the window drawn: before, its empty row of impact markers
    (unclipped) claimed the figure's corner and the layout collapsed ('constrained_layout not
    applied'), the panels squeezed to slivers."""
    import warnings

    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = figures(eq14, kind="pounding", levels=["3"], time_range=(0.0, 0.5))["3"]
    assert len(_impact_times(_axes(fig)["gap floor-3"])) == 0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        FigureCanvasAgg(fig).draw()
    assert min(ax.get_position().height for ax in fig.axes) > 0.25
