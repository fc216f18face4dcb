"""Reading a scene: YAML text or data to a validated, resolved scene (:class:`LoadedScene`).

The reader sits above the scene model (:mod:`pframe.model`) and the Pi-form scenes
(:mod:`pframe.nondim`): a scene written in Pi numbers is expanded here, before the model sees
it, so neither package needs the other. Below it: :mod:`pframe.yamltext` (YAML with line
numbers), :mod:`pframe.model.load` (validation with messages that name the line).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

from pframe.errors import InputError
from pframe.model.load import ModelError, check_numbers, plugin_names, read_input, validated
from pframe.yamltext import compose, where

Path_ = tuple  # a path into the YAML data: keys and list indices


@dataclass(frozen=True)
class LoadedScene:
    """A validated scene with where it came from."""

    scene: object
    text: str
    source: str
    base_dir: Path
    lines: dict = field(repr=False)
    expanded: object = field(repr=False, default=None)

    def where(self, path: Path_) -> str:
        return where(self.source, self.lines, path)

    @property
    def data(self) -> dict:
        """The scene's YAML data as its file says it (a Pi-form scene in Pi numbers)."""
        return compose(self.text, self.source)[0]

    @property
    def units(self):
        """The units its result file is written in (:func:`pframe.nondim.output.output_units`:
        SI, or the paper's dimensionless variables with their reference scales)."""
        from pframe.nondim.output import output_units

        return output_units(self.scene, self.expanded)


def scene_from_data(data: dict, lines: dict, source: str, base_dir: Path | str = ".",
                    text: str = "") -> LoadedScene:
    """Validate composed YAML data (a Pi-form scene is expanded first) and resolve it;
    ``lines`` map data paths to lines of ``source`` for the messages."""
    from pframe.model.expand import expand
    from pframe.model.scene import scene_class, scene_motions

    unit_scales = ()
    if "pi" in data:  # a scene written in Pi numbers (pframe.nondim.pi_form)
        from pframe.nondim.pi_form import expand_pi_data

        check_numbers(data, lines, source)
        unit_scales = _unit_scales(data)
        data = expand_pi_data(data, lines, source, base_dir or ".")
        # a Pi-form scene is the paper's formulation: its contacts use the published damping
        # formula of their law unless the expansion says otherwise (a note, not a warning)
        for contact in data.get("contacts") or []:
            if isinstance(contact, dict) and "restitution" in contact:
                contact.setdefault("calibration", "published")
    plugins = plugin_names(data, lines, source)
    scene = validated(scene_class(*plugins), data, lines, source)
    base_dir = Path(base_dir or ".")
    for motion in scene_motions(scene):
        if motion.kind == "record":
            # copies of the scene (model_copy) read the record from here, whatever the cwd
            motion._folder = str(base_dir.resolve())
    try:
        expanded = expand(scene, base_dir)
    except ModelError as exc:
        raise InputError(f"{where(source, lines, exc.path)}: {exc.message}") from None
    if unit_scales:
        expanded = dataclasses.replace(expanded, unit_scales=unit_scales)
    if scene.output.units == "dimensionless":  # fail now, not after the run
        from pframe.nondim.scene_variables import reference_scales

        try:
            reference_scales(scene, expanded)
        except InputError as exc:
            raise InputError(f"{where(source, lines, ('output',))}: {exc}") from None
    return LoadedScene(scene, text, source, base_dir, lines, expanded)


def _unit_scales(data: dict) -> tuple[str, ...]:
    """The reference scales a Pi-form scene leaves at 1: m_b (kg) always unless given; w_p
    (rad/s) unless given or taken from a record."""
    scales = data.get("scales") if isinstance(data.get("scales"), dict) else {}
    excitation = data.get("excitation") if isinstance(data.get("excitation"), dict) else {}
    out = [] if "m_b" in scales else ["m_b"]
    if "w_p" not in scales and excitation.get("kind") != "record":
        out.append("w_p")
    return tuple(out)


def parse_scene(text: str, source: str = "<string>", base_dir: Path | None = None) -> LoadedScene:
    """Validate a scene given as YAML text; raise :class:`InputError` naming the line."""
    data, lines = compose(text, source)
    if not isinstance(data, dict):
        raise InputError(f"{source}: a scene is a YAML mapping (keys such as buildings, "
                         "contacts, excitation, analysis); this file holds "
                         f"{'nothing' if data is None else type(data).__name__}")
    return scene_from_data(data, lines, source, base_dir, text)



def load_scene(path: str | Path) -> LoadedScene:
    """Read and validate a scene file."""
    path = Path(path)
    return parse_scene(read_input(path, "model"), str(path), path.parent)


def variant(loaded: LoadedScene, change, composed: tuple | None = None,
            text: bool = True) -> LoadedScene:
    """A variant of a loaded scene, made on its data -- the one way pframe makes variants.

    ``change(data)`` edits the scene's YAML data (a dict, as the file says it: a Pi-form
    scene stays in Pi numbers) in place; the variant is validated as a file is, its messages
    name the original file and lines, and its text (``input_yaml`` of a result) is the
    changed data. A key that ``change`` expects and does not find raises there, instead of
    leaving the scene unchanged.

    Many variants of one scene: ``composed`` is ``compose(loaded.text, loaded.source)``,
    done once (it is copied, not changed); ``text=False`` leaves the variant's text empty,
    for variants that are run and never written (it costs more than the validation)."""
    import copy

    import yaml

    data, lines = compose(loaded.text, loaded.source) if composed is None else composed
    data = copy.deepcopy(data)
    change(data)
    text = yaml.safe_dump(data, sort_keys=False, allow_unicode=True) if text else ""
    # the folder the record was read from (absolute), not base_dir again relative to a
    # current folder that may have changed since
    folder = getattr(loaded.scene.excitation, "_folder", None) or loaded.base_dir
    return scene_from_data(data, lines, loaded.source, folder, text)
