"""``pframe expand MODEL.yaml``: the dimensional scene a Pi-form scene stands for, or a scene
written in another unit system in SI (docs/units.md)."""

from __future__ import annotations

import sys
from pathlib import Path

from pframe.commands import checked_output, write_text_output


def expanded_text(path: Path) -> str | None:
    """The dimensional YAML of a Pi-form scene file, or the SI YAML of a scene in another
    unit system; None for a dimensional scene in SI."""
    from pframe.nondim.emit import dump_scene
    from pframe.nondim.pi_form import is_pi_form, pi_expansion
    from pframe.reader import load_scene

    loaded = load_scene(path)  # validates both forms, with line numbers
    data, lines = loaded.data, loaded.lines
    if not is_pi_form(data):
        return None if loaded.system.si else _in_si(path, data, loaded.system)
    expansion = pi_expansion(data, lines, str(path), path.parent)
    expanded, s = expansion.data, expansion.scales
    header = [
        f"Expanded from the Pi-form scene {path} by 'pframe expand'.",
        f"Reference scales: m_b = {s['m_b']!r} kg, a_p = {s['a_p']!r} m/s^2, "
        f"w_p = {s['w_p']!r} rad/s; l_e = a_p / w_p^2 = {s['a_p'] / s['w_p'] ** 2!r} m.",
    ]
    if data.get("excitation", {}).get("kind") == "record":
        found = expansion.excitation
        header.append(f"The record is scaled to its PGA a_p and its time axis to w_p = "
                      f"{found.frequency_is}.")
    header += _group_lines(expansion.groups)
    header.append("dt = dtau / w_p, duration = tau / w_p.")
    return dump_scene(expanded, header, "../schemas/model.schema.json")


def _in_si(path: Path, data: dict, system) -> str:
    """A scene written in ``system``, in SI (the scene pframe runs; docs/units.md)."""
    from pframe.nondim.emit import dump_scene
    from pframe.nondim.scene_units import to_si

    header = [f"Converted from {path} (units: {system.name}) to SI (N, m, kg, s) by "
              "'pframe expand'."]
    return dump_scene({k: v for k, v in to_si(data, system).items() if k != "units"}, header,
                      "../schemas/model.schema.json")


def _group_lines(groups, width: int = 96) -> list[str]:
    """``Pi_k = K_a / (m_b w_p^2), ...`` wrapped into lines."""
    lines, line = [], "Pi groups:"
    for group in groups:
        item = f" {group.name} = {group.formula()},"
        if len(line) + len(item) > width:
            lines.append(line)
            line = " "
        line += item
    return lines + [line.rstrip(",")]


def _expand(args) -> int:
    path = Path(args.model)
    checked_output(args.output, args.overwrite, [args.model])  # before any work
    text = expanded_text(path)
    if text is None:
        print(f"pframe: {path} is a dimensional scene already; "
              f"{'printed' if args.output is None else 'written'} unchanged", file=sys.stderr)
        from pframe.yamltext import read_bounded

        text = read_bounded(path, "model")
    write_text_output(text, args.output, args.overwrite, inputs=[args.model])
    return 0


def register(sub) -> None:
    expand = sub.add_parser("expand", help="print the dimensional scene of a Pi-form scene, or "
                                "a scene written in another unit system in SI")
    expand.add_argument("model", help="scene file in Pi form (YAML with a 'pi:' mapping) or in "
                        "another unit system (units: kN-m-t, ...)")
    expand.add_argument("-o", "--output", help="write the YAML here instead of printing it")
    expand.add_argument("--overwrite", action="store_true", help="replace an existing output")
    expand.set_defaults(run=_expand)
