"""The figure of a gap audit (``pframe gap``): the gap each rule asks for at each contact level,
beside the simulated critical gap and the provided gap; and, over an intensity axis, the
pounding fragility with its lognormal fit."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pframe.errors import InputError

#: marker and colour of each rule
STYLE = {"ABS": ("s", "tab:red"), "SRSS": ("D", "tab:orange"), "SRSS_EN_0.7": ("v", "tab:olive"),
         "DDC": ("^", "tab:green"), "simulated": ("o", "tab:blue")}
#: the code rules (and rules of the user's own), in their order in the file
MORE = [(m, c) for m, c in zip("PX*hp<>d8H", ("tab:purple", "tab:brown", "tab:pink", "tab:gray",
                                              "tab:cyan", "k", "tab:olive", "darkblue",
                                              "darkred", "darkgreen"))]


#: records below which a fitted fragility dispersion is flagged as rough
FEW_RECORDS = 10


def gap_figure(path: str | Path, statistic: str = "p84", level: float | None = None):
    """The report figure: gap needed against contact level (one marker per rule, the
    ``statistic`` over the records, whiskers from the median to the maximum), the provided
    gap as a line; a second panel with the fragility when the file has several levels and a
    provided gap. Returns (figure, notes)."""
    import matplotlib.pyplot as plt

    from pframe.api import open as open_result

    with open_result(path) as opened:
        ds = opened.load()
    if statistic not in ds.statistic_name.values:
        raise InputError(f"--statistic {statistic}: one of {', '.join(ds.statistic_name.values)}")
    levels = ds.level.values
    if level is None:
        index = len(levels) - 1
    else:
        index = int(np.argmin(np.abs(levels - level)))
    at = float(levels[index])
    fragility = "provided_gap" in ds and len(levels) > 1
    fig, axes = plt.subplots(1, 2 if fragility else 1, figsize=(11 if fragility else 6.5, 4.8),
                             squeeze=False, layout="constrained")
    ax = axes[0, 0]
    floors = ds.floor.values.astype(float)
    rules = [str(r) for r in ds.rule_name.values]
    offsets = np.linspace(-0.18, 0.18, len(rules))
    stats = ds.gap_statistics.isel(level=index)
    others = [r for r in rules if r not in STYLE]
    for rule, dy in zip(rules, offsets):
        marker, colour = STYLE.get(rule) or MORE[others.index(rule) % len(MORE)]
        value = 1000 * stats.sel(statistic_name=statistic, rule_name=rule).values
        low = 1000 * stats.sel(statistic_name="median", rule_name=rule).values
        high = 1000 * stats.sel(statistic_name="max", rule_name=rule).values
        ax.errorbar(value, floors + dy, xerr=[np.maximum(value - low, 0), np.maximum(high - value, 0)],
                    fmt=marker, color=colour, capsize=3, ms=7,
                    label=rule + (" (g_req)" if rule == "simulated" else ""))
    if "provided_gap" in ds:
        ax.axvline(1000 * float(ds.provided_gap), color="k", ls="--", lw=1.2,
                   label=f"provided gap {1000 * float(ds.provided_gap):.0f} mm")
    ax.set_yticks(floors, [f"{c}\n(floor {int(f)})" for c, f in zip(ds.contact_name.values, floors)])
    ax.set_xlabel("separation needed (mm)")
    ax.set_xlim(left=0)
    from pframe.record.netcdf import short_units

    units = short_units(ds.level.attrs.get("units", ""))
    what = (f"{ds.level.attrs.get('long_name', 'level')} = {at:g} {units}" if units == "g"
            else "records as given")
    count = ds.sizes["record"]
    heading = (f"{statistic} of {count} records (whiskers: median to max)" if count > 1
               else f"record {ds.record_name.values[0]}")
    ax.set_title(f"{heading}\n{what}", fontsize=10)
    ax.grid(True, axis="x", alpha=0.3)
    ax.legend(fontsize=8, loc="best", framealpha=0.9)
    notes = [f"{statistic} at level {at:g}" if units == "g" else f"{statistic}, records as given"]
    if fragility:
        ax2 = axes[0, 1]
        from pframe.gap.fragility import lognormal_probability

        ax2.plot(levels, ds.pounding_fraction_any.values, "ko", label="fraction of records "
                 "pounding (any contact)")
        median, beta = float(ds.fragility_median_any), float(ds.fragility_dispersion_any)
        if np.isfinite(median) and np.isfinite(beta):
            x = np.linspace(0, levels.max() * 1.3, 200)[1:]
            label = f"lognormal fit: median {median:.3g} {units}, dispersion {beta:.2f}"
            if count < FEW_RECORDS:
                caveat = (f"from {count} record{'s' if count > 1 else ''}: a rough estimate "
                          f"(use {FEW_RECORDS} or more)")
                label += f"\n{caveat}"
                notes.append(f"fragility {caveat}")
            ax2.plot(x, lognormal_probability(x, median, beta), "k-", label=label)
        else:
            notes.append("fragility not fitted")
        ax2.set_xlabel(f"{ds.attrs.get('measure', 'IM')} ({units})")
        ax2.set_ylabel(f"P(g_req > {1000 * float(ds.provided_gap):.0f} mm | IM)")
        ax2.set_ylim(-0.03, 1.03)
        ax2.set_xlim(left=0)
        ax2.grid(True, alpha=0.3)
        ax2.legend(fontsize=8, loc="upper left")
        ax2.set_title("pounding fragility", fontsize=10)
    from pframe.plot.style import fitted

    fig.suptitle(fitted(audit_title(ds), fig.get_figwidth(), 11), fontsize=11)
    return fig, notes


def audit_title(ds) -> str:
    """What the audit ran, for the figure's title: the scene's file, the records and the
    levels (not the scene's own title, which may describe another excitation or scaling)."""
    source = Path(str(ds.attrs.get("source", "the scene"))).name
    count = ds.sizes.get("record", 0)
    records = (f"record {ds.record_name.values[0]}" if count == 1
               else f"{count} records of {Path(str(ds.attrs.get('suite', ''))).name or 'a suite'}")
    from pframe.record.netcdf import short_units

    levels = ds.level.values
    units = short_units(ds.level.attrs.get("units", ""))
    if units == "g":
        scaled = (f"scaled to {ds.attrs.get('measure', 'IM')} = "
                  + ", ".join(f"{v:g}" for v in levels) + " g")
    else:
        scaled = "as given"
    return f"Gap audit of {source}: {records}, {scaled}"
