"""One chunk of a sweep: its variants validated, assembled into one batch and run by the kernel.

:func:`run_chunk` is a pure function of the sweep definition and the chunk's index; it returns
plain numpy arrays (no pickled objects), so the same chunk computed in this process, in another
thread or on a cluster worker gives the same arrays, and they can be saved as they are.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from pframe.errors import InputError, PframeError
from pframe.model.scene import Envelope
from pframe.quantities import QUANTITIES
from pframe.sweep.definition import RESPONSES
from pframe.sweep.grid import Spec, parse
from pframe.sweep.probing import PLANAR_LAYOUT, TOPOLOGY_CHANGED, in_plan, topology
from pframe.sweep.spec import code_fingerprint
from pframe.verdict import of_result

#: per-variant bookkeeping kept beside the responses
STATUS_FIELDS = ("complete", "status", "steps_completed", "energy_balance_error",
                 "algorithmic_dissipation", "trusted", "newton_solves", "split_steps")
#: a variant that never ran (its scene is invalid) holds this in its integer responses
MISSING_COUNT = -1


def _yield_drift(plan, member: int) -> np.ndarray:
    """Yield drift of each storey: f_y / k of a law with ``stiffness`` and ``yield_force``
    parameters (bilinear), its ``yield_drift`` parameter, or NaN (an elastic storey)."""
    out = np.full(len(plan.story_names), np.nan)
    for group in plan.story_groups:
        names = group.law.param_names
        params = group.params[member]
        if "yield_force" in names and "stiffness" in names:
            values = params[:, names.index("yield_force")] / params[:, names.index("stiffness")]
        elif "yield_drift" in names:
            values = params[:, names.index("yield_drift")]
        else:
            continue
        out[group.index] = values
    return out


def _buildings(plan) -> tuple[np.ndarray, np.ndarray]:
    """Building index of each declared node and of each storey."""
    node_building = np.array([plan.buildings.index(name.split("/")[0])
                              for name in plan.node_names], dtype=np.int64)
    building_of_dof = np.empty(plan.n_dof, dtype=np.int64)
    building_of_dof[plan.node_dof] = node_building
    return node_building, building_of_dof[plan.story_dofs[:, 1]]


def _per_building(values: np.ndarray, owner: np.ndarray, count: int) -> np.ndarray:
    out = np.full(count, np.nan)
    for b in range(count):
        mine = values[owner == b]
        if mine.size and not np.all(np.isnan(mine)):
            out[b] = np.nanmax(mine)
    return out


@dataclasses.dataclass(frozen=True)
class Layout:
    """What each variant contributes to the sweep's file (besides the sweep's axes): each
    array's trailing dimensions and their sizes, from the base scene. ``in_plan``: the nodes
    are written along the site's x and y with their rotation (``<q>_rz``), as ``pframe
    solve`` writes a scene in plan; a base scene is in plan when it moves its floors in plan,
    names plan points (a floor plan) or has a motion in two components, and every variant is
    then written so (a DOF a variant does not move is 0)."""

    in_plan: bool
    dims: dict  # name -> trailing dimension names
    sizes: dict  # dimension name -> length

    @property
    def shapes(self) -> dict[str, tuple]:
        return {name: tuple(self.sizes[d] for d in dims) for name, dims in self.dims.items()}


def _entity_dims(entity, plan: bool, channels: int) -> tuple[tuple[str, ...], ...]:
    """The trailing dimensions of the arrays of a quantity of ``entity``: one array, or in
    plan a node quantity along the site's x and y and its rotation (as ``pframe solve``)."""
    if entity is None:
        return (("direction",),) if channels > 1 else ((),)
    if entity == "node" and plan:
        return ("node", "direction"), ("node",)
    if entity == "point":
        return (("point", "axis"),)
    return ((entity,),)


def layout(spec: Spec, expanded) -> Layout:
    """The :class:`Layout` of a sweep from its base scene: responses along their entity,
    histories along time and entity."""
    plan = in_plan(expanded)
    sizes = {"node": len(expanded.node_names), "story": len(expanded.stories),
             "contact": len(expanded.contacts), "building": len(expanded.buildings),
             "link": len(expanded.links), "foundation": len(expanded.foundations),
             "point": len(expanded.point_names), "axis": 2, "direction": 2,
             "t": expanded.steps // spec.model.keep.every + 1}
    channels = len(expanded.channels)
    dims = {}
    for name in spec.responses:
        entity = RESPONSES[name]
        if entity is not None and not sizes[entity]:
            continue
        if name.startswith("peak_") and name[len("peak_"):] in QUANTITIES:
            q = name[len("peak_"):]
            dims.update(zip(_names(q, entity, plan, "peak_"),
                            _entity_dims(entity, plan, channels)))
        else:
            dims[name] = (entity,) if entity else ()
    if plan and expanded.point_names:
        dims["torsional_irregularity"] = ("node", "axis")
    for q in spec.model.keep.histories:
        entity = QUANTITIES[q][0]
        if entity is not None and not sizes[entity]:
            continue
        dims.update((each, ("t",) + trailing) for each, trailing in zip(
            _names(q, entity, plan, ""), _entity_dims(entity, plan, channels)))
    return Layout(plan, dims, sizes)


def _names(q: str, entity, plan: bool, prefix: str) -> tuple[str, ...]:
    """The arrays of quantity ``q``: itself, and in plan a node quantity's rotation."""
    from pframe.record.hdf5 import ROTATION

    if plan and entity == "node":
        return prefix + q, prefix + ROTATION[q][0]
    return (prefix + q,)


def _site(plan, data: np.ndarray) -> np.ndarray:
    """(..., nodes, 3) a node quantity in the kernel's DOF order as each node's u_x, u_y,
    theta (0 where the plan does not move it)."""
    out = np.zeros(data.shape[:-1] + (len(plan.node_names), 3))
    own = plan.dof_node >= 0  # not a foundation's DOF
    out[..., plan.dof_node[own], plan.dof_component[own]] = data[..., own]
    return out


def _quantity(plan, q: str, data, convert, in_plan_layout: bool) -> list[np.ndarray]:
    """The arrays of quantity ``q`` (:func:`_names`) from the kernel's columns ``data`` (an
    envelope (width,) or a history (rows, width)), in the result file's units."""
    from pframe.record.hdf5 import ROTATION

    data = np.asarray(data, dtype=float)
    entity, units = QUANTITIES[q][0], QUANTITIES[q][1]
    if entity == "point":
        data = data.reshape(data.shape[:-1] + (data.shape[-1] // 2, 2))
    if entity != "node":
        return [convert.variable(data, units, "")[0]]
    if not in_plan_layout:
        return [convert.variable(data[..., plan.node_dof], units, "")[0]]
    site = _site(plan, data)
    return [convert.variable(site[..., :2], units, "")[0],
            convert.variable(site[..., 2], ROTATION[q][1], "")[0]]


def responses_of(spec: Spec, plan, result, member: int, convert,
                 layout: Layout | None = None, expanded=None) -> dict[str, np.ndarray]:
    """The kept responses of one batch member, in the units of the result file, in the
    sweep's ``layout`` (default: the planar layout); ``expanded``, the member's scene (its
    named points' positions: the torsional irregularity)."""
    from pframe.irregularity import torsional_irregularity

    flat = layout is None or not layout.in_plan

    def peak(q):
        return _quantity(plan, q, result.envelope[q][member], convert, not flat)

    node_building, story_building = _buildings(plan)
    nb = len(plan.buildings)
    out = {}
    for name in spec.responses:
        entity = RESPONSES[name]
        if entity in ("contact",) and not plan.contact_names:
            continue
        if entity == "story" and not plan.story_names:
            continue
        if name == "impact_count":
            out[name] = result.impacts[member].astype(np.int32)
        elif name == "ductility":
            out[name] = result.envelope["story_drift"][member] / _yield_drift(plan, member)
        elif name == "building_peak_displacement":
            # in plan: the largest of the centres of mass along the site's x and y
            moved = peak("displacement")[0]
            per_node = moved if flat else np.max(moved, axis=-1)
            out[name] = _per_building(per_node, node_building, nb)
        elif name == "building_peak_story_drift":
            out[name] = _per_building(peak("story_drift")[0], story_building, nb)
        elif name == "building_peak_ductility":
            ductility = result.envelope["story_drift"][member] / _yield_drift(plan, member)
            out[name] = _per_building(ductility, story_building, nb)
        else:
            q = name[len("peak_"):]
            if QUANTITIES[q][0] is not None and layout is not None \
                    and not layout.sizes[QUANTITIES[q][0]]:
                continue
            out.update(zip(_names(q, QUANTITIES[q][0], not flat, "peak_"), peak(q)))
    if not flat and "torsional_irregularity" in layout.dims:
        points = np.asarray(result.envelope["point_drift"][member]).reshape(-1, 2)
        out["torsional_irregularity"] = torsional_irregularity(
            plan.point_names, expanded.point_positions, points, plan.node_names)
    return out


def _histories_of(plan, result, member: int, convert,
                  layout: Layout | None = None) -> dict[str, np.ndarray]:
    flat = layout is None or not layout.in_plan
    out = {}
    for q, _ in plan.history:
        entity = QUANTITIES[q][0]
        if entity is not None and layout is not None and not layout.sizes[entity]:
            continue
        out.update(zip(_names(q, entity, not flat, ""),
                       _quantity(plan, q, result.history[q][member], convert, not flat)))
    return out


def _placeholder(name: str, shape: tuple):
    if name == "impact_count":
        return np.full(shape, MISSING_COUNT, dtype=np.int32)
    return np.full(shape, np.nan)


def _not_run(shapes: dict, reason: str) -> dict:
    row = {name: _placeholder(name, shape) for name, shape in shapes.items()}
    row.update(complete=np.int8(0), status=f"invalid scene: {reason}",
               steps_completed=np.int32(0), energy_balance_error=np.nan,
               algorithmic_dissipation=np.nan, trusted=np.int8(0), newton_solves=np.int64(0),
               split_steps=np.int64(0), scales=np.full(3, np.nan),
               dt=np.nan, duration=np.nan, record_duration=np.nan)
    return row


def recorders(spec: Spec, layout: Layout) -> tuple:
    """The recorders of the sweep's runs: the sweep's own, and in plan the envelope of the
    points' drift that the torsional irregularity is read off (which assembly adds to a
    scene that moves in plan, but not to a variant that happens not to)."""
    if "torsional_irregularity" not in layout.dims:
        return spec.recorders
    return spec.recorders + (Envelope(kind="envelope", quantities=["point_drift"]),)


def _assemble(spec: Spec, loaded: dict, rows: dict, layout: Layout):
    """The batch of the valid variants. A variant that assembly refuses (an explicit step
    above its stability limit) is found alone and recorded as not run; the others go on."""
    from pframe.assemble import assemble, assemble_batch

    members = sorted(loaded)
    kept = recorders(spec, layout)
    expanded = {i: dataclasses.replace(loaded[i].expanded, recorders=kept) for i in members}
    if not members:
        return [], None
    try:
        return members, assemble_batch([expanded[i] for i in members])
    except InputError:
        pass
    good = []
    for i in members:
        try:
            assemble(expanded[i])
            good.append(i)
        except InputError as exc:
            rows[i] = _not_run(layout.shapes, str(exc))
    return good, (assemble_batch([expanded[i] for i in good]) if good else None)


def run_chunk(definition, chunk: int, threads: int | None = 1) -> dict[str, np.ndarray]:
    """Run chunk ``chunk`` of a sweep; return its arrays, one row per variant.

    Keys: each kept response (``peak_displacement`` ...) and history (NaN after a variant's
    last step when the chunk's variants run for different times), the :data:`STATUS_FIELDS`,
    ``scales`` (m_b, a_p, w_p of dimensionless output, NaN for SI), ``dt``, ``duration`` (s,
    analysed), ``record_duration`` (s, the record as applied; NaN without one),
    ``warnings``, and ``solve_seconds`` / ``compile_seconds`` (this computation's timing,
    which the result file leaves out). A variant whose scene is invalid is not run: NaN (-1
    for counts) and its reason in ``status``. Variants of different numbers of steps (records
    of different lengths, docs/sweeps.md#durations-under-records) run as one batch per number
    of steps.
    """
    from pframe.kernel import simulate
    from pframe.outputs import check_stop
    from pframe.sweep.variants import cut_warning, load_fitted, materialise, record_end

    if definition.code != code_fingerprint():
        raise PframeError(
            f"{definition.source}: this process runs other pframe code ({code_fingerprint()}) "
            f"than the sweep was started with ({definition.code}); every process computing "
            "chunks of a sweep needs the same pframe (install it alike on every worker)")
    spec = parse(definition)
    folder = materialise(definition)
    reference, layout = _reference(definition)
    loaded, rows = {}, {}
    warnings: list[str] = []
    for index in spec.chunk_range(chunk):
        check_stop()  # Ctrl-C: a chunk's variants take long to load; stop between them
        try:
            scene = load_fitted(spec, index, folder)
            if topology(scene.expanded, spec.recorders, spec) != reference:
                raise InputError(TOPOLOGY_CHANGED)
            if not layout.in_plan and in_plan(scene.expanded):
                raise InputError(PLANAR_LAYOUT)
            loaded[index] = scene
        except InputError as exc:
            rows[index] = _not_run(layout.shapes, str(exc).replace(str(folder) + "/", ""))
            continue
        cut = cut_warning(spec, index, scene.expanded)
        if cut is not None:
            warnings.append(cut)

    solve_seconds = compile_seconds = 0.0
    by_steps: dict[int, dict] = {}
    for index in sorted(loaded):
        by_steps.setdefault(loaded[index].expanded.steps, {})[index] = loaded[index]
    for _, group in sorted(by_steps.items()):
        members, plan = _assemble(spec, group, rows, layout)
        if not members:
            continue
        warnings += [w for w in plan.warnings if w not in warnings]
        result = simulate(plan, threads=threads)
        solve_seconds += result.solve_seconds
        compile_seconds += result.compile_seconds
        for member, index in enumerate(members):
            expanded = loaded[index].expanded
            convert = loaded[index].units  # its reference scales, found when it was read
            values = responses_of(spec, plan, result, member, convert, layout, expanded)
            values.update(_histories_of(plan, result, member, convert, layout))
            end = record_end(expanded)
            verdict = of_result(result, member)
            values.update(
                complete=np.int8(result.completed(member)),
                status=result.describe_failure(member),
                steps_completed=np.int32(result.states_done(member) - 1),
                energy_balance_error=verdict.balance_error,
                algorithmic_dissipation=verdict.algorithmic,
                trusted=np.int8(verdict.trusted),
                newton_solves=np.int64(result.iterations[member]),
                split_steps=np.int64(result.substeps[member]),
                scales=(np.array([convert.scales[k] for k in ("m_b", "a_p", "w_p")], dtype=float)
                        if convert.dimensionless else np.full(3, np.nan)),
                dt=float(plan.dt[member]),
                duration=float(plan.steps * plan.dt[member]),
                record_duration=np.nan if end is None else end,
            )
            rows[index] = values

    ordered = [rows[i] for i in spec.chunk_range(chunk)]
    for q in (name for name, dims in layout.dims.items() if dims[:1] == ("t",)):
        if q in ordered[0]:  # pad shorter runs with NaN to the chunk's longest
            longest = max(len(row[q]) for row in ordered)
            for row in ordered:
                if len(row[q]) < longest:
                    pad = np.full((longest - len(row[q]),) + row[q].shape[1:], np.nan)
                    row[q] = np.concatenate([row[q], pad])
    arrays = {key: np.array([row[key] for row in ordered]) for key in ordered[0]}
    arrays["status"] = np.array([row["status"] for row in ordered], dtype=str)
    arrays["warnings"] = np.array(warnings, dtype=str)
    arrays["solve_seconds"] = np.float64(solve_seconds)
    arrays["compile_seconds"] = np.float64(compile_seconds)
    return arrays


def _reference(definition) -> tuple[tuple, Layout]:
    """The topology every variant must share and the :class:`Layout` of a variant's arrays,
    both from the base scene (cached per definition)."""
    cached = _references.get(definition.digest)
    if cached is None:
        spec = parse(definition)
        base = spec.base_scene()
        cached = (topology(base.expanded, spec.recorders, spec), layout(spec, base.expanded))
        _references[definition.digest] = cached
    return cached


_references: dict[str, tuple] = {}


def warm_up(definition) -> float:
    """Compile (or load from the on-disk cache) the sweep's kernel with a one-step run of the
    base scene, so that threads running chunks side by side never compile it twice. Returns
    the seconds it took."""
    from pframe.assemble import assemble
    from pframe.kernel import simulate
    spec = parse(definition)
    start = time.perf_counter()
    base = spec.base_scene()
    ex = base.expanded
    expanded = ex.first_steps(1, recorders=spec.recorders)
    simulate(assemble(expanded), threads=1)
    return time.perf_counter() - start
