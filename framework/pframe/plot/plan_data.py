"""What the figures of a scene in plan read beyond the histories (no matplotlib): how far each
contact's two points have closed along its normal, and each storey's torsional irregularity.

A contact in plan acts at a point of each floor along its normal n (docs/plan.md): it closes
by ``side(left) - side(right)``, each side the sum of ``a . (u_x, u_y, theta)`` over its
floors with ``a = (n_x, n_y, (P - c) x n)`` (:mod:`pframe.model.plan`; Chopra, Dynamics of
Structures, ch. 9). The file stores the floors' histories, not the sides: they are the
scene's (its ``input_yaml``), expanded here exactly as the run expanded them, so the
gap-closing figure draws what the kernel's contact saw.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pframe.errors import InputError

#: the derived history of the gap-closing figure of a scene in plan
CLOSING = "contact_closing"
#: a side's component (0 u_x, 1 u_y, 2 theta) -> the history holding it
COMPONENT_HISTORY = ("displacement_x", "displacement_y", "displacement_rz")


def contact_closing(ds, source: str, histories: dict, contacts) -> tuple:
    """``(values or None, note)``: the closing ``side(left) - side(right)`` of each of
    ``contacts`` along its normal (m), ``values[k, j]`` at the time of the floors'
    displacement histories (``histories``, as :func:`pframe.plot.data.read_result` reads
    them), from the scene's contact sides; None with the reason when the scene cannot say (no
    note when the scene has no contact or the file no displacement history: the figures say
    that)."""
    parts = [histories.get(q) for q in COMPONENT_HISTORY]
    if not contacts or any(h is None for h in parts):
        return None, ""
    if (parts[0].units, parts[1].units, parts[2].units) != ("m", "m", "rad"):
        # a lever arm (m) times a rotation adds to a displacement in m only
        return None, ("the floors' displacements are not in m and rad (a dimensionless "
                      "file): no gap-closing panels")
    from pframe.api import scene_of_attributes

    try:
        expanded = scene_of_attributes(dict(ds.attrs), source, Path(".")).expanded
    except InputError as exc:
        return None, (f"the contacts' points and normals come from the scene the result holds, "
                      f"and it cannot be read ({exc}): no gap-closing panels")
    if tuple(expanded.node_names) != tuple(parts[0].names) or \
            [c.name for c in expanded.contacts] != list(contacts):
        return None, ("the scene the result holds does not name the file's floors and "
                      "contacts: no gap-closing panels")
    values = np.zeros((parts[0].time.size, len(contacts)))
    for j, element in enumerate(expanded.contacts):
        for sign, terms in zip((1.0, -1.0), element.side_terms()):
            for node, component, coefficient in terms:
                values[:, j] += sign * coefficient * parts[component].values[:, node]
    return values, ""


def torsion_ratios(ds, nodes) -> dict:
    """``floor -> (ratio along x, ratio along y)`` of the file's ``torsional_irregularity``
    (its building's axes; NaN where not defined), or {} when the file has none."""
    if "torsional_irregularity" not in ds.variables:
        return {}
    ratio = np.asarray(ds["torsional_irregularity"].values, dtype=float)
    if ratio.shape != (len(nodes), 2):
        return {}
    return {node: (float(x), float(y)) for node, (x, y) in zip(nodes, ratio)}


def gap_closing_in_plan(result, contact: str):
    """:func:`pframe.plot.figure.gap_closing` of a contact in plan: ``(time, closing, gap,
    onsets)`` with the closing of its points along its normal (:func:`contact_closing`),
    None when the file lacks it or the gap."""
    along = result.histories.get(CLOSING)
    if along is None or contact not in along.names or contact not in result.gaps:
        return None
    closing, gap = along.column(contact), result.gaps[contact]
    closed = closing > gap  # each impact: the closing rises past the gap (as in the kernel)
    onsets = np.flatnonzero(closed & ~np.concatenate(([False], closed[:-1])))
    return along.time, closing, gap, along.time[onsets]
