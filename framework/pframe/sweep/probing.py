"""The checks a sweep passes before anything runs: probes of its variants through the loader."""

from __future__ import annotations

import dataclasses

import numpy as np

from pframe.errors import InputError
from pframe.model.load import validated
from pframe.sweep.grid import AxisSpec, Spec, parse
from pframe.sweep.spec import SweepDefinition

#: why a variant cannot join its batch
TOPOLOGY_CHANGED = ("the variant differs from the base scene in topology (nodes, storeys, "
                    "contacts, laws, integrator, number of steps) or in a setting its batch "
                    "shares (Newton tolerances and iterations); a sweep varies numbers that "
                    "each variant may have on its own")
#: why a variant that moves its floors in plan cannot join a sweep of the planar layout
PLANAR_LAYOUT = ("the variant moves its floors in plan (along y or turning), but the sweep "
                 "writes the planar layout of its base scene (one value per node, along x): "
                 "write the base scene in plan (give its buildings a plan: {size: [...]}, or "
                 "take as the base a value at which its floors already move in plan) so that "
                 "every variant is written with its nodes' x, y and rotation "
                 "(docs/sweeps.md#scenes-in-plan)")


def in_plan(expanded) -> bool:
    """Whether a sweep of this base scene writes the layout of a scene in plan
    (:class:`pframe.sweep.chunk.Layout`): it moves its floors in plan, names plan points (a
    floor plan) or has a motion in two components."""
    return (expanded.dofs is not None or bool(expanded.point_names)
            or "y" in expanded.channels)


def topology(expanded, recorders, spec=None) -> tuple:
    """What variants of one sweep must share (as :func:`pframe.assemble.assemble_batch`
    requires), with the sweep's recorders. Under a record (``spec.base_record``) the number
    of steps may differ: each variant runs its own record's length, and a chunk runs one
    batch per number of steps (docs/sweeps.md#durations-under-records)."""
    from pframe.assemble import batch_key

    steps = 0 if spec is not None and spec.base_record is not None else expanded.steps
    return batch_key(dataclasses.replace(expanded, recorders=recorders, steps=steps))


def check(definition: SweepDefinition) -> None:
    """Validate probes of the sweep before anything runs: every value of every axis through
    the scene model, and variant 0, each axis's first and last values and every record file
    through the whole loader (expansion to numbers and the topology check). A problem only
    some combination of values has is found when its chunk runs (the variant is recorded as
    failed, with the reason)."""
    from pframe.sweep.variants import load_fitted, materialise, variant_data

    spec = parse(definition)
    folder = materialise(definition)
    base = spec.base_scene()
    reference = topology(base.expanded, spec.recorders, spec)
    probes: dict[int, tuple[AxisSpec | None, bool]] = {0: (None, True)}
    for axis in spec.axes:
        count = len(axis.values)
        for position in range(count):
            whole = axis.is_file or position in (0, count - 1)
            index = _index_with(spec, axis, position)
            if index not in probes or (whole and not probes[index][1]):
                probes[index] = (axis, whole)
    for index, (axis, whole) in sorted(probes.items()):
        try:
            data = variant_data(spec, index)
            if whole:
                loaded = load_fitted(spec, index, folder)
                if topology(loaded.expanded, spec.recorders, spec) != reference:
                    raise InputError(TOPOLOGY_CHANGED)
                if in_plan(loaded.expanded) and not in_plan(base.expanded):
                    raise InputError(PLANAR_LAYOUT)
            else:
                _validate_model(data, spec, folder)
        except InputError as exc:
            message = str(exc).replace(str(folder) + "/", "")
            axis = axis or spec.axes[0]
            raise InputError(f"{spec.where('axes', axis.index)}: axis {axis.name!r}, variant "
                             f"{index} ({spec.describe(index)}): {message}") from None


def _validate_model(data: dict, spec: Spec, folder) -> None:
    """The scene model's checks alone (no expansion to numbers): cheap enough for every value."""
    from pframe.model.load import plugin_names as _plugin_names
    from pframe.model.scene import scene_class

    lines, source = spec.base_lines, spec.base_where
    if "pi" in data:
        from pframe.nondim.pi_form import expand_pi_data

        data = expand_pi_data(data, lines, source, folder)  # a record is read from there
    plugins = _plugin_names(data, lines, source)
    validated(scene_class(*plugins), data, lines, source)


def _index_with(spec: Spec, axis: AxisSpec, position: int) -> int:
    if spec.model.combine == "zip":
        return position
    positions = [0] * len(spec.axes)
    positions[spec.axes.index(axis)] = position
    return int(np.ravel_multi_index(positions, spec.shape))
