"""The audit's labelled result: records x levels x contacts x rules, as an xarray.Dataset
written to netCDF4-compatible HDF5 (h5netcdf) under a temporary name and renamed."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pframe.gap import members
from pframe.gap.fragility import fit_lognormal

#: the statistics over the suite
STATISTICS = ("median", "p84", "max")
KIND = "gap_audit"


def _statistics(values: np.ndarray) -> np.ndarray:
    """median, 84th percentile and maximum over axis 0 (records), NaN (failed runs) left out."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a level where every run failed
        return np.stack([np.nanmedian(values, axis=0), np.nanpercentile(values, 84, axis=0),
                         np.nanmax(values, axis=0)])


def measure_label(inputs) -> str:
    m = inputs.suite.measure
    if m.kind == "pga":
        return ("PGA" if getattr(inputs, "supports", None) is None else
                "PGA at each record's reference support (record_intensity_support)")
    try:
        period = f"{float(m.period):g} s"
    except ValueError:
        period = f"T_1 of {m.period}"
    label = f"Sa({period}, {100 * m.damping:g} %)"
    return label if getattr(inputs, "supports", None) is None else \
        f"{label} at each record's reference support (record_intensity_support)"


def build_dataset(inputs, rows: dict, gap: float | None = None, en_coincident: bool = False,
                  codes=None, geometry=None):
    """The Dataset of an audit from the batch's rows (variants record-major); ``codes``, the
    code rules (:class:`pframe.gap.selection.Selection`), ``geometry`` the contacts' floors
    (:class:`pframe.gap.floors.Geometry`; by default from the scene)."""
    import pframe
    from pframe.api import indexed
    from pframe.gap.floors import contact_geometry
    from pframe.gap.selection import Selection, describe, rules_over_runs
    from pframe.record.netcdf import with_units

    R, L = inputs.factors.shape
    shape = (R, L, len(inputs.pairs.names))
    complete = rows["complete"].reshape(R, L).astype(np.int8)
    ok = complete.astype(bool)[:, :, None]
    u_left = np.where(ok, rows["peak_left"].reshape(shape), np.nan)
    u_right = np.where(ok, rows["peak_right"].reshape(shape), np.nan)
    g_sim = np.where(ok, np.maximum(rows["g_req"].reshape(shape), 0.0), np.nan)

    codes = codes if codes is not None else Selection()
    if geometry is None:
        geometry = contact_geometry(inputs.loaded.expanded, inputs.pairs.left,
                                    inputs.pairs.right, override=codes.aligned,
                                    tolerance=codes.tolerance)
    rules = rules_over_runs(inputs, codes, geometry, u_left, u_right, en_coincident)
    rules["simulated"] = g_sim
    names = list(rules)
    table = np.stack([rules[n] for n in names], axis=-1)  # (R, L, C, rule)
    data = {
        "gap_required": (("record", "level", "contact", "rule"), table, {
            "units": "m", "long_name": "minimum separation by each rule; 'simulated' is "
            "g_req = max over time of (u_left - u_right) without contact, in plan of the "
            "contact's two points along its normal (0 if never approaching)"}),
        "gap_statistics": (("statistic", "level", "contact", "rule"), _statistics(table), {
            "units": "m", "long_name": "median, 84th percentile and maximum of gap_required "
            "over the records (failed runs left out)"}),
        "peak_displacement_left": (("record", "level", "contact"), u_left, {
            "units": "m", "long_name": "peak |u| of the contact's left floor (in plan: of its "
            "point along the contact's normal), no contact"}),
        "peak_displacement_right": (("record", "level", "contact"), u_right, {
            "units": "m", "long_name": "peak |u| of the contact's right floor (in plan: of "
            "its point along the contact's normal), no contact"}),
        **_run_variables(inputs, rows, complete),
        **_scene_variables(inputs, geometry),
    }
    buildings = list(inputs.loaded.expanded.buildings)
    attrs = {
        "title": f"gap audit: {inputs.loaded.scene.title or inputs.loaded.source}",
        "pframe_kind": KIND,
        "source": inputs.loaded.source,
        "suite": inputs.suite.source,
        "measure": measure_label(inputs),
        "input_yaml": inputs.loaded.text,
        "dt": inputs.dt,
        "steps": inputs.steps,
        "duration": inputs.steps * inputs.dt,
        "warnings": "\n".join(inputs.warnings),
        "en_coincident_floor_factor": int(en_coincident),
        "code_factors": "; ".join(dict.fromkeys(_factors(c) for c in codes.chosen)),
        "code_rules": describe(codes, buildings),
        "pframe_version": pframe.__version__,
        "Conventions": "CF-1.8",
    }
    if gap is not None:
        data.update(_pounding_variables(inputs, gap, g_sim, complete))
    return indexed(labelled(data, _coordinates(inputs, names, buildings), with_units(attrs)))


def labelled(data: dict, coords: dict, attrs: dict):
    """The Dataset of variables and coordinates given as ``name: (dims, values, attrs)``."""
    import xarray as xr

    return xr.Dataset({k: xr.Variable(*v) for k, v in data.items()},
                      coords={k: xr.Variable(*v) for k, v in coords.items()}, attrs=attrs)


def _level_units(inputs) -> str:
    """The units of the levels: intensities in g, in UDUNITS' terms (its "g" is the gram),
    or 1 for records as given."""
    from pframe.record.netcdf import STANDARD_GRAVITY

    return STANDARD_GRAVITY if inputs.scaled else "1"


def _coordinates(inputs, rules: list[str], buildings: list[str]) -> dict:
    """The records, levels, contacts, rules, statistics and buildings of an audit: named
    positions are label coordinates <dim>_name (CF: no string coordinate variables),
    indexed so that .sel(rule_name="DDC") selects by name."""
    return {
        "record_name": ("record", np.array(inputs.suite.names, dtype=object),
                        {"long_name": "ground-motion record"}),
        "level": ("level", inputs.levels, {
            "units": _level_units(inputs),
            "long_name": (f"target intensity ({measure_label(inputs)})" if inputs.scaled
                          else "records as given (factor 1)")}),
        "contact_name": ("contact", np.array(inputs.pairs.names, dtype=object),
                         {"long_name": "contact element (the level audited)"}),
        "rule_name": ("rule", np.array(rules, dtype=object),
                      {"long_name": "separation rule (ABS, SRSS, DDC, ...; simulated)"}),
        "statistic_name": ("statistic", np.array(STATISTICS, dtype=object),
                           {"long_name": "statistic over the records"}),
        "building_name": ("building", np.array(buildings, dtype=object),
                          {"long_name": "building"}),
    }


def _run_variables(inputs, rows: dict, complete) -> dict:
    """Each run's scale factor, intensity, completion and status."""
    from pframe.record.netcdf import STANDARD_GRAVITY

    R, L = inputs.factors.shape
    return {
        "scale_factor": (("record", "level"), inputs.factors, {
            "units": "1", "long_name": "factor applied to the record"}),
        "intensity": (("record", "level"), inputs.intensities[:, None] * inputs.factors, {
            "units": STANDARD_GRAVITY,
            "long_name": f"{measure_label(inputs)} of the scaled record"}),
        "complete": (("record", "level"), complete, {
            "units": "1", "long_name": "1 if the run completed"}),
        "status": (("record", "level"), rows["status"].reshape(R, L).astype(object), {
            "long_name": "completed, or why the run stopped"}),
    }


def _scene_variables(inputs, geometry) -> dict:
    """What the rules take of the scene: each building's period and damping, each
    contact's modal correlation, floors, nodes and gap, and each record's length."""
    from pframe.gap.selection import contact_correlation

    pairs = inputs.pairs
    floor = np.array([int(n.split("/")[1]) if n.split("/")[1].isdigit() else i + 1
                      for i, n in enumerate(pairs.left)])
    return {
        "period": (("building",), inputs.periods, {
            "units": "s", "long_name": "first fixed-base period"}),
        "damping_ratio": (("building",), inputs.damping, {
            "units": "1", "long_name": "Rayleigh damping ratio at the first period"}),
        "correlation": (("contact",), contact_correlation(inputs), {
            "units": "1", "long_name": "CQC correlation coefficient rho of the two "
            "buildings' first modes (DDC rule)"}),
        "floors_aligned": (("contact",), geometry.aligned, {
            "units": "1", "long_name": "1 if the two buildings' floors align, 0 if not, NaN "
            "unknown (no storey heights): " + geometry.decided}),
        "floor": (("contact",), floor.astype(np.int32),
                  {"units": "1", "long_name": "floor of the left node"}),
        "left_node": (("contact",), np.array(pairs.left, dtype=object),
                      {"long_name": "left node of the contact"}),
        "right_node": (("contact",), np.array(pairs.right, dtype=object),
                       {"long_name": "right node of the contact"}),
        "scene_gap": (("contact",), pairs.gaps, {
            "units": "m", "long_name": "the gap the scene gives the contact"}),
        "record_duration": (("record",), np.array(
            [m.duration for m in inputs.suite.motions], dtype=float), {
            "units": "s", "long_name": "time of the record's last sample (every run goes on "
            "to the analysed duration: free vibration after its record)"}),
        **({} if inputs.supports is None else {"record_intensity_support": (
            ("record",), np.array([members.reference(m) for m in inputs.suite.motions],
                                  dtype=object), {
                "long_name": "the support whose motion the record's intensity is of, every "
                "support's scaled by its one factor (docs/supports.md#suites-of-a-motion-"
                "per-support)"})}),
    }


def _pounding_variables(inputs, gap: float, g_sim, complete) -> dict:
    """At the provided ``gap``: which runs pound, the fraction of the records that pound at
    each level, and the lognormal fragility of pounding fitted to them."""
    level_units = _level_units(inputs)
    ok = complete.astype(bool)[:, :, None]
    pounds = np.where(ok, (g_sim > gap).astype(np.int8), -1).astype(np.int8)
    n = complete.sum(axis=0)  # (L,)
    hit = (pounds == 1).sum(axis=0)  # (L, C)
    any_hit = ((pounds == 1).any(axis=2) & complete.astype(bool)).sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        fraction = hit / n[:, None]
        fraction_any = any_hit / n
    fits = [fit_lognormal(inputs.levels, n, hit[:, c]) if inputs.scaled else (np.nan, np.nan)
            for c in range(hit.shape[1])]
    fit_any = fit_lognormal(inputs.levels, n, any_hit) if inputs.scaled else (np.nan, np.nan)
    return {
        "provided_gap": ((), float(gap), {"units": "m", "long_name": "the gap provided"}),
        "pounds": (("record", "level", "contact"), pounds, {
            "units": "1", "long_name": "1 if g_req > provided gap, 0 if not, -1 not run"}),
        "pounding_fraction": (("level", "contact"), fraction, {
            "units": "1", "long_name": "fraction of the records that pound at the contact"}),
        "pounding_fraction_any": (("level",), fraction_any, {
            "units": "1", "long_name": "fraction of the records that pound at any contact"}),
        "fragility_median": (("contact",), np.array([f[0] for f in fits]), {
            "units": level_units, "long_name": "median of the lognormal fragility "
            "P(g_req > gap | IM) (maximum likelihood)"}),
        "fragility_dispersion": (("contact",), np.array([f[1] for f in fits]), {
            "units": "1", "long_name": "dispersion (log standard deviation) of the "
            "lognormal fragility"}),
        "fragility_median_any": ((), fit_any[0], {
            "units": level_units, "long_name": "median of the fragility of pounding at "
            "any contact"}),
        "fragility_dispersion_any": ((), fit_any[1], {
            "units": "1", "long_name": "dispersion of the fragility of pounding at any "
            "contact"}),
    }


def _factors(chosen) -> str:
    """A chosen rule's factors for both buildings, then each building's own."""
    from pframe.gap.codes import CODES

    group = next((g for g, rules in CODES.items() if chosen.rule in rules), chosen.rule.name)
    text = f"{group}: " + ", ".join(f"{k} = {v:g}" if isinstance(v, (int, float)) else
                                    f"{k} = {v}"
                                    for k, v in chosen.rule.resolved(chosen.factors).items())
    return text + "".join(f" ({b}: " + ", ".join(f"{k} = {v}" for k, v in f.items()) + ")"
                          for b, f in chosen.buildings.items())


def write_dataset(ds, output: str | Path, call: str | None = None) -> Path:
    """Write ``ds`` to ``output`` (netCDF-4, CF-1.8, through the one writer of result files)
    via a temporary file in the same folder, renamed when complete: whole or absent."""
    from pframe.record.netcdf import write_dataset as write

    return write(ds, output, call)
