"""The figure set of a risk study (``pframe risk``): the fitted fragilities, the hazard curve
with each limit state's mean annual frequency, and the annual frequency of pounding against
the gap with the gap at the target."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.stats import norm


def risk_figures(path: str | Path) -> dict:
    """{"fragility": fig, "hazard": fig, "gap": fig} (the last two when the file has them)."""
    import matplotlib.pyplot as plt

    from pframe.api import open as open_result

    with open_result(path) as opened:
        ds = opened.load()
    out = {}
    fig, ax = plt.subplots(figsize=(6.5, 4.5), layout="constrained")
    levels = ds.level.values
    x = np.geomspace(max(levels.min() / 3, 1e-3), levels.max() * 2, 300)
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
    ax.set_xlabel(f"{ds.attrs.get('measure', 'IM')} (g)")
    ax.set_ylabel("P(limit state | IM)")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)
    else:
        ax.text(0.5, 0.5, "no fragility fitted (see the file's warnings)", ha="center",
                transform=ax.transAxes)
    ax.set_title(f"fragilities ({ds.attrs.get('design', '')}, maximum likelihood)")
    out["fragility"] = fig
    if "hazard_frequency" in ds:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
        a1.loglog(ds.hazard_im.values, ds.hazard_frequency.values, "k-")
        a1.set_xlabel(f"{ds.attrs.get('measure', 'IM')} (g)")
        a1.set_ylabel("annual frequency of exceedance")
        a1.set_title("hazard curve")
        if "annual_frequency" in ds:
            names = [f"{lim}\n{c.split('_')[0]}" for lim in ds.limit_name.values
                     for c in ds.condition_name.values]
            value = ds.annual_frequency.values.ravel()
            low = ds.annual_frequency_low.values.ravel()
            high = ds.annual_frequency_high.values.ravel()
            pos = np.arange(value.size)
            a2.bar(pos, np.nan_to_num(value), color="tab:blue")
            a2.errorbar(pos, value, yerr=[np.nan_to_num(value - low), np.nan_to_num(high - value)],
                        fmt="none", ecolor="k", capsize=3)
            a2.set_yscale("log")
            a2.set_xticks(pos, names, fontsize=7)
            a2.set_ylabel("mean annual frequency (5-95 %)")
        else:
            a2.set_axis_off()
            a2.text(0.5, 0.5, "no fragility fitted: no mean annual frequency",
                    ha="center", transform=a2.transAxes)
        out["hazard"] = fig
    if "pounding_frequency" in ds:
        fig, ax = plt.subplots(figsize=(6.5, 4.5), layout="constrained")
        ax.semilogy(1000 * ds.gap.values, ds.pounding_frequency.values, "o-", ms=3,
                    label="envelope (used)")
        if "pounding_frequency_raw" in ds:  # the refitted curve, where it rises with the gap
            ax.semilogy(1000 * ds.gap.values, ds.pounding_frequency_raw.values, ":",
                        color="0.4", lw=1, label="refitted at each gap")
        if "gap_at_target" in ds:
            ax.axhline(float(ds.target_annual_frequency), color="k", ls="--", lw=1,
                       label="target")
            ax.axvline(1000 * float(ds.gap_at_target), color="tab:red", lw=1.2,
                       label=f"gap at target {1000 * float(ds.gap_at_target):.1f} mm")
            if "rule_separation_at_target" in ds:
                for r, v in zip(ds.rule_name.values, ds.rule_separation_at_target.values):
                    ax.axvline(1000 * float(v), ls=":", lw=1, color="0.4")
                    ax.text(1000 * float(v), ax.get_ylim()[1], str(r), rotation=90,
                            va="top", fontsize=7)
            ax.legend(fontsize=8)
        ax.set_xlabel("uniform gap (mm)")
        ax.set_ylabel("annual frequency of pounding")
        out["gap"] = fig
    return out
