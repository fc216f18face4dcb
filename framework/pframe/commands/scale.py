"""``pframe scale``: similitude ratios of a scale model, and scaling a scene.

    pframe scale --length 1/16 --modulus 1 --acceleration 1
    pframe scale MODEL.yaml --length 1/16 --modulus 1 --acceleration 1 [--to prototype] [-o OUT]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from pframe.commands import checked_output, write_text_output

#: the quantities a ratio may be chosen for (pframe.nondim.similitude.QUANTITIES)
CHOICES = ("length", "displacement", "time", "frequency", "velocity", "acceleration", "mass",
           "density", "force", "stiffness", "modulus", "energy")


class _Factor(argparse.Action):
    """Collects ``--length 1/16`` etc. in command-line order (the first three independent
    ratios form the basis)."""

    def __call__(self, parser, namespace, value, option_string=None):
        factors = list(getattr(namespace, "factors", None) or [])
        factors.append((self.dest, value))
        namespace.factors = factors


def _table(sim) -> list[str]:
    rows = sim.rows()
    chosen = ", ".join(f"{name} {value}" for name, value in sim.chosen)
    out = [f"similitude S = model / prototype, from {chosen}",
           f"  {'quantity':<13}{'symbol':<7}{'dimension':<14}{'ratio':<16}value"]
    for r in rows:
        how = "chosen" if r["status"] == "chosen" else f"implied: {r['formula']}"
        out.append(f"  {r['quantity']:<13}{r['symbol']:<7}{r['dimension']:<14}{r['ratio']:<16}"
                   f"{r['value']:<13.6g}{how}")
    return out + [f"note: {n}" for n in sim.notes()]


def _scale(args) -> int:
    import json

    from pframe.nondim.similitude import similitude

    sim = similitude(dict(args.factors or []))
    if args.model is None:
        if args.json:
            print(json.dumps({"chosen": [[n, str(v)] for n, v in sim.chosen],
                              "rows": sim.rows(), "notes": sim.notes()}, indent=2))
        else:
            print("\n".join(_table(sim)))
        return 0
    checked_output(args.output, args.overwrite, [args.model])  # before any work
    text = _scaled_scene(Path(args.model), sim, args.to)
    write_text_output(text, args.output, args.overwrite, inputs=[args.model])
    return 0


def _scaled_scene(path: Path, sim, to: str) -> str:
    from pframe.errors import InputError
    from pframe.nondim.emit import dump_scene
    from pframe.nondim.pi_form import is_pi_form
    from pframe.nondim.similitude import SimilitudeError, scale_scene
    from pframe.reader import load_scene, parse_scene
    from pframe.yamltext import where

    loaded = load_scene(path)
    if loaded.expanded.foundations:
        raise InputError(f"{path}: pframe scale does not scale soil yet (docs/soil.md: its "
                         "springs, dashpots and foundation inertias); remove soil")
    data, lines = loaded.data, loaded.lines
    try:
        scaled = scale_scene(data, sim, to)
    except SimilitudeError as exc:  # the file, line and field of a value it cannot scale
        if exc.path is None:
            raise InputError(f"{path}: {exc}") from None
        raise InputError(f"{where(str(path), lines, exc.path)}: {exc.reason}") from None
    header = [f"{path} scaled to {to} size by 'pframe scale' (S = model / prototype):"]
    header += [line.strip() for line in _table(sim)[2:]]
    schema = "pi-scene" if is_pi_form(data) else "model"
    text = dump_scene(scaled, header, f"../schemas/{schema}.schema.json")
    parse_scene(text, f"{path} scaled", loaded.base_dir)  # the result is a valid scene
    return text


def register(sub) -> None:
    scale = sub.add_parser(
        "scale", help="similitude ratios of a scale model; scale a scene to model size",
        description="Give three independent scale ratios S = model / prototype (for a "
        "shaking-table model: --length, --modulus, --acceleration); every other ratio is "
        "derived, exactly. With MODEL, print (or write) the scene scaled.")
    scale.add_argument("model", nargs="?", help="scene file to scale (dimensional or Pi form)")
    for name in CHOICES:
        scale.add_argument(f"--{name}", dest=name, action=_Factor, metavar="S",
                           help=f"{name} ratio, e.g. 1/16")
    scale.add_argument("--to", choices=("model", "prototype"), default="model",
                       help="scale MODEL to model size (multiply by S, default) or to "
                       "prototype size (divide by S)")
    scale.add_argument("-o", "--output", help="write the scaled scene here")
    scale.add_argument("--overwrite", action="store_true", help="replace an existing output")
    scale.add_argument("--json", action="store_true", help="print the ratios as JSON")
    scale.set_defaults(run=_scale, factors=None)
