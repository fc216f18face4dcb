"""``pframe validate FILE.yaml``: check a scene, a Pi-form scene or a sweep file without running
it, and show how its inputs were read (record files, restitution, warnings)."""

from __future__ import annotations

import sys
from pathlib import Path

#: keys only a sweep file has (docs/sweeps.md); a scene has none of them
SWEEP_KEYS = frozenset({"base", "scene", "axes", "combine", "keep", "chunk"})


def input_kind(data) -> str:
    """``risk``, ``sweep``, ``suite``, ``pi-scene`` or ``scene``: what kind of input file composed YAML
    data is."""
    if isinstance(data, dict):
        if "design" in data and "scene" in data:
            return "risk"
        if SWEEP_KEYS & set(data):
            return "sweep"
        if "records" in data or ("folder" in data and "buildings" not in data):
            return "suite"
        if "pi" in data:
            return "pi-scene"
    return "scene"


def _warn(source: str, warnings) -> None:
    sys.stdout.flush()
    for warning in warnings:
        print(f"pframe: warning: {source}: {warning}", file=sys.stderr)


def record_lines(loaded) -> list[str]:
    """The facts of the records a loaded scene reads, as lines (none for a scene whose one
    motion is a sine or a pulse): how each file was read, its units and where they were read,
    the PGA after every scaling and when it occurs, what part the analysis covers; a motion in
    two components and the motions of the supports, each described. ``pframe solve`` prints
    them too."""
    from pframe.model.support_motion import displacement_lines

    excitation = loaded.scene.excitation
    ex = loaded.expanded
    if loaded.scene.supports:
        return support_lines(loaded) + displacement_lines(ex)
    if excitation is None or excitation.kind not in ("record", "components"):
        return displacement_lines(ex)
    from pframe.model.motion import GroundMotion

    ground = GroundMotion({}, ex.record, tuple(ex.component_records))
    return motion_lines(excitation, ground, loaded) + displacement_lines(ex)


def motion_lines(excitation, ground, loaded) -> list[str]:
    """Lines of one excitation as applied (``ground`` its
    :class:`pframe.model.motion.GroundMotion`: the records read): a record's facts, a sine's,
    pulse's or stochastic motion's, or two components each so after how they are turned."""
    from pframe.excitation.describe import (
        applied_motion,
        describe_line,
        describe_scene_record,
        motion_line,
    )
    from pframe.model.motion import turn

    duration = loaded.expanded.dt * loaded.expanded.steps
    if excitation is None:
        return ["excitation: none (the ground stands still)"]
    if excitation.kind == "record":
        return [describe_line(describe_scene_record(excitation, loaded.base_dir),
                              duration=duration)]
    if excitation.kind != "components":
        return [motion_line(applied_motion(excitation, ground.record, duration))]
    records = dict(ground.records)
    cos, sin = turn(excitation.angle)
    out = [f"excitation: two components turned {excitation.angle:g} degrees: x along "
           f"({cos:.4g}, {sin:.4g}) of the site's axes, y along ({-sin:.4g}, {cos:.4g})"]
    for axis, motion in excitation.motions():
        if motion.kind == "record":
            line = describe_line(describe_scene_record(motion, loaded.base_dir),
                                 duration=duration)
        else:
            line = motion_line(applied_motion(motion, records.get(axis), duration))
        out.append(f"component {axis}: {line.removeprefix('excitation: ')}")
    return out


def _coherent_words(excitation) -> str:
    """A coherent simulation in words: its motion's model, coherency, waves, conditioning."""
    motion = excitation.motion
    parts = [f"the {motion.model} spectrum and modulating function"]
    c = excitation.coherency
    parts.append("fully coherent" if c is None else
                 f"Luco-Wong coherency (alpha {c.incoherence:g}, v_s {c.shear_velocity:g} m/s)"
                 if c.model == "luco_wong" else
                 f"Harichandran-Vanmarcke coherency (A {c.amplitude:g}, alpha {c.alpha:g}, "
                 f"k {c.k:g} m, f0 {c.f0:g} Hz, b {c.b:g})")
    if excitation.velocity is not None:
        parts.append(f"waves at {excitation.velocity:g} m/s towards "
                     f"{excitation.direction:g} degrees")
    if excitation.record is not None:
        parts.append(f"conditioned on the record {excitation.record.file} at support "
                     f"{excitation.at}")
    return "; ".join(parts)


def support_lines(loaded) -> list[str]:
    """The supports of a loaded scene (docs/supports.md): where each stands, the scene's
    motion (the same under every support without its own, or a wave passage with each
    support's delay), and each support's own motion."""
    scene, ex = loaded.scene, loaded.expanded
    out = ["supports: " + ", ".join(f"{s.name} at [{s.position[0]:g}, {s.position[1]:g}] m"
                                    for s in scene.supports)]
    excitation = scene.excitation
    own = [s.excitation is not None for s in scene.supports]
    shared = next((m for m, mine in zip(ex.support_motions, own) if not mine), None)
    if excitation is not None and excitation.kind == "coherent":
        import numpy as np

        out.append("excitation: motions simulated at the supports (coherent, seed "
                   f"{excitation.seed}): " + _coherent_words(excitation))
        for name, tau, row in zip(ex.supports, ex.support_delays, ex.support_samples):
            peak = float(np.max(np.abs(row)))
            at = float(np.argmax(np.abs(row)) * ex.dt)
            out.append(f"  support {name}: delay {tau:.4g} s; PGA {peak:.4g} m/s^2 "
                       f"({peak / 9.80665:.4g} g) at t = {at:.4g} s")
    elif excitation is not None and excitation.kind == "wave_passage":
        delays = ", ".join(f"{name} {tau:.4g} s" for name, tau in
                           zip(ex.supports, ex.support_delays))
        out.append(f"excitation: a wave passage at {excitation.velocity:g} m/s towards "
                   f"{excitation.direction:g} degrees: each support's motion delayed by "
                   f"{delays}; the motion:")
        out += ["  " + line for line in motion_lines(excitation.motion, shared, loaded)]
    elif not all(own):
        without = [s.name for s, mine in zip(scene.supports, own) if not mine]
        out += [f"{line} (under {', '.join(without)})"
                for line in motion_lines(excitation, shared, loaded)]
    for support, motion in zip(scene.supports, ex.support_motions):
        if support.excitation is not None:
            out += [f"support {support.name}: {line.removeprefix('excitation: ')}"
                    for line in motion_lines(support.excitation, motion, loaded)]
    return out


def excitation_lines(loaded) -> list[str]:
    """The motion a loaded scene applies, as lines: :func:`record_lines` for a record, the
    amplitude, period, peak and end of a sine or pulse; none without excitation."""
    from pframe.excitation.describe import applied_motion, motion_line

    excitation = loaded.scene.excitation
    if loaded.scene.supports or excitation is None or excitation.kind in ("record",
                                                                          "components"):
        return record_lines(loaded)
    duration = loaded.expanded.dt * loaded.expanded.steps
    return [motion_line(applied_motion(excitation, loaded.expanded.record, duration))]


def _scene(path: Path, kind: str, text: str, data, lines) -> int:
    from pframe import resources
    from pframe.assemble import assemble, modes
    from pframe.reader import parse_scene, scene_from_data

    # the file as _validate read and composed it: YAML is read once (its parsing is most of
    # the time validate takes)
    loaded = (scene_from_data(data, lines, str(path), path.parent, text)
              if isinstance(data, dict) else parse_scene(text, str(path), path.parent))
    ex = loaded.expanded
    # announced before anything large is built: the time and file a run would take
    _warn(loaded.source, resources.check(resources.of_expanded(ex, streaming=True),
                                         loaded.source))
    plan = assemble(ex)
    what = "a scene in Pi numbers: " if kind == "pi-scene" else ""
    print(f"{loaded.source}: valid; {what}{len(ex.node_names)} nodes in {len(ex.buildings)} "
          f"buildings, {len(ex.stories)} storeys, {len(ex.contacts)} contacts, {ex.steps} steps "
          f"of dt = {ex.dt:g} s")
    notes = [f"note: {n}" for n in plan.notes + ex.notes]
    if not loaded.system.si:  # docs/units.md
        from pframe.units import describe

        print(f"  units: {loaded.system.name} ({describe(loaded.system)}): the scene is read "
              "in them and its results are written in them; the lines below name their own "
              "units")
    for line in (modes.period_lines(ex) + [f"damping of {t.removeprefix('building ')}"
                                           for t in plan.damping_text]
                 + excitation_lines(loaded) + notes):
        print(f"  {line}")
    _warn(loaded.source, plan.warnings)
    return 0


def _sweep(path: Path) -> int:
    from pframe.excitation.describe import describe_line, describe_scene_record
    from pframe.sweep import load_sweep, parse

    definition = load_sweep(path)
    spec = parse(definition)
    axes = ", ".join(f"{a.name}: {len(a.values)}" for a in spec.axes)
    base = definition.base_source or "inline"
    print(f"{definition.source}: valid; a sweep of {spec.count} variants ({spec.model.combine} of "
          f"{axes}) of the base scene {base}")
    excitation = spec.base_data.get("excitation") or {}
    seen = set()
    for _, _, key, file in definition.records:
        if key in seen:
            continue
        seen.add(key)
        facts = describe_scene_record(excitation, file=file)
        print(f"  {describe_line(facts)}")
    # what a run would warn of, for the first and the last variant (every axis at its first
    # and at its last value): the others differ in numbers only
    from pframe.assemble import assemble
    from pframe.sweep.variants import load_fitted, materialise

    said = set()
    for index in dict.fromkeys((0, spec.count - 1)):
        variant = load_fitted(spec, index, materialise(definition))
        for note in variant.expanded.notes:
            if note not in said:
                print(f"  note: {note} (variant {index}: {spec.describe(index)})")
                said.add(note)
        _warn(definition.source, [f"variant {index} ({spec.describe(index)}): {w}"
                                  for w in assemble(variant.expanded).warnings])
    return 0


def _suite(path: Path) -> int:
    """A ground-motion suite of ``pframe gap``: its structure, and each record it names read
    as the audit would read it (records not beside the suite are named, not refused: the
    audit takes their folder with --records-folder)."""
    from pframe.excitation.suite import RecordEntry, SuiteFile
    from pframe.model.load import read_input, validated
    from pframe.yamltext import compose as _compose

    data, lines = _compose(read_input(path, "suite"), str(path))
    model = validated(SuiteFile, data, lines, str(path))
    entries = [RecordEntry(file=r) if isinstance(r, str) else r for r in model.records]
    print(f"{path}: valid; a ground-motion suite of {len(entries)} record"
          f"{'' if len(entries) == 1 else 's'}" + (f" and the folder {model.folder}"
                                                    if model.folder else "")
          + f", levels in {model.measure.kind}")
    for entry in entries:
        for name in entry.files:
            _suite_record(path, entry, name)
    return 0


def _suite_record(path: Path, entry, name: str) -> None:
    """One record file of a suite's entry: how it reads, or that it is not beside the suite."""
    from pframe.excitation.describe import describe_line, describe_record

    file = path.parent / name
    try:
        present = file.is_file()
    except OSError as exc:  # a name no file system takes (too long, NUL bytes)
        from pframe.errors import InputError
        from pframe.outputs import cause

        raise InputError(f"{path}: the record name {name[:60]!r}"
                         f"{'...' if len(name) > 60 else ''} is not a file name: "
                         f"{cause(exc)}") from None
    if present:
        facts = describe_record(file, entry.format, entry.units, entry.scale)
        print(f"  {describe_line(facts)}")
    else:
        print(f"  {name}: not beside the suite (pframe gap --records-folder DIR finds it)")


def _risk(path: Path, records_folder) -> int:
    """A risk study checked as ``pframe risk`` checks it before running: the study file, its
    hazard table, scene, suite and records, the measure, the limits against the scene."""
    from pframe.risk.study import open_study

    opened = open_study(path, records_folder)
    spec, inputs = opened.spec, opened.inputs
    R, L = inputs.factors.shape
    design = spec.design
    runs = (f"{R} motions x {L} levels" if design.kind in ("msa", "ida") and design.hunt is None
            else f"{R} motions")
    print(f"{path}: valid; a risk study ({design.kind}) of {inputs.loaded.source}: {runs}"
          + (f", hazard {opened.hazard.source or 'table'} ({opened.hazard.im.size} points, "
             f"{opened.hazard.im[0]:.3g}-{opened.hazard.im[-1]:.3g} g)"
             if opened.hazard is not None else ""))
    _warn(str(path), inputs.warnings)
    return 0


def _validate(args) -> int:
    from pframe.model.load import read_input
    from pframe.yamltext import compose as _compose

    path = Path(args.model)
    text = read_input(path, "input")
    data, lines = _compose(text, str(path))
    kind = input_kind(data)
    if kind == "suite":
        return _suite(path)
    if kind == "risk":
        return _risk(path, getattr(args, "records_folder", None))
    return _sweep(path) if kind == "sweep" else _scene(path, kind, text, data, lines)


def register(sub) -> None:
    validate = sub.add_parser(
        "validate", help="check a scene, Pi-form scene or sweep file without running it",
        description="Check a scene file, a scene in Pi numbers or a sweep file (recognised by "
                    "its keys) without running it; print how each record file was read and "
                    "the warnings a run would give.")
    validate.add_argument("model", help="scene, Pi-form scene, sweep, suite or risk study "
                          "file (YAML)")
    validate.add_argument("--records-folder", metavar="DIR",
                          help="a risk study: where its suite's records are (as pframe risk "
                               "--records-folder; default: the study's records_folder)")
    validate.set_defaults(run=_validate)
