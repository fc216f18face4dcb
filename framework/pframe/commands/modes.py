"""``pframe modes FILE.yaml``: the modes of a scene's buildings (fixed base, on their soil,
isolated) and of the scene its links couple: periods, directions, participation factors,
effective modal masses and damping ratios, as tables (``pframe.modal``; docs/modes.md)."""

from __future__ import annotations

#: modes shown per analysis unless --count says otherwise
SHOWN = 12


def _modes(args) -> int:
    from pframe.api import count_argument, loaded_scene
    from pframe.modal import dataset, table_lines

    shown = count_argument(args.count, "--count", "modes") or SHOWN
    ds = dataset(loaded_scene(args.scene))
    for line in table_lines(ds, shown):
        print(line)
    return 0


def register(sub) -> None:
    p = sub.add_parser("modes", help="a scene's modes: periods, directions, participation, "
                       "effective masses, damping ratios")
    p.add_argument("scene", help="scene file (.yaml) or a result file (.nc) of one")
    p.add_argument("--count", type=int, default=None,
                   help=f"modes shown per analysis (default {SHOWN}; every mode is computed)")
    p.set_defaults(run=_modes)
