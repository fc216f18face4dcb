"""Every kind of figure pframe draws is fit for a report at its default size
(docs/plotting.md): each text lies inside the figure, no two texts overlap, each axis label
gives its units, and each axis spans its data (within a margin), not some range the data
never reach.

The kinds: a run's level figure (histories and loops), its gap-closing figure, the links
figure, a scene in plan's level and torsion figures, a sweep's response spectrum, the gap
audit's figure (one and two panels), and the risk study's fragility, hazard and gap
figures."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from pframe.cli import main  # noqa: E402

REPO = Path(__file__).resolve().parents[1]

#: the units an axis label may end with, in parentheses or brackets
UNITS = {"s", "m", "mm", "cm", "m/s", "mm/s", "m/s^2", "mm/s^2", "N", "kN", "MN", "g", "rad",
         "mrad", "rad/s", "mrad/s",
         "1/yr", "dimensionless", "N m", "kN m", "J", "kJ", "%"}
#: axis labels that count things rather than measure them (no units to give)
COUNTS = {"storey (the floor above it)"}


def _texts(fig):
    """(name, Text) of every text drawn: titles, axis and tick labels, offsets, legends,
    annotations; the figure's own titles and texts."""
    out = [(f"figure text {t.get_text()!r}", t) for t in fig.texts]
    for name in ("_suptitle", "_supxlabel", "_supylabel"):
        t = getattr(fig, name, None)
        if t is not None:
            out.append((name[1:], t))
    for k, ax in enumerate(fig.axes):
        if not ax.get_visible() or not ax.axison:
            continue
        where = f"axes {k} ({ax.get_title(loc='left') or ax.get_title()!r})"
        for what, t in (("title", ax.title), ("left title", ax._left_title),
                        ("right title", ax._right_title), ("xlabel", ax.xaxis.label),
                        ("ylabel", ax.yaxis.label), ("x offset", ax.xaxis.get_offset_text()),
                        ("y offset", ax.yaxis.get_offset_text())):
            out.append((f"{where} {what}", t))
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            for tick in axis.get_major_ticks():
                if lo - 1e-9 * abs(hi - lo) <= tick.get_loc() <= hi + 1e-9 * abs(hi - lo):
                    out.append((f"{where} tick {tick.label1.get_text()!r}", tick.label1))
        out += [(f"{where} text {t.get_text()!r}", t) for t in ax.texts]
    seen, unique = set(), []
    for n, t in out:  # the figure's texts hold its suptitle too
        if id(t) not in seen and t.get_visible() and t.get_text().strip():
            seen.add(id(t))
            unique.append((n, t))
    return unique


def _legends(fig):
    return [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + fig.legends


def check_layout(fig, name: str) -> None:
    """The four layout facts of the module docstring, for one figure."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    frame = fig.bbox
    boxes = [(n, t.get_window_extent(renderer)) for n, t in _texts(fig)]
    boxes += [(f"legend {k}", lg.get_window_extent(renderer))
              for k, lg in enumerate(_legends(fig))]
    for what, box in boxes:
        assert (frame.x0 - 0.5 <= box.x0 and box.x1 <= frame.x1 + 0.5
                and frame.y0 - 0.5 <= box.y0 and box.y1 <= frame.y1 + 0.5), \
            f"{name}: {what} is clipped by the figure's edge ({box} outside {frame})"
    for i, (a, box_a) in enumerate(boxes):
        for b, box_b in boxes[i + 1:]:
            inner = box_a.intersection(box_a, box_b)
            if inner is not None and inner.width > 1 and inner.height > 1:
                raise AssertionError(f"{name}: {a} overlaps {b}")
    for k, ax in enumerate(fig.axes):
        if ax.get_visible() and ax.axison:
            _check_axes(ax, f"{name}, axes {k} ({ax.get_title(loc='left') or ax.get_title()})")


def _check_axes(ax, where: str) -> None:
    for axis, label in (("x", ax.get_xlabel()), ("y", ax.get_ylabel())):
        if label:
            _check_units(label, f"{where} {axis} label")
    data = ax.dataLim
    for axis, (lo, hi), (d0, d1) in (("x", ax.get_xlim(), (data.x0, data.x1)),
                                     ("y", ax.get_ylim(), (data.y0, data.y1))):
        lo, hi = sorted((lo, hi))
        if not (np.isfinite(d0) and np.isfinite(d1)) or d1 <= d0:
            continue  # nothing drawn along it, or a flat line
        if (ax.get_xscale() if axis == "x" else ax.get_yscale()) == "log":
            d0 = max(d0, (ax.xaxis if axis == "x" else ax.yaxis).get_minpos())
            span, reach = np.log10(hi / lo), np.log10(d1 / d0)
            assert span <= reach + 1.0, \
                f"{where}: the {axis} axis spans {lo:g}-{hi:g}, the data {d0:g}-{d1:g}"
        else:
            reach = max(d1, 0.0) - min(d0, 0.0)  # an axis may start at 0 by design
            assert hi - lo <= 1.5 * reach, \
                f"{where}: the {axis} axis spans {lo:g}-{hi:g}, the data {d0:g}-{d1:g}"


def _check_units(label: str, where: str) -> None:
    text = label.replace("\n", " ").strip()
    if text in COUNTS or text.startswith("P(") or text.startswith("$"):
        return  # a count, a probability, or the paper's dimensionless symbol
    found = re.search(r"[(\[]([^()\[\]]+)[)\]]\s*$", text)
    # a power of ten before the units is the axis's scale ($10^{-3}$ m)
    units = re.sub(r"^\$10\^\{-?\d+\}\$\s*", "", found.group(1).strip()) if found else ""
    assert units in UNITS, \
        f"{where} {label!r} gives no units in parentheses or brackets"


# --------------------------------------------------------------------------------------------
# the figures
# --------------------------------------------------------------------------------------------

#: two buildings in plan, each symmetric about its x axis, shaken along x: along y and in
#: rotation they move by round-off only (about 1e-18 of x and less)
SYMMETRIC = """\
title: a symmetric pair in plan under x
buildings:
  - name: A
    floors: 2
    mass: 4.0e5
    plan: {size: [20.0, 12.0]}
    lines:
      - {name: X1, position: [0, 0], direction: x, material: elastic, stiffness: 1.2e8}
      - {name: X2, position: [0, 12], direction: x, material: elastic, stiffness: 1.2e8}
      - {name: Y1, position: [0, 0], direction: y, material: elastic, stiffness: 1.0e8}
      - {name: Y2, position: [20, 0], direction: y, material: elastic, stiffness: 1.0e8}
  - name: B
    floors: 2
    mass: 3.0e5
    origin: [20.1, -2.0]
    plan: {size: [16.0, 16.0]}
    lines:
      - {name: X1, position: [0, 0], direction: x, material: elastic, stiffness: 2.0e8}
      - {name: X2, position: [0, 16], direction: x, material: elastic, stiffness: 2.0e8}
      - {name: Y1, position: [0, 0], direction: y, material: elastic, stiffness: 2.0e8}
      - {name: Y2, position: [16, 0], direction: y, material: elastic, stiffness: 2.0e8}
damping: {ratio: 0.05, modes: [1, 3]}
excitation: {kind: sine, amplitude: 3.0, frequency: 6.0, cycles: 3}
analysis: {dt: 0.002, duration: 1.0}
recorders:
  - {kind: history, quantities: [displacement, velocity]}
"""

@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A run, a run with links, a run in plan, a sweep, two gap audits and a risk study."""
    from test_plot import SCENE as PLANAR
    from test_plot_plan import SCENE as PLAN
    from test_risk import pulse_study

    folder = tmp_path_factory.mktemp("layout")
    out = {}
    for name, text in (("run", PLANAR), ("plan", PLAN), ("symmetric", SYMMETRIC)):
        scene = folder / f"{name}.yaml"
        scene.write_text(text)
        out[name] = folder / f"{name}.nc"
        assert main(["solve", str(scene), "-o", str(out[name]), "-q"]) == 0
    links = (REPO / "models" / "damper-linked.yaml").read_text()
    scene = folder / "links.yaml"
    scene.write_text(re.sub(r"duration: [0-9.]+", "duration: 2.0", links))
    out["links"] = folder / "links.nc"
    assert main(["solve", str(scene), "-o", str(out["links"]), "-q"]) == 0
    sweep = folder / "sweep.yaml"
    # a dimensionless axis: its label says so
    sweep.write_text(f"base: {folder / 'run.yaml'}\naxes:\n  - {{name: restitution, path: "
                     "contacts.*.restitution, linspace: [0.3, 0.9, 4], units: '1'}\n")
    out["sweep"] = folder / "sweep.nc"
    assert main(["sweep", str(sweep), "-o", str(out["sweep"]), "-q"]) == 0
    pulse = str(REPO / "models" / "wu2021-pulse.yaml")
    out["gap"] = folder / "gap.nc"
    assert main(["gap", pulse, "--levels", "0.2,0.4,0.6,0.8,1.0", "-o", str(out["gap"]),
                 "-q"]) == 0
    out["gap2"] = folder / "gap2.nc"
    assert main(["gap", pulse, "--levels", "0.2,0.4,0.6,0.8,1.0", "--gap", "0.124",
                 "-o", str(out["gap2"]), "-q"]) == 0
    out["risk"] = folder / "risk.nc"
    assert main(["risk", str(pulse_study(folder)), "-o", str(out["risk"]), "-q"]) == 0
    return out


@pytest.mark.slow
def test_a_run_figures_fit(files):
    from pframe.plot import figures

    for kind in ("all", "pounding"):
        for level, fig in figures(files["run"], kind=kind).items():
            check_layout(fig, f"run {kind} level {level}")
    for level, fig in figures(files["links"], kind="links").items():
        check_layout(fig, f"links {level}")
    for level, fig in figures(files["plan"]).items():
        check_layout(fig, f"plan {level}")


@pytest.mark.slow
def test_round_off_panels_are_drawn_as_zero_saying_so(files):
    """A panel whose values are round-off (a symmetric scene's y and rotation) is drawn as
    zero with a note, not as noise on an axis of 1e-30 m; the panels of real motion are
    drawn as they are: x, and the turned pair struck at a corner's rotations and corners
    (its building A, symmetric about its own x, twists under the impacts at its corner, but
    its centre of mass does not move along y)."""
    import xarray as xr

    from pframe.plot import figures

    with xr.open_dataset(files["symmetric"]) as ds:
        x, y = np.abs(ds.displacement.values).max(axis=(0, 1))  # along x, along y
        assert 0 < y < 1e-15 * x  # the scene is what the test needs
    fig = figures(files["symmetric"])["1"]
    check_layout(fig, "symmetric plan")
    notes = {ax.get_label(): [t.get_text() for t in ax.texts] for ax in fig.axes}
    for quantity in ("displacement_y", "velocity_y", "displacement_rz", "velocity_rz"):
        ax = next(a for a in fig.axes if a.get_label() == quantity)
        assert len(notes[quantity]) == 1 and notes[quantity][0].startswith("0 to round-off"), \
            (quantity, notes[quantity])
        assert all(np.all(line.get_ydata() == 0) for line in ax.get_lines())
        assert "10^" not in ax.get_ylabel(), ax.get_ylabel()
    for quantity in ("displacement_x", "velocity_x"):
        assert notes[quantity] == [], (quantity, notes[quantity])
    for level, fig in figures(files["plan"]).items():
        for ax in fig.axes:
            if ax.get_label().startswith(("displacement_x", "velocity_x", "displacement_rz",
                                          "velocity_rz", "point_")):
                assert not ax.texts, (level, ax.get_label(), ax.texts[0].get_text())


@pytest.mark.slow
def test_sweep_and_gap_audit_figures_fit(files):
    from pframe.plot.gap import gap_figure
    from pframe.plot.spectrum import spectrum

    check_layout(spectrum(files["sweep"])[0], "sweep spectrum")
    for name in ("gap", "gap2"):
        fig, _ = gap_figure(files[name])
        check_layout(fig, name)
        assert fig._suptitle.get_text().startswith("Gap audit of wu2021-pulse.yaml")


@pytest.mark.slow
def test_risk_figures_fit_and_show_the_study_intensities(files):
    """The hazard panel spans the study's intensities (a factor 3 each side), not the whole
    tabulated curve (a power law here, tabulated from 1e-4 to 100 g); the rules at the
    target are named in the legend with their values, not in labels that overlap."""
    import xarray as xr

    from pframe.plot.risk import risk_figures

    figs = risk_figures(files["risk"])
    assert set(figs) == {"fragility", "hazard", "gap"}
    for name, fig in figs.items():
        check_layout(fig, f"risk {name}")
    with xr.open_dataset(files["risk"]) as ds:
        levels = ds.level.values
        assert ds.hazard_im.values.min() <= 1e-3 and ds.hazard_im.values.max() >= 10
        rules = dict(zip(ds.rule_name.values, 1000 * ds.rule_separation_at_target.values))
    low, high = figs["hazard"].axes[0].get_xlim()
    assert levels.min() / 10 <= low < levels.min() and levels.max() < high <= levels.max() * 10
    legend = [t.get_text() for t in figs["gap"].axes[0].get_legend().get_texts()]
    for rule, value in rules.items():
        assert f"{rule} at target IM {value:.1f} mm" in legend


@pytest.mark.slow
def test_a_subset_study_draws_its_probabilities_or_says_why_not(tmp_path, capsys):
    """One probability (a stationary motion): nothing to draw, said in one message (it was a
    traceback). Probabilities at stripes: against the intensity, with their intervals."""
    import xarray as xr
    import yaml

    from pframe.plot.risk import _stripe_figure

    study = tmp_path / "subset.yaml"
    study.write_text(yaml.safe_dump({
        "scene": str(REPO / "models" / "wu2021-pulse.yaml"), "dt": 0.005,
        "stochastic": {"model": "clough_penzien", "intensity": 0.05, "ground_frequency": 15.0,
                       "ground_damping": 0.6, "duration": 2.0, "step": 0.01},
        "design": {"kind": "subset", "samples": 100}, "pounding_runs": False}))
    out = tmp_path / "subset.nc"
    assert main(["risk", str(study), "-o", str(out), "-q", "--threads", "2"]) == 0
    capsys.readouterr()
    assert main(["plot", str(out), "-o", str(tmp_path / "subset.png")]) == 2
    err = capsys.readouterr().err
    assert "one probability of pounding" in err and "Traceback" not in err
    assert not list(tmp_path.glob("*.png"))
    levels = np.array([0.2, 0.4, 0.8])
    p = np.array([1e-6, 3.5e-3, 2.4e-2])
    ds = xr.Dataset({"level_probability": ("level", p),
                     "level_probability_low": ("level", p / 3),
                     "level_probability_high": ("level", p * 3)},
                    coords={"level": ("level", levels, {"units": "g"})},
                    attrs={"duration": 6.0, "measure": "PGA"})
    fig = _stripe_figure(ds)
    check_layout(fig, "subset stripes")
    x, y = fig.axes[0].lines[0].get_data()
    np.testing.assert_array_equal(x, levels)
    np.testing.assert_array_equal(y, p)
