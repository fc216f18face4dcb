"""Reading a scene: YAML text or data to a validated, resolved scene (:class:`LoadedScene`).

The reader sits above the scene model (:mod:`pframe.model`) and the Pi-form scenes
(:mod:`pframe.nondim`): a scene written in Pi numbers is expanded here, before the model sees
it, so neither package needs the other. Below it: :mod:`pframe.yamltext` (YAML with line
numbers), :mod:`pframe.model.load` (validation with messages that name the line).
"""

from __future__ import annotations

import copy
import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

from pframe.errors import InputError
from pframe.model.load import ModelError, check_numbers, plugin_names, read_input, validated
from pframe.units import SI
from pframe.yamltext import compose, dump, where

Path_ = tuple  # a path into the YAML data: keys and list indices


# eq=False: nothing compares two loaded scenes (their dicts would not hash); each generated
# function is compiled at every start
@dataclass(frozen=True, eq=False)
class LoadedScene:
    """A validated scene with where it came from.

    ``given`` is the scene's data as it was given (a file's composed YAML, a dict, a scene
    object's fields; a Pi-form scene in Pi numbers), ``lines`` the line of each of its values
    in ``source`` (none for data and objects: their messages name the keys), ``given_text``
    a file's own text. A scene given as data or objects has no text until one is asked for
    (:attr:`text`)."""

    scene: object
    source: str
    base_dir: Path
    lines: dict = field(repr=False)
    expanded: object = field(repr=False, default=None)
    given: dict | None = field(repr=False, default=None)
    given_text: str | None = field(repr=False, default=None)
    #: the reference scales m_b, a_p, w_p of the paper's dimensionless variables, or None for
    #: a scene without them (:func:`pframe.nondim.reference.reference_scales`)
    reference: dict | None = field(repr=False, default=None)
    #: the units its result file is written in (:class:`pframe.nondim.output.OutputUnits`:
    #: SI, or the paper's dimensionless variables with the reference scales)
    units: object = field(repr=False, default=None)
    #: the unit system the scene is written in (:class:`pframe.units.UnitSystem`; its
    #: ``scene`` and ``expanded`` are in SI whatever it is: docs/units.md)
    system: object = field(repr=False, default=None)

    def where(self, path: Path_) -> str:
        return where(self.source, self.lines, path)

    @property
    def text(self) -> str:
        """The scene's YAML (a result file's ``input_yaml``): a file's own text, comments
        included; for data and objects, their data written once, when first asked for."""
        if self.given_text is None:
            text = "" if self.given is None else dump(self.given)
            object.__setattr__(self, "given_text", text)  # a cache of what given says
        return self.given_text

    @property
    def data(self) -> dict:
        """The scene's YAML data as given (a Pi-form scene in Pi numbers): a copy, the
        caller's to change."""
        return copy.deepcopy(self.given)


def scene_from_data(data: dict, lines: dict, source: str, base_dir: Path | str = ".",
                    text: str | None = None) -> LoadedScene:
    """Validate scene data (composed YAML, or plain Python data; a Pi-form scene is expanded
    first) and resolve it: the one validation and the one expansion of every scene read.
    ``lines`` map data paths to lines of ``source`` for the messages (empty: messages name
    the keys); ``text`` is the file's text, if the data came from one. ``data`` becomes the
    scene's :attr:`LoadedScene.given`: the caller does not change it afterwards."""
    given = data
    from pframe.model.expand import expand
    from pframe.model.scene import scene_class, scene_motions
    from pframe.nondim.output import OutputUnits

    unit_scales = ()
    system = unit_system(data, lines, source)
    if "pi" in data and not system.si:
        raise InputError(f"{where(source, lines, ('units',))}: a Pi-form scene is written in "
                         "Pi numbers and SI scales; units applies to a dimensional scene (write "
                         "the scene out with pframe expand, or leave units out)")
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
    if system.si:
        scene = validated(scene_class(*plugins), data, lines, source)
    else:
        scene = _validated_in_si(data, system, scene_class(*plugins), lines, source)
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
    reference = _reference(scene, expanded, source, lines)
    given_output = given.get("output") if isinstance(given.get("output"), dict) else {}
    output = SI if "units" in given_output else system  # output.units: SI asks for SI
    units = OutputUnits(reference if scene.output.units == "dimensionless" else None, output)
    return LoadedScene(scene, source, base_dir, lines, expanded, given, text, reference, units,
                       system)


def require_si(loaded: LoadedScene, what: str) -> None:
    """Refuse a scene written in another unit system where ``what`` (a command, a study)
    reads or writes SI only: its numbers would be taken for SI, or its results labelled in
    units the scene does not use.

    Raises
    ------
    InputError
        Naming the file, the line of ``units``, the system, and how to get the SI scene.
    """
    system = getattr(loaded, "system", None)
    if system is None or system.si:
        return
    raise InputError(f"{loaded.where(('units',))}: {what} reads and writes SI units only (N, "
                     f"m, kg, s), and this scene is written in {system.name}; pframe expand "
                     f"{loaded.source} -o SCENE.yaml writes it in SI (docs/units.md)")


def unit_system(data: dict, lines: dict, source: str):
    """The :class:`pframe.units.UnitSystem` a scene's data names (``units``; default SI).

    Raises
    ------
    InputError
        Naming the file, the line and ``units``, with the names accepted.
    """
    from pframe.units import SYSTEMS

    name = data.get("units", SI.name)
    if isinstance(name, str) and name in SYSTEMS:
        return SYSTEMS[name]
    raise InputError(f"{where(source, lines, ('units',))}: unknown unit system {name!r}; "
                     f"accepted: {', '.join(SYSTEMS)} (force-length-mass, or force-length-time "
                     "where the mass unit is force s^2 / length; docs/units.md)")


def _validated_in_si(data: dict, system, model, lines: dict, source: str):
    """The scene of data written in ``system``, validated in SI, its ``units`` SI (the
    validated scene is in SI and says so). A number of unknown dimension is an InputError
    naming it; invalid data gets the validation's message of the numbers as written (a mass
    of -0.25 t, not of -250 kg)."""
    from pframe.nondim.scene_units import to_si
    from pframe.nondim.similitude import SimilitudeError

    try:
        converted = {**to_si(data, system), "units": SI.name}
    except SimilitudeError as exc:
        validated(model, data, lines, source)
        reason = exc.reason.removeprefix("cannot scale this value: ")
        raise InputError(f"{where(source, lines, exc.path)}: cannot convert this value from "
                         f"{system.name} to SI: {reason}") from None
    try:
        return validated(model, converted, lines, source)
    except InputError as exc:
        validated(model, data, lines, source)  # the same problem, in the scene's numbers
        raise InputError(f"{exc} (the numbers quoted are the scene's in SI: N, m, kg)") \
            from None


def _reference(scene, expanded, source: str, lines: dict) -> dict | None:
    """The scene's reference scales (m_b, a_p, w_p), found once: the result file's
    ``reference_*`` attributes, and its units when ``output.units`` is dimensionless, where
    a scene without them is refused now, naming ``output``, not after the run."""
    from pframe.nondim.reference import reference_scales

    try:
        return reference_scales(scene, expanded)
    except (InputError, ValueError, TypeError, AttributeError) as exc:
        if scene.output.units == "dimensionless":
            raise InputError(f"{where(source, lines, ('output',))}: {exc}") from None
        return None


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


def variant(loaded: LoadedScene, change) -> LoadedScene:
    """A variant of a loaded scene, made on its data -- the one way pframe makes variants.

    ``change(data)`` edits a copy of the scene's data as given (a dict, as the file says it:
    a Pi-form scene stays in Pi numbers) in place; the variant is validated as a file is, its
    messages name the original file and lines, and its text (``input_yaml`` of a result), if
    asked for, is the changed data. A key that ``change`` expects and does not find raises
    there, instead of leaving the scene unchanged."""
    data = loaded.data
    change(data)
    # the folder the record was read from (absolute), not base_dir again relative to a
    # current folder that may have changed since
    folder = getattr(loaded.scene.excitation, "_folder", None) or loaded.base_dir
    return scene_from_data(data, loaded.lines, loaded.source, folder)
