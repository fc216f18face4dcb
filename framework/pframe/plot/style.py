"""What every figure of a run shares: matplotlib (or why it is missing), the buildings' and
contacts' colours, the axes' look, and the heading that says what ran."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from pframe.errors import InputError

BUILDING_COLOURS = ("C0", "C3", "C2", "C1", "C4", "C5")
CONTACT_COLOURS = ("k", "C7", "C8", "C9")


def matplotlib_figure():
    """The :class:`~matplotlib.figure.Figure` class, or a clear error when matplotlib is absent."""
    try:
        from matplotlib.figure import Figure
    except ImportError:
        raise InputError(
            f"plot draws with matplotlib, which is not installed in this Python "
            f"({sys.executable}). Install pframe's plot extra into the same environment with "
            'pip install "pframe[plot]" (pip keeps the pframe you have and adds matplotlib; '
            'from a clone of the repository, pip install -e ".[plot]" does the same) and run '
            "the command again.") from None
    return Figure


def building_colour(result, building: str) -> str:
    """A building keeps its colour in every panel and figure, so left and right read alike."""
    return BUILDING_COLOURS[result.levels.buildings.index(building) % len(BUILDING_COLOURS)]


def on_common_time(drift, force, story: str):
    """Drift and force of one storey at the same times: the coarser of the two strides."""
    x, y = drift.column(story), force.column(story)
    if drift.time.shape == force.time.shape and np.array_equal(drift.time, force.time):
        return x, y
    if drift.time.size < force.time.size:
        return x, np.interp(drift.time, force.time, y)
    return np.interp(force.time, drift.time, x), y


def tidy(ax):
    ax.grid(True, alpha=0.3, linewidth=0.6)
    # keep tick labels short: forces in N reach 1e5 in the paper's example
    ax.ticklabel_format(axis="both", style="sci", scilimits=(-3, 4))
    ax.tick_params(labelsize=8)


def headed(fig, result, heading: str):
    """The figure with its title (the run stopped early, what ran) and, for a dimensionless
    run, its scales below."""
    if not result.complete:
        heading += " (run stopped early)"
    ran = what_ran(result)
    if ran:
        heading += f"\n{ran}"
    fig.suptitle(fitted(heading, fig.get_figwidth(), "large"), fontsize="large")
    if result.reference is not None:
        fig.supxlabel(f"dimensionless with {result.reference.describe()}", fontsize="x-small")
    return fig


def fitted(text: str, width: float, size) -> str:
    """``text`` with each of its lines broken between words where it would be wider than a
    figure ``width`` inches wide in a font of ``size`` (its width measured as matplotlib
    draws it): a long scene title is wrapped, not cut off at the figure's edges."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.textpath import TextToPath

    measure, font = TextToPath(), FontProperties(size=size)
    room = 0.95 * width * 72.0  # points

    def fits(line: str) -> bool:
        return measure.get_text_width_height_descent(line, font, ismath=False)[0] <= room

    out = []
    for line in text.split("\n"):
        current = ""
        for word in line.split(" "):
            trial = f"{current} {word}" if current else word
            if current and not fits(trial):
                out.append(current)
                trial = word
            current = trial
        out.append(current)
    return "\n".join(out)


def _number(value) -> str:
    return f"{value:.4g}" if isinstance(value, (int, float)) else str(value)


def _motion(excitation: dict) -> str | None:
    """An excitation as the scene gives it, in words (None: a kind not described)."""
    kind = excitation.get("kind")
    if kind == "record":
        text = f"record {Path(str(excitation.get('file', ''))).name}"
        if excitation.get("pga") is not None:
            text += f" scaled to PGA {_number(excitation['pga'])}"
        elif excitation.get("scale", 1) != 1:
            text += f" x {_number(excitation['scale'])}"
        return text
    if kind == "sine":
        return (f"sine, amplitude {_number(excitation.get('amplitude'))} m/s^2, "
                f"frequency {_number(excitation.get('frequency'))} rad/s")
    if kind in ("cycloidal", "ricker"):
        return (f"{kind} pulse, amplitude {_number(excitation.get('amplitude'))} m/s^2, "
                f"period {_number(excitation.get('period'))} s")
    if kind == "components":  # a motion along x and one along y, turned by angle
        parts = [f"{axis}: {_motion(excitation[axis])}" for axis in ("x", "y")
                 if isinstance(excitation.get(axis), dict) and _motion(excitation[axis])]
        angle = excitation.get("angle") or 0
        return "; ".join(parts) + (f" (turned {_number(angle)} deg)" if angle else "") \
            if parts else None
    return None


def what_ran(result) -> str:
    """One line saying what the run was, from the scene it holds: the excitation as given
    (a record's file name and scale, a sine's amplitude and frequency, a pulse, each of two
    components), and the verdict on its accuracy when it is not 'trusted'."""
    import yaml

    parts = []
    try:
        scene = yaml.safe_load(result.input_yaml) if result.input_yaml else None
    except yaml.YAMLError:
        scene = None
    excitation = scene.get("excitation") if isinstance(scene, dict) else None
    if isinstance(excitation, dict):
        text = _motion(excitation)
        if text:
            parts.append(text)
    elif isinstance(scene, dict) and "pi" not in scene and "buildings" in scene:
        parts.append("free vibration")
    accuracy = result.attributes.get("accuracy")
    if accuracy is not None:
        accuracy = accuracy.decode() if isinstance(accuracy, bytes) else str(accuracy)
        if accuracy != "trusted":
            parts.append(f"accuracy: {accuracy}")
    return "; ".join(parts)
