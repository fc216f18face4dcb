"""A risk study's labelled result (xarray.Dataset, written as netCDF-4 CF-1.8) and its
summary table."""

from __future__ import annotations

import math

import numpy as np

from pframe.record.netcdf import PER_YEAR, STANDARD_GRAVITY
from pframe.risk.analysis import CONDITIONS, G
from pframe.risk.fragility import CONFIDENCE

KIND = "risk_study"


def build_dataset(spec, inputs, rows: dict, result, text: str, source: str, hazard=None,
                  search=None):
    """A study's labelled result: its runs (intensity, critical gap, peaks, impacts, which
    completed), each limit's fragility under each condition, and where the study has them
    the annual frequencies, the hazard curve, the annual frequency of pounding over uniform
    gaps and the gap at the target."""
    from pframe.api import indexed
    from pframe.gap.output import labelled, measure_label

    coords = _coordinates(inputs, result, search)
    if "free_drift_ratio_each" in rows:  # a planar scene: storey by storey
        coords.update(_storey_coordinates(inputs.loaded.expanded))
    data = {**_run_variables(inputs, rows, result), **_fragility_variables(spec, result)}
    attrs = study_attributes(inputs, text, source, [*inputs.warnings, *result.warnings],
                             title="risk study", suite=inputs.suite.source,
                             measure=measure_label(inputs), design=spec.design.kind)
    if search is not None:
        d = spec.design
        attrs.update(ida_limit=d.limit, ida_condition=d.condition or (
            "with_pounding" if spec.pounding_runs else "without_pounding"),
            ida_resolution=d.resolution, ida_rounds=search.rounds, ida_runs=search.runs,
            ida_hunt=f"start {d.hunt.start:g} g, step {d.hunt.step:g} g, growth "
                     f"{d.hunt.growth:g}, max_level {d.max_level:g} g")
    if any(math.isfinite(result.maf[k][0]) for k in result.maf):
        data.update(_annual_frequency_variables(result))
        data.update(_design_life_variables(data, spec.design_life))
        attrs["design_life"] = spec.design_life
    if hazard is not None:
        data["hazard_frequency"] = (("hazard_point",), hazard.frequency, {
            "units": PER_YEAR, "long_name": "annual frequency of exceedance of hazard_im"})
        coords["hazard_im"] = ("hazard_point", hazard.im, {
            "units": STANDARD_GRAVITY,
            "long_name": f"intensity of the hazard curve ({hazard.source})"})
    if result.gap_grid is not None:
        coords["gap"] = ("gap", result.gap_grid, {"units": "m", "long_name": "uniform gap"})
        data["pounding_frequency"] = (("gap",), result.gap_rates, {
            "units": PER_YEAR, "long_name": "annual frequency of pounding at the gap: the "
            "upper envelope from the right of pounding_frequency_raw (at each gap, the "
            "largest of any wider gap), whose root is gap_at_target"})
        data["pounding_frequency_raw"] = (("gap",), result.gap_rates_raw, {
            "units": PER_YEAR, "long_name": "annual frequency of pounding at the gap, the "
            "design's fragility refitted at each gap (not monotone in general)"})
    if math.isfinite(result.target):
        data.update(_target_variables(result))
        if result.rules_at_target:
            coords["rule_name"] = ("rule", np.array(list(result.rules_at_target), dtype=object),
                                   {"long_name": "separation rule"})
            data["rule_separation_at_target"] = (("rule",), np.array(
                list(result.rules_at_target.values())), {
                "units": "m", "long_name": "median over the records of the rule's separation "
                "at intensity_at_target (ABS, SRSS, DDC of the peak displacements, the code "
                "rules of the study's codes described in code_rules; simulated: the critical "
                "gap)"})
            if spec.codes is not None:
                from pframe.gap.selection import describe, selection

                attrs["code_rules"] = describe(selection(spec.codes),
                                               inputs.loaded.expanded.buildings)
    return indexed(labelled(data, coords, attrs))


def study_attributes(inputs, text: str, source: str, warnings: list[str], title: str,
                     **more) -> dict:
    """The attributes every study's file has: its title, kind, files and texts, the runs'
    step and length, its warnings, and what wrote it; ``more`` in the middle."""
    import pframe

    return {
        "title": f"{title}: {inputs.loaded.scene.title or inputs.loaded.source}",
        "pframe_kind": KIND, "source": source, "scene": inputs.loaded.source, **more,
        "study_yaml": text, "input_yaml": inputs.loaded.text, "dt": inputs.dt,
        "steps": inputs.steps, "duration": inputs.steps * inputs.dt,
        "warnings": "\n".join(warnings),
        "pframe_version": pframe.__version__, "Conventions": "CF-1.8",
    }


def _coordinates(inputs, result, search) -> dict:
    """The records, levels (intensities, or the runs of a hunt and fill), contacts,
    buildings, limit states and conditions of a study."""
    from pframe.gap.output import measure_label

    return {
        "record_name": ("record", np.array(inputs.suite.names, dtype=object),
                        {"long_name": "ground-motion record"}),
        "level": ("level", np.asarray(inputs.levels, float),
                  {"units": "1", "long_name": "run of the record's hunt and fill, in order of "
                   "intensity (see intensity)"} if search is not None else
                  {"units": STANDARD_GRAVITY if inputs.scaled else "1",
                   "long_name": (f"target intensity ({measure_label(inputs)})" if inputs.scaled
                                 else "records as given (cloud analysis)")}),
        "contact_name": ("contact", np.array(inputs.pairs.names, dtype=object),
                         {"long_name": "contact level"}),
        "building_name": ("building", np.array(list(inputs.loaded.expanded.buildings),
                                               dtype=object), {"long_name": "building"}),
        "limit_name": ("limit", np.array(result.limit_names, dtype=object),
                       {"long_name": "limit state"}),
        "condition_name": ("condition", np.array(CONDITIONS, dtype=object),
                           {"long_name": "runs without the contacts, or with them at the "
                            "scene's gaps"}),
    }


def _run_variables(inputs, rows: dict, result) -> dict:
    """Each run's intensity, critical gap, peak drift (and ratio) and floor acceleration of
    each building under each condition, impacts, and whether it completed (NaN, -1: not
    run or failed)."""
    from pframe.gap.output import measure_label

    R, L = inputs.factors.shape
    C = len(inputs.pairs.names)
    nb = len(inputs.loaded.expanded.buildings)

    def grid(key, width, fill=np.nan):
        if key not in rows:
            return np.full((R, L, width), fill)
        ok = (rows[key.split("_")[0] + "_complete"] == 1)[:, None]
        return np.where(ok, rows[key].reshape(R * L, width), fill).reshape(R, L, width)

    drift = np.stack([grid("free_drift", nb), grid("contact_drift", nb)])
    ratio = np.stack([grid("free_drift_ratio", nb), grid("contact_drift_ratio", nb)])
    acc = np.stack([grid("free_acceleration", nb), grid("contact_acceleration", nb)]) / G
    impacts = (np.where((rows["contact_complete"] == 1)[:, None], rows["contact_impacts"], -1)
               .reshape(R, L, C).astype(np.int32) if "contact_impacts" in rows
               else np.full((R, L, C), -1, np.int32))
    out = _storey_variables(inputs, grid) if "free_drift_ratio_each" in rows else {}
    return {
        **out,
        "intensity": (("record", "level"), result.im.reshape(R, L), {
            "units": STANDARD_GRAVITY,
            "long_name": f"intensity of the run ({measure_label(inputs)})"}),
        "critical_gap": (("record", "level", "contact"), grid("free_g_req", C), {
            "units": "m", "long_name": "max over time of u_left - u_right without contacts: "
            "the gap below which the floors pound"}),
        "peak_story_drift": (("condition", "record", "level", "building"), drift, {
            "units": "m", "long_name": "peak |storey drift| over the building's storeys"}),
        "peak_story_drift_ratio": (("condition", "record", "level", "building"), ratio, {
            "units": "1", "long_name": "peak |storey drift ratio| over the building's storeys "
            "(NaN without storey heights)"}),
        "peak_floor_acceleration": (("condition", "record", "level", "building"), acc, {
            "units": STANDARD_GRAVITY,
            "long_name": "peak absolute floor acceleration over the building's "
            "floors"}),
        "impact_count": (("record", "level", "contact"), impacts, {
            "units": "1", "long_name": "impacts in the run with contacts (-1: not run)"}),
        "complete": (("condition", "record", "level"), np.stack([
            rows.get(f"{p}_complete", np.zeros(R * L, np.int8)).reshape(R, L)
            for p in ("free", "contact")]).astype(np.int8),
            {"units": "1", "long_name": "1 if the run completed, 0 if it failed, -1 if not "
             "run (a slot of ida by hunt and fill)"}),
    }


def _storey_coordinates(expanded) -> dict:
    """Each storey's and node's name, building and location in it: storey k of a building
    (counted up from the ground, in the scene's order) is location k, and so is the floor
    it carries (its upper node); the ground is 0, a node no storey carries (a tuned mass)
    -1. FEMA P-58's numbering of stories and floors, which pelicun's demand table uses."""
    buildings = np.array(expanded.buildings, dtype=object)
    story_location = np.zeros(len(expanded.stories), np.int32)
    node_location = np.full(len(expanded.node_names), -1, np.int32)
    for b in range(len(buildings)):
        for k, e in enumerate(np.flatnonzero(expanded.story_building == b)):
            story_location[e] = k + 1
            node_location[expanded.stories[e].nodes[1]] = k + 1
    return {
        "story_name": ("story", np.array([e.name for e in expanded.stories], dtype=object),
                       {"long_name": "storey"}),
        "story_building": ("story", buildings[np.asarray(expanded.story_building)],
                           {"long_name": "building of the storey"}),
        "story_location": ("story", story_location, {
            "units": "1", "long_name": "storey number in its building, from the ground up "
            "(FEMA P-58)"}),
        "node_name": ("node", np.array(expanded.node_names, dtype=object),
                      {"long_name": "floor (node)"}),
        "node_building": ("node", buildings[np.asarray(expanded.node_building)],
                          {"long_name": "building of the node"}),
        "node_location": ("node", node_location, {
            "units": "1", "long_name": "floor number in its building (that of the storey "
            "below it; -1: a node no storey carries)"}),
    }


def _storey_variables(inputs, grid) -> dict:
    """A planar scene's demands storey by storey and floor by floor (the demand table pelicun
    reads: pframe.risk.pelicun): each storey's peak drift ratio, each floor's peak absolute
    acceleration, and each run's peak ground acceleration, under each condition."""
    expanded = inputs.loaded.expanded
    stories = [e.name for e in expanded.stories]
    nodes = list(expanded.node_names)

    def both(key, width):
        return np.stack([grid(f"free_{key}", width), grid(f"contact_{key}", width)])

    return {
        "story_peak_drift_ratio": (("condition", "record", "level", "story"),
                                   both("drift_ratio_each", len(stories)), {
            "units": "1", "long_name": "peak |storey drift ratio| of each storey (NaN without "
            "its height)"}),
        "node_peak_absolute_acceleration": (("condition", "record", "level", "node"),
                                            both("acceleration_each", len(nodes)) / G, {
            "units": STANDARD_GRAVITY,
            "long_name": "peak absolute acceleration |a + a_g| of each floor"}),
        "peak_ground_acceleration": (("condition", "record", "level"),
                                     both("ground_acceleration", 1)[..., 0] / G, {
            "units": STANDARD_GRAVITY,
            "long_name": "peak ground acceleration of the run's motion (as "
            "scaled, sampled on the run's step)"}),
    }


#: the units of each kind of limit (an acceleration "in g" as UDUNITS reads it)
_LIMIT_UNITS = {"pounding": "m", "drift": "m", "drift_ratio": "1",
                "acceleration": STANDARD_GRAVITY}


def _fragility_variables(spec, result) -> dict:
    """Each limit (its value and units) and its lognormal fragility under each condition:
    median and dispersion with their confidence bounds, or why there is none."""
    frag, lim, cond = result.fragilities, result.limit_names, CONDITIONS
    pct = f"{100 * CONFIDENCE:g} %"

    def table(f):
        return np.array([[f(frag[(n, c)]) for c in cond] for n in lim], dtype=float)

    return {
        "limit_value": (("limit",), np.array(result.limit_values, float), {
            "units": "1", "long_name": "the limit: gap (m) for pounding, drift (m), drift "
            "ratio (1), floor acceleration (g); see limit_units"}),
        "limit_units": (("limit",), np.array([_LIMIT_UNITS[k] for k in result.limit_kinds],
                                             dtype=object), {"long_name": "units of the limit"}),
        "fragility_median": (("limit", "condition"), table(lambda f: f.median), {
            "units": STANDARD_GRAVITY, "long_name": "median theta of the lognormal fragility "
            f"({spec.design.kind}, maximum likelihood)"}),
        "fragility_dispersion": (("limit", "condition"), table(lambda f: f.dispersion), {
            "units": "1", "long_name": "dispersion beta of the lognormal fragility"}),
        "fragility_median_low": (("limit", "condition"), table(lambda f: f.bounds()[0][0]),
                                 {"units": STANDARD_GRAVITY,
                                  "long_name": f"lower {pct} bound of theta "
                                  "(Fisher information)"}),
        "fragility_median_high": (("limit", "condition"), table(lambda f: f.bounds()[0][1]),
                                  {"units": STANDARD_GRAVITY,
                                   "long_name": f"upper {pct} bound of theta"}),
        "fragility_dispersion_low": (("limit", "condition"),
                                     table(lambda f: f.bounds()[1][0]),
                                     {"units": "1", "long_name": f"lower {pct} bound of beta"}),
        "fragility_dispersion_high": (("limit", "condition"),
                                      table(lambda f: f.bounds()[1][1]),
                                      {"units": "1", "long_name": f"upper {pct} bound of beta"}),
        "fragility_note": (("limit", "condition"), np.array(
            [[frag[(n, c)].note for c in cond] for n in lim], dtype=object), {
            "long_name": "why the fragility is absent (NaN), where it is: what the data "
            "cannot fix"}),
    }


def _annual_frequency_variables(result) -> dict:
    """Each limit's mean annual frequency under each condition, with its 5-95 % range."""
    def maf(i):
        return np.array([[result.maf[(n, c)][i] for c in CONDITIONS]
                         for n in result.limit_names], dtype=float)

    return {
        "annual_frequency": (("limit", "condition"), maf(0), {
            "units": PER_YEAR, "long_name": "mean annual frequency of the limit state"}),
        "annual_frequency_low": (("limit", "condition"), maf(1), {
            "units": PER_YEAR, "long_name": "5th percentile of the annual frequency over "
            "the fragility's parameter uncertainty"}),
        "annual_frequency_high": (("limit", "condition"), maf(2), {
            "units": PER_YEAR, "long_name": "95th percentile of the annual frequency"}),
    }


def _design_life_variables(data: dict, years: float) -> dict:
    """The probability of each ``annual_frequency*`` variable's limit state happening at
    least once in ``years`` (Poisson occurrences), with its range (the map is monotone)."""
    from pframe.risk.hazard import probability_in_years

    out = {}
    for name, (dims, rate, _) in list(data.items()):
        if not name.startswith("annual_frequency") or name.endswith("_cov"):
            continue
        which = {"annual_frequency": "", "annual_frequency_low": "lower end of the range of ",
                 "annual_frequency_high": "upper end of the range of "}[name]
        out[name.replace("annual_frequency", "probability_in_design_life")] = (
            dims, probability_in_years(rate, years), {
                "units": "1", "long_name": f"{which}the probability that the limit state "
                f"happens at least once in the design life ({years:g} years): 1 - exp(-"
                f"annual_frequency x {years:g}), its occurrences a Poisson process"})
    return out


def _target_variables(result) -> dict:
    """The target annual frequency, the intensity there and the gap at it (with its
    bootstrap range and the regression's estimate)."""
    return {
        "target_annual_frequency": ((), result.target, {"units": PER_YEAR,
                                    "long_name": "the target annual frequency of pounding"}),
        "intensity_at_target": ((), result.im_at_target, {
            "units": STANDARD_GRAVITY, "long_name": "the intensity the hazard curve exceeds at the "
            "target frequency"}),
        "gap_at_target": ((), result.gap, {
            "units": "m", "long_name": "smallest uniform gap at and above which the "
            "annual frequency of pounding is at most the target (the largest crossing of "
            "the refitted curve)"}),
        "gap_at_target_low": ((), result.gap_low, {
            "units": "m", "long_name": "5th percentile of the gap over record bootstrap"}),
        "gap_at_target_high": ((), result.gap_high, {
            "units": "m", "long_name": "95th percentile of the gap over record bootstrap"}),
        "gap_at_target_regression": ((), result.gap_regression, {
            "units": "m", "long_name": "the gap at target from the regression of ln "
            "critical gap on ln IM (a smooth second estimate)"}),
    }


def subset_dataset(spec, inputs, params, estimate, problem, text, source, notes,
                   terms=None, stripes=None, maf=None, hazard=None):
    """The result of a subset study: the probability of pounding with its c.o.v. and
    confidence interval, the intermediate thresholds, the uncertain variables; over a suite
    of records (``terms``: each stripe's per-record estimates; ``stripes``: each stripe's
    estimate), each record's conditional probability at each stripe, and with a hazard
    (``maf``: lambda, low, high, cov) the annual frequency of pounding."""
    m = spec.stochastic
    data = {
        "pounding_probability": ((), estimate.probability, {
            "units": "1", "long_name": "probability of pounding within the analysed time "
            "(subset simulation)"}),
        "pounding_probability_low": ((), estimate.low, {
            "units": "1", "long_name": "lower bound of its 95 % interval (the estimator "
            "taken lognormal)"}),
        "pounding_probability_high": ((), estimate.high, {
            "units": "1", "long_name": "upper bound of its 95 % interval"}),
        "pounding_probability_cov": ((), estimate.cov, {
            "units": "1", "long_name": "coefficient of variation of the estimator (Au & Beck "
            "2001, the chains' correlation included)"}),
        "evaluations": ((), np.int64(sum(e.evaluations for e in stripes) if stripes
                                     else estimate.evaluations), {
            "units": "1", "long_name": "runs of the kernel"}),
        "threshold": (("subset_level",), np.array(estimate.levels, float), {
            "units": "m", "long_name": "intermediate threshold of g = gap - critical gap "
            "(0: the last level)"}),
    }
    coords = {}
    if terms is not None:  # over records: no common thresholds; each record's estimate
        del data["threshold"]
        coords["record"] = ("record", np.array([mo.name for mo in inputs.suite.motions],
                                               dtype=object), {"long_name": "ground motion"})
        coords["level"] = ("level", np.asarray(inputs.levels, float), {
            "units": STANDARD_GRAVITY,
            "long_name": "intensity level (stripe) the records are scaled to"})
        data["record_probability"] = (("record", "level"), np.array(
            [[t.probability for t in stripe] for stripe in terms]).T, {
            "units": "1", "long_name": "probability of pounding under the record (subset "
            "simulation over the uncertain values; 0: below the floor or none found)"})
        data["record_probability_cov"] = (("record", "level"), np.array(
            [[t.cov for t in stripe] for stripe in terms]).T, {
            "units": "1", "long_name": "its coefficient of variation"})
        data["record_scale_factor"] = (("record", "level"), np.asarray(inputs.factors, float),
                                       {"units": "1", "long_name": "scale factor applied"})
        for name, key, long in (("level_probability", "probability", "probability of "
                                 "pounding at the level: the mean over the records"),
                                ("level_probability_low", "low", "lower bound of its 95 % "
                                 "interval"),
                                ("level_probability_high", "high", "upper bound of its 95 % "
                                 "interval (with the bound of records stopped below the "
                                 "floor)"),
                                ("level_probability_cov", "cov", "its coefficient of "
                                 "variation")):
            data[name] = (("level",), np.array([getattr(e, key) for e in stripes], float),
                          {"units": "1", "long_name": long})
        if len(stripes) > 1:  # no single probability: one per level
            for k in ("pounding_probability", "pounding_probability_low",
                      "pounding_probability_high", "pounding_probability_cov"):
                del data[k]
        if maf is not None:
            for name, value, long in (
                    ("annual_frequency", maf[0], "mean annual frequency of pounding: the "
                     "levels' probabilities, linear in ln IM between them, over the hazard"),
                    ("annual_frequency_low", maf[1], "lower bound of its 95 % interval"),
                    ("annual_frequency_high", maf[2], "upper bound of its 95 % interval"),
                    ("annual_frequency_cov", maf[3], "its coefficient of variation (the "
                     "levels' estimates' variances combined)")):
                data[name] = ((), float(value), {"units": PER_YEAR if "cov" not in name
                                                 else "1", "long_name": long})
            data.update(_design_life_variables(data, spec.design_life))
            coords["hazard_im"] = ("hazard_point", np.asarray(hazard.im, float),
                                   {"units": STANDARD_GRAVITY,
                                    "long_name": "hazard curve: intensity"})
            data["hazard_frequency"] = (("hazard_point",), np.asarray(hazard.frequency, float),
                                        {"units": PER_YEAR, "long_name": "hazard curve: annual "
                                         "frequency of exceeding the intensity"})
    if params:
        coords["variable_name"] = ("variable", np.array([p.path for p in params], dtype=object),
                                   {"long_name": "uncertain scene value (path)"})
        data["variable_distribution"] = (("variable",), np.array(
            [p.distribution for p in params], dtype=object), {"long_name": "distribution"})
        data["variable_parameters"] = (("variable", "parameter"), np.array(
            [[p.a, p.b] for p in params]), {"units": "1", "long_name": "mean, sd / median, "
                                            "dispersion / low, high"})
    motion = (", ".join(f"{k} {v}" for k, v in m.items()) if m is not None else
              f"the suite's {len(inputs.suite.motions)} records"
              + (" scaled to " + ", ".join(f"{float(x):g}" for x in inputs.levels)
                 + " g" if inputs.scaled else " as recorded"))
    attrs = study_attributes(inputs, text, source, notes, title="risk study (subset "
                             "simulation)", design="subset", motion=motion,
                             measure=_subset_measure(inputs, m),
                             probability_level=spec.design.probability_level,
                             samples_per_level=spec.design.samples,
                             **({"design_life": spec.design_life} if maf is not None else {}))
    from pframe.gap.output import labelled

    return labelled(data, coords, attrs)


def _subset_measure(inputs, stochastic) -> str:
    """The intensity measure of a subset study's levels, as every study file names it; a
    stochastic motion is not scaled to an intensity, and its file says so."""
    if stochastic is not None:
        return "none (stochastic motions as generated, not scaled to an intensity)"
    from pframe.gap.output import measure_label

    return measure_label(inputs)


def _percent(p: float) -> str:
    """A probability as a percentage with the digits it needs (NaN as NaN)."""
    if not math.isfinite(p):
        return "NaN"
    return f"{100 * p:.3g} %"


def study_line(ds) -> str:
    """What a study ran, in a line: its design, motions, intensity measure and levels."""
    from pframe.record.netcdf import short_units

    a = ds.attrs
    design = str(a.get("design", "?"))
    n = ds.sizes.get("record", 0)
    motions = (f"{n} record{'s' if n != 1 else ''}" if "record" in ds.dims
               else str(a.get("motion", "its motions")))
    measure = str(a.get("measure", "not recorded in the file"))
    if "ida_runs" in a:
        levels = (f"hunt and fill to {a['ida_limit']} ({a['ida_hunt']}; {a['ida_runs']} runs "
                  f"in {a['ida_rounds']} rounds)")
    elif "level" in ds.coords and short_units(ds.level.attrs.get("units", "")) == "g":
        levels = "levels " + ", ".join(f"{float(x):g}" for x in ds.level.values) + " g"
    elif "level" in ds.coords:
        levels = "records as given (cloud analysis)"
    else:
        levels = "no levels"
    return f"{design} design over {motions}; intensity measure {measure}; {levels}"


def summary(ds) -> str:
    """The terminal summary of a study: what it ran (:func:`study_line`), then each limit's
    fragility (median, dispersion and their bounds) and annual frequency, then the gap (of
    a subset design: the probabilities of pounding)."""
    return study_line(ds) + "\n" + _results(ds)


def _cov(value) -> str:
    """A subset estimate's c.o.v. as the summary words it: a number, or why there is none (no
    run pounded, so the estimate is 0 and its c.o.v. is undefined, not inf or nan)."""
    value = float(value)
    if math.isfinite(value):
        return f"c.o.v. {value:.2f}"
    return "c.o.v. undefined: no run pounded"


def _results(ds) -> str:
    """The study's results as :func:`summary` prints them, under its first line."""
    if "level_probability" in ds and ds.sizes["level"] > 1:
        out = [f"probability of pounding within {float(ds.attrs['duration']):g} s by subset "
               f"simulation over {ds.sizes.get('variable', 0)} uncertain values, the mean over "
               f"{ds.sizes['record']} records, at each level:"]
        for k in range(ds.sizes["level"]):
            out.append(f"  {float(ds.level[k]):8.4g} g  {float(ds.level_probability[k]):.3e} "
                       f"({_cov(ds.level_probability_cov[k])}; 95 % "
                       f"{float(ds.level_probability_low[k]):.3e}-"
                       f"{float(ds.level_probability_high[k]):.3e})")
        if "annual_frequency" in ds:
            out.append(f"mean annual frequency of pounding: {float(ds.annual_frequency):.3e} /yr "
                       f"({_cov(ds.annual_frequency_cov)}; 95 % "
                       f"{float(ds.annual_frequency_low):.3e}-"
                       f"{float(ds.annual_frequency_high):.3e})")
        if "probability_in_design_life" in ds:
            years = float(ds.attrs["design_life"])
            out.append(f"probability of pounding at least once in {years:g} years: "
                       f"{_percent(float(ds.probability_in_design_life))} (95 % "
                       f"{_percent(float(ds.probability_in_design_life_low))}-"
                       f"{_percent(float(ds.probability_in_design_life_high))}; 1 - exp(-MAF "
                       f"x {years:g}), occurrences a Poisson process)")
        out.append(f"{int(ds.evaluations)} runs")
        return "\n".join(out)
    if "pounding_probability" in ds:
        return (f"probability of pounding within {float(ds.attrs['duration']):g} s: "
                f"{float(ds.pounding_probability):.3e} ("
                f"{_cov(ds.pounding_probability_cov)}; 95 % "
                f"{float(ds.pounding_probability_low):.3e}-"
                f"{float(ds.pounding_probability_high):.3e}) from "
                f"{int(ds.evaluations)} runs by subset simulation over "
                f"{ds.sizes.get('variable', 0)} uncertain values and "
                + ("the motion's white noise" if "record" not in ds.dims else
                   f"each of {ds.sizes['record']} records (their mean)"))
    life = "probability_in_design_life" in ds
    years = float(ds.attrs.get("design_life", math.nan))
    pct = f"{100 * CONFIDENCE:g}%"
    lines = [f"{'limit':<12} {'condition':<17} {'median':>8} {'beta':>6} "
             f"{f'{pct} median':>17} {f'{pct} beta':>13}"
             + (f" {'MAF /yr':>10} {'(5-95 %)':>21}" if "annual_frequency" in ds else "")
             + (f" {f'P {years:g} yr':>9}" if life else "")]
    lines.append("-" * len(lines[0]))
    for limit in ds.limit_name.values:
        for cond in ds.condition_name.values:
            sel = {"limit_name": limit, "condition_name": cond}
            m = float(ds.fragility_median.sel(sel))
            row = (f"{limit:<12} {cond:<17} {m:>8.4g} {float(ds.fragility_dispersion.sel(sel)):>6.3g}"
                   f" {float(ds.fragility_median_low.sel(sel)):>8.4g}-"
                   f"{float(ds.fragility_median_high.sel(sel)):<8.4g}"
                   f" {float(ds.fragility_dispersion_low.sel(sel)):>6.3g}-"
                   f"{float(ds.fragility_dispersion_high.sel(sel)):<6.3g}")
            if "annual_frequency" in ds:
                row += (f" {float(ds.annual_frequency.sel(sel)):>10.3e} "
                        f"{float(ds.annual_frequency_low.sel(sel)):>10.3e}-"
                        f"{float(ds.annual_frequency_high.sel(sel)):<10.3e}")
            if life:
                row += f" {_percent(float(ds.probability_in_design_life.sel(sel))):>9}"
            lines.append(row)
    if life:
        lines.append(f"P {years:g} yr: the probability of the limit state at least once in "
                     f"a design life of {years:g} years, 1 - exp(-MAF x {years:g}) "
                     "(occurrences a Poisson process)")
    if "gap_at_target" in ds:
        def mm(name):
            value = float(ds[name])
            return f"{1000 * value:.1f}" if math.isfinite(value) else "NaN"

        gap = (f"{mm('gap_at_target')} mm" if math.isfinite(float(ds.gap_at_target)) else
               "NaN (not given: see the warnings)")
        lines.append(f"gap at annual frequency {float(ds.target_annual_frequency):.3g} "
                     f"(return period {1 / float(ds.target_annual_frequency):.0f} years, "
                     f"IM {float(ds.intensity_at_target):.3g} g): {gap} "
                     f"(90 % bootstrap {mm('gap_at_target_low')}-{mm('gap_at_target_high')} "
                     f"mm; regression {mm('gap_at_target_regression')} mm)")
        if "rule_separation_at_target" in ds:
            lines.append("code rules at that IM (median over the records): " + ", ".join(
                f"{r} {1000 * float(v):.1f} mm" for r, v in
                zip(ds.rule_name.values, ds.rule_separation_at_target.values)))
    return "\n".join(lines)
