"""``pframe validate MODEL.yaml``: check a scene without running it."""

from __future__ import annotations


def _validate(args) -> int:
    from pframe.model import load_scene

    loaded = load_scene(args.model)
    ex = loaded.expanded
    print(f"{loaded.source}: valid; {len(ex.node_names)} nodes in {len(ex.buildings)} buildings, "
          f"{len(ex.stories)} storeys, {len(ex.contacts)} contacts, {ex.steps} steps")
    return 0


def register(sub) -> None:
    validate = sub.add_parser("validate", help="check a scene file without running it")
    validate.add_argument("model")
    validate.set_defaults(run=_validate)
