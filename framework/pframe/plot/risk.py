"""The figure set of a risk study (``pframe risk``): the fitted fragilities, the hazard curve
with each limit state's mean annual frequency, and the annual frequency of pounding against
the gap with the gap at the target."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.stats import norm

from pframe.plot.gap import STYLE
from pframe.record.netcdf import short_units

#: how far the hazard panel reaches beyond the study's intensities (a factor each side)
IM_MARGIN = 3.0


def risk_figures(path: str | Path) -> dict:
    """{"fragility": fig, "hazard": fig, "gap": fig} (the last two when the file has them)."""
    from pframe.api import open as open_result

    with open_result(path) as opened:
        ds = opened.load()
    if "limit_name" not in ds:  # subset simulation: probabilities, no fragilities
        if "level_probability" not in ds or ds.sizes.get("level", 0) < 2:
            from pframe.errors import InputError

            raise InputError(f"{path}: a subset simulation's result is one probability of "
                             "pounding (pframe risk printed it, with its interval): there is "
                             "no curve to draw; a subset study over records at two or more "
                             "levels draws its probability against the intensity")
        out = {"probability": _stripe_figure(ds)}
    else:
        out = {"fragility": _fragility_figure(ds)}
    if "hazard_frequency" in ds:
        out["hazard"] = _hazard_figure(ds)
    if "pounding_frequency" in ds:
        out["gap"] = _gap_figure(ds)
    return out


def _measure(ds) -> str:
    return f"{ds.attrs.get('measure', 'IM')} (g)"


def _intensities(ds) -> np.ndarray:
    """The intensities the study's runs reached (g): its levels, or each run's IM."""
    im = np.asarray(ds.intensity.values if "intensity" in ds else ds.level.values, float)
    return im[np.isfinite(im) & (im > 0)]


def _stripe_figure(ds):
    """A subset study over records: the probability of pounding at each level with its 95 %
    interval."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4.5), layout="constrained")
    x, p = ds.level.values, ds.level_probability.values
    low, high = ds.level_probability_low.values, ds.level_probability_high.values
    shown = p > 0
    ax.errorbar(x[shown], p[shown], yerr=[(p - low)[shown], (high - p)[shown]], fmt="o-",
                capsize=3, label="subset simulation (95 %)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(_measure(ds))
    ax.set_ylabel("P(pounding | IM)")
    ax.set_title(f"probability of pounding within {float(ds.attrs.get('duration', 0)):.3g} s")
    ax.legend(fontsize=8)
    return fig


def _fragility_figure(ds):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4.5), layout="constrained")
    im = _intensities(ds)
    x = np.geomspace(max(im.min() / IM_MARGIN, 1e-3), im.max() * 2, 300)
    styles = {"without_pounding": "-", "with_pounding": "--"}
    for k, limit in enumerate(ds.limit_name.values):
        for cond in ds.condition_name.values:
            sel = {"limit_name": limit, "condition_name": cond}
            m, b = float(ds.fragility_median.sel(sel)), float(ds.fragility_dispersion.sel(sel))
            if not (np.isfinite(m) and np.isfinite(b)):
                continue
            ax.plot(x, norm.cdf(np.log(x / m) / b), styles.get(str(cond), "-"), color=f"C{k}",
                    label=f"{limit}, {str(cond).replace('_', ' ')}")
    ax.set_xscale("log")
    ax.set_xlabel(_measure(ds))
    ax.set_ylabel("P(limit state | IM)")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)
    else:
        ax.text(0.5, 0.5, "no fragility fitted (see the file's warnings)", ha="center",
                transform=ax.transAxes)
    ax.set_title(f"fragilities ({ds.attrs.get('design', '')}, maximum likelihood)")
    return fig


def _hazard_figure(ds):
    """The hazard curve over the study's intensities (a table or a power law may reach far
    beyond them: 1e-4 to 100 g), its levels marked; each limit state's annual frequency."""
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
    hazard_im, rate = ds.hazard_im.values, ds.hazard_frequency.values
    im = _intensities(ds)
    if "intensity_at_target" in ds and np.isfinite(float(ds.intensity_at_target)):
        im = np.append(im, float(ds.intensity_at_target))
    low = max(im.min() / IM_MARGIN, hazard_im.min())
    high = min(im.max() * IM_MARGIN, hazard_im.max())
    shown = (hazard_im >= low) & (hazard_im <= high) & (rate > 0)
    a1.loglog(hazard_im[shown], rate[shown], "k-", label="hazard curve")
    levels = (np.unique(np.asarray(ds.level.values, float))
              if short_units(ds.level.attrs.get("units", "")) == "g" else np.array([]))
    if levels.size:
        a1.loglog(levels, np.interp(np.log(levels), np.log(hazard_im), rate), "o",
                  color="C0", ms=4, label="the study's levels")
    if "intensity_at_target" in ds and np.isfinite(float(ds.intensity_at_target)):
        a1.plot([float(ds.intensity_at_target)], [float(ds.target_annual_frequency)], "s",
                color="tab:red", ms=6, label="target")
    a1.set_xlim(low, high)
    a1.set_xlabel(_measure(ds))
    a1.set_ylabel("annual frequency of exceedance (1/yr)")
    a1.set_title("hazard curve over the study's intensities")
    a1.legend(fontsize=8)
    if "annual_frequency" in ds and "limit_name" in ds:
        _frequency_bars(ds, a2)
    elif "annual_frequency" in ds:  # subset over records: pounding only
        value = float(ds.annual_frequency)
        a2.bar([0], [value], color="tab:blue")
        a2.errorbar([0], [value], yerr=[[value - float(ds.annual_frequency_low)],
                                        [float(ds.annual_frequency_high) - value]],
                    fmt="none", ecolor="k", capsize=3)
        a2.set_yscale("log")
        a2.set_xticks([0], ["pounding"])
        a2.set_xlim(-1, 1)
        a2.set_ylabel("mean annual frequency (1/yr)")
        a2.set_title("annual frequency of pounding (95 %)")
    else:
        a2.set_axis_off()
        a2.text(0.5, 0.5, "no fragility fitted: no mean annual frequency",
                ha="center", transform=a2.transAxes)
    return fig


def _frequency_bars(ds, ax) -> None:
    """Each limit state's mean annual frequency (bars) with its 5-95 % range; a limit state
    without a fit is marked so, not left blank."""
    names = [f"{lim}\n{c.split('_')[0]}" for lim in ds.limit_name.values
             for c in ds.condition_name.values]
    value = ds.annual_frequency.values.ravel()
    low = ds.annual_frequency_low.values.ravel()
    high = ds.annual_frequency_high.values.ravel()
    pos = np.arange(value.size)
    fitted = np.isfinite(value) & (value > 0)
    ax.bar(pos[fitted], value[fitted], color="tab:blue")
    ax.errorbar(pos[fitted], value[fitted], yerr=[np.nan_to_num(value - low)[fitted],
                                                  np.nan_to_num(high - value)[fitted]],
                fmt="none", ecolor="k", capsize=3)
    ax.set_yscale("log")
    for p in pos[~fitted]:
        ax.text(p, 0.02, "no fit", rotation=90, ha="center", va="bottom", fontsize=7,
                color="0.4", transform=ax.get_xaxis_transform())
    ax.set_xticks(pos, names, fontsize=7)
    ax.set_xlim(-0.6, value.size - 0.4)
    ax.set_ylabel("mean annual frequency (1/yr)")
    ax.set_title("each limit state's annual frequency (5-95 %)")


def _gap_figure(ds):
    """The annual frequency of pounding against the uniform gap: the envelope, the refitted
    curve, the target and the gap at it, and the rules at the target's intensity, each in
    the legend with its value (labels on the lines would overlap where rules agree)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4.5), layout="constrained")
    ax.semilogy(1000 * ds.gap.values, ds.pounding_frequency.values, "o-", ms=3,
                label="envelope (used)")
    if "pounding_frequency_raw" in ds:  # the refitted curve, where it rises with the gap
        ax.semilogy(1000 * ds.gap.values, ds.pounding_frequency_raw.values, ":",
                    color="0.4", lw=1, label="refitted at each gap")
    if "gap_at_target" in ds:
        ax.axhline(float(ds.target_annual_frequency), color="k", ls="--", lw=1,
                   label=f"target {float(ds.target_annual_frequency):.3g} /yr")
        ax.axvline(1000 * float(ds.gap_at_target), color="tab:red", lw=1.2,
                   label=f"gap at target {1000 * float(ds.gap_at_target):.1f} mm")
        if "rule_separation_at_target" in ds:
            from pframe.plot.gap import MORE

            others = 0
            for r, v in zip(ds.rule_name.values, ds.rule_separation_at_target.values):
                if not np.isfinite(v):
                    continue
                style = STYLE.get(str(r))
                if style is None:
                    style, others = MORE[others % len(MORE)], others + 1
                ax.axvline(1000 * float(v), ls=":", lw=1.2, color=style[1],
                           label=f"{r} at target IM {1000 * float(v):.1f} mm")
        ax.legend(fontsize=7, loc="upper right")
    ax.set_xlabel("uniform gap (mm)")
    ax.set_ylabel("annual frequency of pounding (1/yr)")
    ax.set_title("annual frequency of pounding against the gap")
    return fig
