"""``pframe plot`` of a scene in plan (docs/plotting.md#buildings-in-plan): the figures hold
the file's histories per direction, the gap-closing panel is the closing of the contact's
points along its normal (checked against the small-rotation kinematics written here and the
linear contact law's force), the torsion figure holds the file's ratios against the limits of
ASCE 7-22 Table 12.3-1, nothing is clipped or overlaps, and a file lacking what a figure needs
is refused naming what to record."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from pframe.cli import main  # noqa: E402
from pframe.irregularity import TORSIONAL_IRREGULARITY  # noqa: E402
from pframe.plot import figures, read_result  # noqa: E402

#: building B turned 30 degrees, its north-west corner GAP east of A's point (20, 9)
GAP, STIFFNESS, ANGLE = 0.02, 2.0e9, 30.0
ORIGIN_B = (20.0 + GAP + 16.0 * math.sin(math.radians(ANGLE)),
            9.0 - 16.0 * math.cos(math.radians(ANGLE)))
SCENE = f"""\
title: plan test, a turned building struck at a corner
buildings:
  - name: A
    floors: 3
    mass: 4.0e5
    height: 3.5
    plan: {{size: [20.0, 12.0]}}
    lines:
      - {{name: X1, position: [0, 0], direction: x, material: bilinear, stiffness: 1.2e8,
          yield_drift: 0.02, alpha: 0.05}}
      - {{name: X2, position: [0, 12], direction: x, material: bilinear, stiffness: 1.2e8,
          yield_drift: 0.02, alpha: 0.05}}
      - {{name: Y1, position: [0, 0], direction: y, material: bilinear, stiffness: 1.0e8,
          yield_drift: 0.02, alpha: 0.05}}
      - {{name: Y2, position: [20, 0], direction: y, material: bilinear, stiffness: 1.0e8,
          yield_drift: 0.02, alpha: 0.05}}
  - name: B
    floors: 2
    mass: 3.0e5
    height: 3.5
    origin: [{ORIGIN_B[0]!r}, {ORIGIN_B[1]!r}]
    angle: {ANGLE}
    plan: {{size: [16.0, 16.0]}}
    centre_of_mass: [9.0, 8.0]
    lines:
      - {{name: X1, position: [0, 0], direction: x, material: elastic, stiffness: 2.0e8}}
      - {{name: X2, position: [0, 16], direction: x, material: elastic, stiffness: 2.0e8}}
      - {{name: Y1, position: [0, 0], direction: y, material: elastic, stiffness: 2.0e8}}
      - {{name: Y2, position: [16, 0], direction: y, material: elastic, stiffness: 2.0e8}}
contacts:
  - {{name: c1, nodes: [A/1, B/1], points: [[20, 9], NW], normal: [1, 0], gap: {GAP},
     law: linear, stiffness: {STIFFNESS}}}
  - {{name: c2, nodes: [A/2, B/2], points: [[20, 9], NW], normal: [1, 0], gap: {GAP},
     law: linear, stiffness: {STIFFNESS}}}
damping: {{ratio: 0.05, modes: [1, 3]}}
excitation: {{kind: sine, amplitude: 3.0, frequency: 6.0, cycles: 3}}
analysis: {{dt: 0.002, duration: 3.0}}
recorders:
  - {{kind: history, quantities: [displacement, velocity, story_drift, story_force,
                                  contact_force, point_displacement, point_drift]}}
"""


def solved(folder, text, name="plan"):
    scene = folder / f"{name}.yaml"
    scene.write_text(text, encoding="utf-8")
    out = folder / f"{name}.nc"
    assert main(["solve", str(scene), "-o", str(out), "-q"]) == 0
    return out


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    return solved(tmp_path_factory.mktemp("plot-plan"), SCENE)


def read(path):
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        return ds.load()


def axes_by_label(fig):
    return {ax.get_label(): ax for ax in fig.axes}


def lines_by_label(ax):
    return {line.get_label(): line for line in ax.get_lines()}


def names(ds, entity):
    return [str(v) for v in ds[f"{entity}_name"].values]


@pytest.mark.slow
def test_a_file_in_plan_is_read_per_direction_not_refused_as_a_sweep(result_file):
    """Before: 'the file holds a sweep (displacement has the dimensions t, node,
    direction)'. Each component is a history of its own, the rotation another."""
    ds, result = read(result_file), read_result(result_file)
    assert result.plan
    nodes, points = names(ds, "node"), names(ds, "point")
    for k, axis in enumerate("xy"):
        h = result.histories[f"displacement_{axis}"]
        assert h.names == tuple(nodes) and h.units == "m"
        np.testing.assert_array_equal(h.values, ds.displacement.values[:, :, k])
        np.testing.assert_array_equal(result.histories[f"velocity_{axis}"].values,
                                      ds.velocity.values[:, :, k])
        h = result.histories[f"point_drift_{axis}"]
        assert h.names == tuple(points)
        np.testing.assert_array_equal(h.values, ds.point_drift.values[:, :, k])
    rotation = result.histories["displacement_rz"]
    assert rotation.units == "rad"
    np.testing.assert_array_equal(rotation.values, ds.displacement_rz.values)
    assert result.torsion == {n: tuple(r) for n, r in
                              zip(nodes, ds.torsional_irregularity.values.tolist())}
    # every line of resistance of a storey is at its level, not the last one only
    assert result.levels.lines["2"] == {"A": ["A/2/X1", "A/2/X2", "A/2/Y1", "A/2/Y2"],
                                        "B": ["B/2/X1", "B/2/X2", "B/2/Y1", "B/2/Y2"]}


def small_rotation_closing(ds, left: str, right: str):
    """n . (u_P - u_Q) of A's point P = (20, 9) and B's north-west corner Q along n = (1, 0),
    each point moving as u_P = (u_x - theta (P_y - c_y), u_y + theta (P_x - c_x)) about its
    floor's centre of mass c (docs/plan.md), from the geometry written in this file."""
    turn = math.radians(ANGLE)
    corner = (ORIGIN_B[0] - 16.0 * math.sin(turn), ORIGIN_B[1] + 16.0 * math.cos(turn))
    centre_b = (ORIGIN_B[0] + 9.0 * math.cos(turn) - 8.0 * math.sin(turn),
                ORIGIN_B[1] + 9.0 * math.sin(turn) + 8.0 * math.cos(turn))
    nodes = names(ds, "node")
    assert corner == pytest.approx((20.0 + GAP, 9.0), abs=1e-12)
    assert ds.node_x.values[nodes.index(right)] == pytest.approx(centre_b[0], abs=1e-9)
    closing = 0.0
    for node, point, centre, sign in ((left, (20.0, 9.0), (10.0, 6.0), 1.0),
                                      (right, corner, centre_b, -1.0)):
        i = nodes.index(node)
        u_x, theta = ds.displacement.values[:, i, 0], ds.displacement_rz.values[:, i]
        closing = closing + sign * (u_x - theta * (point[1] - centre[1]))
    return closing


@pytest.mark.slow
def test_the_gap_closing_is_the_points_along_the_normal(result_file):
    """The pounding figure of a contact in plan draws the closing of its two points along its
    normal: the kinematics of the plan written out here, and what the kernel's linear contact
    pushed with (F = k (closing - gap) while closed)."""
    ds = read(result_file)
    fig = figures(result_file, kind="pounding", levels=[2])["2"]
    ax = axes_by_label(fig)["gap c2"]
    drawn = lines_by_label(ax)
    closing = small_rotation_closing(ds, "A/2", "B/2")
    np.testing.assert_allclose(drawn["relative"].get_ydata(), closing, rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(drawn["relative"].get_xdata(), ds.t.values)
    assert drawn["gap"].get_ydata()[0] == GAP
    force = ds.contact_force.values[:, names(ds, "contact").index("c2")]
    np.testing.assert_allclose(force, STIFFNESS * np.maximum(closing - GAP, 0.0),
                               rtol=1e-9, atol=1e-3)
    impacts = int(ds.impact_count.values[1])
    assert impacts > 0, "the scene must pound at level 2"
    assert ax.get_title(loc="left").endswith(f"{impacts} impacts")  # every step recorded: all seen


@pytest.mark.slow
def test_the_level_figure_holds_the_file_in_both_directions(result_file):
    ds = read(result_file)
    nodes, stories, points = names(ds, "node"), names(ds, "story"), names(ds, "point")
    fig = figures(result_file, levels=[2])["2"]
    panels = axes_by_label(fig)
    assert set(panels) == {
        "displacement_x", "displacement_y", "velocity_x", "velocity_y",
        "point_displacement_x", "point_displacement_y", "point_drift_x", "point_drift_y",
        "displacement_rz", "velocity_rz", "contact_force", "story_drift A/2/X1",
        "story_drift B/2/X1", *(f"hysteresis {s}" for s in stories if "/2/" in s)}
    for k, axis in enumerate("xy"):
        for quantity in ("displacement", "velocity"):
            lines = lines_by_label(panels[f"{quantity}_{axis}"])
            assert set(lines) == {"A/2", "B/2"}
            for node, line in lines.items():
                np.testing.assert_array_equal(line.get_xdata(), ds.t.values)
                np.testing.assert_array_equal(line.get_ydata(),
                                              ds[quantity].values[:, nodes.index(node), k])
        lines = lines_by_label(panels[f"point_drift_{axis}"])
        assert set(lines) == {p for p in points if p.split(":")[0] in ("A/2", "B/2")}
        for point, line in lines.items():
            np.testing.assert_array_equal(line.get_ydata(),
                                          ds.point_drift.values[:, points.index(point), k])
    rotation = lines_by_label(panels["displacement_rz"])["B/2"]
    np.testing.assert_array_equal(rotation.get_ydata(),
                                  ds.displacement_rz.values[:, nodes.index("B/2")])
    force = lines_by_label(panels["contact_force"])
    assert set(force) == {"c2"}  # c1 joins the floors of level 1
    drift = lines_by_label(panels["story_drift A/2/X1"])
    assert set(drift) == {"X1", "X2", "Y1", "Y2"}
    np.testing.assert_array_equal(drift["Y2"].get_ydata(),
                                  ds.story_drift.values[:, stories.index("A/2/Y2")])
    loop = panels["hysteresis B/2/Y1"].get_lines()[0]
    np.testing.assert_array_equal(loop.get_xdata(),
                                  ds.story_drift.values[:, stories.index("B/2/Y1")])
    np.testing.assert_array_equal(loop.get_ydata(),
                                  ds.story_force.values[:, stories.index("B/2/Y1")])
    # units on every axis; values beyond 1e-3 .. 1e4 in a prefixed unit, no offset above
    assert panels["displacement_x"].get_ylabel() == "displacement along x (m)"
    assert panels["contact_force"].get_ylabel() == "pounding force (MN)"
    assert panels["displacement_rz"].get_ylabel() == "floor rotation (mrad)"
    assert panels["hysteresis B/2/Y1"].get_xlabel() == "drift along the line (mm)"
    for ax in fig.axes:
        for label in (ax.get_ylabel(), ax.get_xlabel() or "shared time (s)"):
            assert re.search(r" \(\S.*\)$", label), f"{ax.get_label()}: {label!r}"
    assert panels["story_drift B/2/X1"].get_xlabel() == "time (s)"


def text_boxes(fig):
    """The window extents of the texts of a figure drawn at its default size, and of each
    axes with its decorations: (label, box)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    out = [("suptitle", fig._suptitle.get_window_extent(renderer))]
    for ax in fig.axes:
        name = ax.get_label()
        for what, text in (("title", ax.title), ("left title", ax._left_title),
                           ("ylabel", ax.yaxis.label), ("xlabel", ax.xaxis.label)):
            if text.get_text():
                out.append((f"{name} {what}", text.get_window_extent(renderer)))
        if ax.get_legend() is not None:
            out.append((f"{name} legend", ax.get_legend().get_window_extent(renderer)))
        # the axes with what it draws around it (tick labels, titles, legend)
        out.append((f"{name} whole", ax.get_tightbbox(renderer, bbox_extra_artists=[])))
        offset = ax.yaxis.get_offset_text()
        if offset.get_text():
            out.append((f"{name} offset", offset.get_window_extent(renderer)))
    for legend in fig.legends:
        out.append(("figure legend", legend.get_window_extent(renderer)))
    return out, fig.bbox


def assert_nothing_clipped_or_overlapping(fig):
    boxes, frame = text_boxes(fig)
    for name, box in boxes:
        assert frame.x0 - 0.5 <= box.x0 and box.x1 <= frame.x1 + 0.5, f"{name} clipped"
        assert frame.y0 - 0.5 <= box.y0 and box.y1 <= frame.y1 + 0.5, f"{name} clipped"
    big = [(n, b) for n, b in boxes if not n.endswith("whole")]
    for i, (a, box_a) in enumerate(big):
        for b, box_b in big[i + 1:]:
            assert not box_a.overlaps(box_b), f"{a} overlaps {b}"


@pytest.mark.slow
def test_nothing_is_clipped_or_overlaps_at_the_default_size(result_file):
    """Every title, legend and axis label of the figures in plan lies inside the figure and
    clear of the others (the points' legends have a row of their own)."""
    figs = figures(result_file)
    assert list(figs) == ["1", "2", "3", "torsion"]
    for fig in figs.values():
        assert_nothing_clipped_or_overlapping(fig)
    pounding = figures(result_file, kind="pounding")
    assert list(pounding) == ["1", "2"]
    for fig in pounding.values():
        assert_nothing_clipped_or_overlapping(fig)


@pytest.mark.slow
def test_the_torsion_figure_holds_the_ratios_against_the_code_limits(result_file):
    ds = read(result_file)
    nodes = names(ds, "node")
    fig = figures(result_file, kind="torsion")["torsion"]
    panels = axes_by_label(fig)
    assert set(panels) == {"torsion A", "torsion B"}
    for building, floors in (("A", 3), ("B", 2)):
        ax = panels[f"torsion {building}"]
        lines = lines_by_label(ax)
        limits = sorted(float(line.get_xdata()[0]) for name, line in lines.items()
                        if name.startswith("1."))
        assert limits == list(TORSIONAL_IRREGULARITY) == [1.2, 1.4]
        rows = [nodes.index(f"{building}/{k}") for k in range(1, floors + 1)]
        for k, axis in enumerate("xy"):
            line = lines[f"along the building's {axis}"]
            np.testing.assert_array_equal(line.get_xdata(),
                                          ds.torsional_irregularity.values[rows, k])
            np.testing.assert_array_equal(line.get_ydata(), np.arange(1, floors + 1))
        assert [t.get_text() for t in ax.get_yticklabels()] == [str(k) for k in
                                                                range(1, floors + 1)]
        assert ax.get_xlim()[1] > 1.4
    assert "ASCE 7-22 Table 12.3-1" in " ".join(fig.get_suptitle().split())


@pytest.mark.slow
def test_units_and_dimensionless_in_plan(result_file):
    """--units converts every length (the closing and its gap with it), --dimensionless
    divides lengths by l_e and keeps the rotation (already dimensionless)."""
    ds = read(result_file)
    nodes = names(ds, "node")
    panels = axes_by_label(figures(result_file, levels=[2], units="engineering")["2"])
    line = lines_by_label(panels["displacement_y"])["B/2"]
    np.testing.assert_allclose(line.get_ydata(),
                               1e3 * ds.displacement.values[:, nodes.index("B/2"), 1],
                               rtol=1e-12)
    gap = axes_by_label(figures(result_file, levels=[2], units="mm", kind="pounding")["2"])
    assert lines_by_label(gap["gap c2"])["gap"].get_ydata()[0] == pytest.approx(1e3 * GAP)
    l_e = 3.0 / 6.0**2
    panels = axes_by_label(figures(result_file, levels=[2], dimensionless=True)["2"])
    line = lines_by_label(panels["displacement_x"])["A/2"]
    np.testing.assert_allclose(line.get_ydata(),
                               ds.displacement.values[:, nodes.index("A/2"), 0] / l_e,
                               rtol=1e-12)
    rotation = lines_by_label(panels["displacement_rz"])["A/2"]
    np.testing.assert_array_equal(rotation.get_ydata(),
                                  ds.displacement_rz.values[:, nodes.index("A/2")])
    assert panels["displacement_rz"].get_ylabel().startswith(r"$\theta$")


@pytest.mark.slow
def test_the_command_writes_levels_and_torsion(result_file, tmp_path, capsys):
    out = tmp_path / "fig.png"
    assert main(["plot", str(result_file), "-o", str(out)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "fig-1.png", "fig-2.png", "fig-3.png", "fig-torsion.png"]
    assert "4 figures (levels 1, 2, 3 and torsion)" in capsys.readouterr().out
    assert main(["plot", str(result_file), "--kind", "torsion", "--story", "2"]) == 2
    assert "leave out --story" in capsys.readouterr().err


ENVELOPES_ONLY = SCENE.split("recorders:")[0] + """recorders:
  - {kind: envelope, quantities: [displacement]}
"""
WITHOUT_PLAN = """\
buildings:
  - name: A
    floors: 1
    mass: 1.0e5
    centre_of_mass: [6.5, 5.0]
    polar_inertia: 1.7e6
    lines:
      - {name: X1, position: [0, 0], direction: x, material: elastic, stiffness: 4.0e7}
      - {name: X2, position: [0, 10], direction: x, material: elastic, stiffness: 4.0e7}
      - {name: Y1, position: [0, 0], direction: y, material: elastic, stiffness: 3.0e7}
      - {name: Y2, position: [10, 0], direction: y, material: elastic, stiffness: 3.0e7}
damping: {ratio: 0.0}
initial_conditions:
  displacement: {A/1: [0.0, 0.01, 0.0]}
analysis: {dt: 0.001, duration: 0.2}
recorders:
  - {kind: history, quantities: [displacement]}
"""


@pytest.mark.slow
@pytest.mark.parametrize(("text", "args", "message"), [
    (ENVELOPES_ONLY, ["--kind", "histories"], "nothing to plot for --kind histories: the "
     "file has no displacement "
     "history"),
    (ENVELOPES_ONLY, ["--kind", "histories"], "point_displacement and point_drift): list them "
     "in a recorder of "
     "kind history"),
    (WITHOUT_PLAN, ["--kind", "torsion"], "the file has no torsional_irregularity: pframe "
     "solve writes it from the peak point_drift at each floor's named points, which a "
     "building has when it has a plan"),
    (ENVELOPES_ONLY, ["--kind", "pounding"], "the file has no displacement history: no "
     "gap-closing panels"),
], ids=["no-histories", "what-to-record", "no-plan-no-torsion", "no-closing"])
def test_a_file_lacking_what_a_figure_needs_is_refused(tmp_path, capsys, text, args, message):
    path = solved(tmp_path, text, "lacking")
    out = tmp_path / "fig.pdf"
    assert main(["plot", str(path), "-o", str(out), *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"pframe: {path}: ") and message in err
    assert "Traceback" not in err and err.count("\n") == 1
    assert not out.exists()


@pytest.mark.slow
def test_torsion_of_a_planar_result_is_refused(tmp_path, capsys):
    from conftest import REPO

    path = tmp_path / "eq14.nc"
    assert main(["solve", str(REPO / "models" / "wu2021-eq14.yaml"), "-o", str(path),
                 "-q"]) == 0
    assert main(["plot", str(path), "--kind", "torsion"]) == 2
    assert "this result's scene is planar" in capsys.readouterr().err


@pytest.mark.slow
def test_from_python_on_a_dataset(result_file):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import pframe

    with pframe.open(result_file) as ds:
        fig = pframe.plot(ds, level=2)
        assert "displacement_y" in axes_by_label(fig)
        ax = pframe.plot(ds, "displacement_rz", names=["B/2"])
        np.testing.assert_array_equal(ax.get_lines()[0].get_ydata(),
                                      ds.displacement_rz.sel(node="B/2").values)
        torsion = pframe.plot(ds, kind="torsion")
        assert set(axes_by_label(torsion)) == {"torsion A", "torsion B"}
    plt.close("all")


def test_the_heading_names_both_components_of_the_motion():
    """A motion in components (docs/plan.md) is said as the scene gives it; before, the
    heading said nothing of it."""
    from types import SimpleNamespace

    from pframe.plot.style import what_ran

    scene = ("excitation: {kind: components, angle: 30, x: {kind: record, file: "
             "records/RSN6_IMPVALL.I_I-ELC180.AT2, scale: 1.5}, y: {kind: sine, amplitude: 1, "
             "frequency: 2}}")
    assert what_ran(SimpleNamespace(input_yaml=scene, attributes={})) == (
        "x: record RSN6_IMPVALL.I_I-ELC180.AT2 x 1.5; y: sine, amplitude 1 m/s^2, frequency "
        "2 rad/s (turned 30 deg)")


@pytest.mark.slow
def test_a_long_title_is_wrapped_not_cut_off(result_file):
    """Before, the title of models/corner-pounding.yaml ran off both edges of the pounding
    figure (8 inches wide)."""
    from dataclasses import replace

    from pframe.plot import prepare

    long = replace(prepare(result_file), title="Corner pounding of a building turned 20 "
                   "degrees against an eccentric frame")
    for kind in ("pounding", "torsion"):
        for fig in figures(long, kind=kind).values():
            assert_nothing_clipped_or_overlapping(fig)
            assert fig.get_suptitle().startswith("Corner pounding of a building")
