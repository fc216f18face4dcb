"""Which floor level each node, storey and contact of a result file belongs to.

A *level* is the floor part of a node name (``3`` for ``A/3``): the paper draws one figure per
level, with the floors of both buildings at that level, the contact between them and the
storeys below them. The rules:

- a node ``B/L`` is floor ``L`` of building ``B``;
- a storey belongs to the level of its upper node: the storey's own name for the building
  shorthand (``A/1`` is the storey below floor ``A/1``), or the ``nodes`` of a named storey in
  the scene text the file holds (``input_yaml``);
- a contact belongs to the levels of its two nodes, read from the ``contacts`` of the scene
  text (so its name may be anything), else from a default name ``<left>-<right>``. A contact
  between floors of different numbers (``A/3-B/2``) is drawn on both levels' figures.

Everything here is plain Python on names: no HDF5, no matplotlib.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Levels:
    """Names of a result file grouped by floor level.

    Attributes
    ----------
    order : tuple of str
        The levels, numeric ones in numeric order first, then the others as they appear.
    buildings : tuple of str
        Building names in the order of the file's nodes (left to right in the paper's figures).
    nodes, stories : dict
        ``level -> {building: name}``: the floor (storey) of each building at that level.
    contacts : dict
        ``level -> [contact name, ...]`` in the file's order.
    unplaced : tuple of str
        Storeys and contacts whose level could not be found (they are not drawn).
    lines : dict
        ``level -> {building: [storey name, ...]}``: every storey element below each
        building's floor at that level, in the file's order (a building in plan has one per
        line of resistance, ``A/3/X1``, ``A/3/Y1``, ...; a planar building one, as in
        ``stories``).
    """

    order: tuple[str, ...]
    buildings: tuple[str, ...]
    nodes: dict[str, dict[str, str]]
    stories: dict[str, dict[str, str]]
    contacts: dict[str, list[str]]
    unplaced: tuple[str, ...]
    lines: dict[str, dict[str, list[str]]] = field(default_factory=dict)


def _split(node: str) -> tuple[str, str] | None:
    building, sep, floor = node.partition("/")
    return (building, floor) if sep and building and floor else None


def _level_key(level: str, first_seen: dict[str, int]):
    return (0, int(level), "") if level.isdigit() else (1, first_seen[level], level)


def _scene_elements(input_yaml: str | None) -> tuple[dict[str, str], dict[str, tuple[str, str]]]:
    """From the scene text: named storey -> upper node, and contact name -> (left, right)."""
    from pframe.errors import InputError as _Unreadable
    from pframe.yamltext import load

    try:
        scene = load(input_yaml) if input_yaml else None
    except _Unreadable:
        scene = None
    if not isinstance(scene, dict):
        return {}, {}
    if "pi" in scene:  # a Pi-form scene: its contacts are named only once it is expanded
        from pframe.errors import InputError
        from pframe.nondim.pi_form import expand_pi_data

        try:
            scene = expand_pi_data(scene, {}, "input_yaml")
        except InputError:
            return {}, {}
    stories, contacts = {}, {}
    for story in scene.get("stories") or []:
        if isinstance(story, dict) and isinstance(story.get("nodes"), list | tuple) \
                and len(story["nodes"]) == 2:
            stories[str(story.get("name") or story["nodes"][1])] = str(story["nodes"][1])
    for contact in scene.get("contacts") or []:
        if isinstance(contact, dict) and isinstance(contact.get("nodes"), list | tuple) \
                and len(contact["nodes"]) == 2:
            left, right = map(str, contact["nodes"])
            contacts[str(contact.get("name") or f"{left}-{right}")] = (left, right)
    return stories, contacts


def group_by_level(node_names, story_names=(), contact_names=(), input_yaml: str | None = None,
                   known: tuple[dict, dict] | None = None) -> Levels:
    """Group a result file's coordinate names by floor level (rules in the module docstring).

    Parameters
    ----------
    node_names, story_names, contact_names : sequence of str
        The ``node``, ``story`` and ``contact`` coordinates of the file.
    input_yaml : str, optional
        The scene text (the file's ``input_yaml`` attribute), for named storeys and contacts
        of files written before the connectivity was stored.
    known : (dict, dict), optional
        Storey -> upper node and contact -> (left, right) as the file stores them
        (``story_upper``, ``contact_left``, ``contact_right``); replaces ``input_yaml``.
    """
    named_stories, named_contacts = known if known is not None else _scene_elements(input_yaml)
    known = set(node_names)
    first_seen: dict[str, int] = {}
    buildings: dict[str, None] = {}
    nodes: dict[str, dict[str, str]] = {}
    for name in node_names:
        parts = _split(name)
        if parts is None:
            continue
        building, level = parts
        buildings[building] = None
        first_seen.setdefault(level, len(first_seen))
        nodes.setdefault(level, {})[building] = name

    unplaced = []
    stories: dict[str, dict[str, str]] = {}
    lines: dict[str, dict[str, list[str]]] = {}
    for name in story_names:
        upper = named_stories.get(name, name)
        parts = _split(upper) if upper in known else None
        if parts is None:
            unplaced.append(name)
            continue
        stories.setdefault(parts[1], {})[parts[0]] = name
        lines.setdefault(parts[1], {}).setdefault(parts[0], []).append(name)

    contacts: dict[str, list[str]] = {}
    for name in contact_names:
        pair = named_contacts.get(name)
        if pair is None:
            # node names may hold '-', so try every split of a default name
            splits = [(name[:i], name[i + 1:]) for i, ch in enumerate(name) if ch == "-"]
            pair = next(((a, b) for a, b in splits
                         if {a, b} <= known | {"ground"} and {a, b} != {"ground"}), None)
        # a wall ('ground' on one side) stands at its floor's level
        floors = [node for node in pair or () if node != "ground"]
        if pair is None or not floors or not all(node in known for node in floors):
            unplaced.append(name)
            continue
        for level in dict.fromkeys(_split(node)[1] for node in floors):
            contacts.setdefault(level, []).append(name)

    order = tuple(sorted(first_seen, key=lambda level: _level_key(level, first_seen)))
    return Levels(order, tuple(buildings), nodes, stories, contacts, tuple(unplaced), lines)
