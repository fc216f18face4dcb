"""What a user iterating on a model feels: the wall time of ``pframe solve`` on edited scenes,
against the wall time of OpenSeesPy's standalone script of the paper's scene.

    python benchmarks/edit_loop.py [--repeats 5] [--edits kelvin,hht,...] [--list]
                                   [--keep-cache DIR] [--records DIR] [--steps N]

First run
    With an empty kernel cache (a new temporary ``PFRAME_CACHE_DIR``, as right after
    installing pframe): the wall time of the whole process
    ``pframe solve models/wu2021-eq14.yaml -o OUT.h5 --overwrite -q``.
Edits
    Then, with that same cache, each edited scene (models/wu2021-eq14.yaml loaded with yaml,
    one thing changed, dumped to a temporary file; checked with ``pframe validate`` first,
    untimed) is solved once by the same command: its wall time, and its CPU time (the
    RUSAGE_CHILDREN difference). Each edit is run once because a user's edit is a first run
    of that scene: whatever it has to compile is part of what the user waits for.
Reference
    The whole standalone OpenSeesPy script of the paper's scene (``pframe.peers.opensees
    .script_text`` of models/wu2021-eq14-linear.yaml, linear contacts, which stock OpenSees
    can model; it builds the model, analyses and saves four histories to .npz), run with this
    Python --repeats times, spread between the edits, after one untimed run; the median wall
    time is the reference.

The table gives each edit's pframe wall and CPU time and the ratio pframe / OpenSees (wall;
below 1 means pframe is faster), then the first-run time, the median and the worst ratio
against the goals: first run <= 30 s, median edit <= 1.0x, worst edit <= 1.5x. A failed edit
(invalid scene, or a run that stops early) is reported with its stderr and left out of the
median and the worst. Nothing is asserted; timings depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import copy
import math
import os
import shlex
import statistics
import sys
import tempfile
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import yaml
from _common import (
    KELVIN,
    LINEAR,
    Timing,
    load_average,
    median_timing,
    opensees_script,
    opensees_unavailable,
    pframe_command,
    print_header,
    ratio,
    run_timed,
    scene_copy,
    table,
)

GOAL_FIRST_RUN = 30.0  # s
GOAL_MEDIAN = 1.0  # pframe / OpenSees
GOAL_WORST = 1.5
RECORDS = Path("/work/shared/records")
#: Hertz stiffness (N/m^1.5) of the hertzdamp edits: the force of the paper's linear stiffness
#: (k = m_eff (65 w_p)^2 = 3.3e7 N/m) at its peak penetration (about 4.5 mm), k / sqrt(0.0045)
HERTZ_STIFFNESS = 5.0e8


class Skip(Exception):
    """An edit that cannot be made on this machine (its reason is printed)."""


# -- the edits: each changes the loaded YAML data of the paper's scene in place ----------------

def _set_law(contact: dict, law: str) -> None:
    """Turn one contact into ``law``, keeping its stiffness and restitution where they apply."""
    restitution = contact.get("restitution", 0.4)
    keep = {key: contact[key] for key in ("name", "nodes", "gap") if key in contact}
    stiffness = {key: contact[key] for key in ("stiffness", "frequency", "frequency_ratio")
                 if key in contact}
    contact.clear()
    contact.update(keep, law=law)
    if law == "hertzdamp":
        contact.update(stiffness=HERTZ_STIFFNESS, restitution=restitution)
    else:
        contact.update(stiffness)
        if law in ("kelvin", "improved_kelvin"):
            contact["restitution"] = restitution


def _all_laws(law: str) -> Callable[[dict, Path], None]:
    def edit(data: dict, records: Path) -> None:
        for contact in data["contacts"]:
            _set_law(contact, law)
    return edit


def _mixed_laws(data: dict, records: Path) -> None:
    for contact, law in zip(data["contacts"], ("linear", "kelvin", "hertzdamp")):
        _set_law(contact, law)


def _history(data: dict) -> dict:
    return next(r for r in data["recorders"] if r["kind"] == "history")


def _add_history(quantity: str) -> Callable[[dict, Path], None]:
    def edit(data: dict, records: Path) -> None:
        _history(data)["quantities"].append(quantity)
    return edit


def _envelope_only(data: dict, records: Path) -> None:
    data["recorders"] = [r for r in data["recorders"] if r["kind"] == "envelope"]


def _integrator(**settings) -> Callable[[dict, Path], None]:
    def edit(data: dict, records: Path) -> None:
        data["analysis"]["integrator"] = dict(settings)
    return edit


def _events(data: dict, records: Path) -> None:
    data["analysis"]["integrator"]["events"] = True


def _elastic(data: dict, records: Path) -> None:
    for building in data["buildings"]:
        building["story"] = {"material": "elastic", "stiffness": building["story"]["stiffness"]}


def _third_building(data: dict, records: Path) -> None:
    """Building C (3 storeys, between A and B in mass and stiffness) right of B, pounding B
    at every floor across the same gap with the same law."""
    data["buildings"].append({
        "name": "C", "floors": 3, "mass": 500.0,
        "story": {"material": "bilinear", "stiffness": 6.0e5, "yield_drift": 0.02,
                  "alpha": 0.1}})
    for level, contact in enumerate(list(data["contacts"]), start=1):
        twin = copy.deepcopy(contact)
        twin.update(name=f"B-C-{level}", nodes=[f"B/{level}", f"C/{level}"])
        data["contacts"].append(twin)


def _floor_mass(data: dict, node: str) -> float:
    building, floor = node.split("/")
    mass = next(b["mass"] for b in data["buildings"] if b["name"] == building)
    return float(mass[int(floor) - 1] if isinstance(mass, list) else mass)


def _record(data: dict, records: Path) -> None:
    """A recorded ground motion instead of the sine. ``frequency_ratio`` is relative to the
    sine's frequency, so each contact gets the stiffness it stood for."""
    if not records.is_dir():
        raise Skip(f"no records folder {records}")
    files = sorted(p for p in records.iterdir() if p.suffix.lower() == ".at2")
    if not files:
        raise Skip(f"no .AT2 file in {records}")
    chosen = next((p for p in files if p.name.lower() == "elcentro.at2"), files[0])
    w_p = float(data["excitation"]["frequency"])
    for contact in data["contacts"]:
        if "frequency_ratio" in contact:
            m1, m2 = (_floor_mass(data, node) for node in contact["nodes"])
            w_bar = float(contact.pop("frequency_ratio")) * w_p
            contact["stiffness"] = m1 * m2 / (m1 + m2) * w_bar ** 2
    data["excitation"] = {"kind": "record", "file": str(chosen.resolve())}


@dataclass
class Edit:
    name: str
    what: str
    apply: Callable[[dict, Path], None]


EDITS = [
    Edit("kelvin", "contact law kelvin (same stiffness and restitution)", _all_laws("kelvin")),
    Edit("linear", "contact law linear (same stiffness)", _all_laws("linear")),
    Edit("hertzdamp", f"contact law hertzdamp, k = {HERTZ_STIFFNESS:.2g} N/m^1.5, same e",
         _all_laws("hertzdamp")),
    Edit("mixed-laws", "contacts linear, kelvin, hertzdamp on floors 1, 2, 3", _mixed_laws),
    Edit("acceleration", "history recorder + acceleration", _add_history("acceleration")),
    Edit("penetration", "history recorder + contact_penetration",
         _add_history("contact_penetration")),
    Edit("envelope-only", "the envelope recorder only (no histories)", _envelope_only),
    Edit("hht", "integrator hht (alpha 0.05)", _integrator(type="hht", alpha=0.05)),
    Edit("generalized-alpha", "integrator generalized_alpha (rho_inf 0.8)",
         _integrator(type="generalized_alpha", rho_infinity=0.8)),
    Edit("events", "integrator newmark with events: true", _events),
    Edit("elastic", "elastic storeys (same initial stiffness)", _elastic),
    Edit("third-building", "building C right of B, 3 more contacts", _third_building),
    Edit("record", "excitation: PEER record (elCentro.AT2) instead of the sine", _record),
    Edit("central-difference", "integrator central_difference",
         _integrator(type="central_difference")),
]


# -- running --------------------------------------------------------------------------------

@dataclass
class Outcome:
    edit: Edit
    timing: Timing | None = None
    status: str = "ok"  # ok, skipped, invalid, exit N

    @property
    def ok(self) -> bool:
        return self.status == "ok"


def _indent(text: str) -> str:
    return "      " + text.strip().replace("\n", "\n      ")


def _cache_summary(folder: Path) -> str:
    files = [p for p in folder.rglob("*") if p.is_file()]
    size = sum(p.stat().st_size for p in files)
    return f"{len(files)} files, {size / 1e6:.1f} MB"


def main(argv: list[str] | None = None) -> int:
    names = [e.name for e in EDITS]
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=5,
                        help="timed runs of the OpenSees script, median kept (default 5)")
    parser.add_argument("--edits", default=None,
                        help="comma-separated subset of the edits (default: all; see --list)")
    parser.add_argument("--list", action="store_true", help="list the edits and exit")
    parser.add_argument("--keep-cache", type=Path, default=None, metavar="DIR",
                        help="kernel cache folder to use and keep (default: a new temporary "
                             "one, removed at the end); empty or absent for a cold first run")
    parser.add_argument("--records", type=Path, default=RECORDS,
                        help=f"folder of PEER .AT2 records for the record edit (default {RECORDS})")
    parser.add_argument("--steps", type=int, default=None,
                        help="shorten both programs' scenes to N steps (default: the models' "
                             "50,000); for quick checks only")
    args = parser.parse_args(argv)
    if args.list:
        for e in EDITS:
            print(f"{e.name:<20} {e.what}")
        return 0
    if args.repeats < 1:
        parser.error("--repeats must be at least 1")
    if args.steps is not None and args.steps < 1:
        parser.error("--steps must be at least 1")
    chosen = EDITS
    if args.edits:
        wanted = [w.strip() for w in args.edits.split(",") if w.strip()]
        unknown = [w for w in wanted if w not in names]
        if unknown:
            parser.error(f"unknown edits {', '.join(unknown)}; choose from {', '.join(names)}")
        chosen = [e for e in EDITS if e.name in wanted]

    print_header()
    cli = pframe_command()
    if cli is None:
        print("pframe CLI not available (no 'pframe solve' with --overwrite on PATH or beside "
              "this Python): nothing to measure")
        return 1
    why_not = opensees_unavailable(in_subprocess=True)

    with tempfile.TemporaryDirectory(prefix="pframe-edit-loop-") as tmp:
        folder = Path(tmp)
        cache = args.keep_cache if args.keep_cache is not None else folder / "cache"
        cold = not cache.exists() or not any(cache.iterdir())
        cache.mkdir(parents=True, exist_ok=True)
        env = {**os.environ, "PFRAME_CACHE_DIR": str(cache.resolve())}
        base_file = scene_copy(KELVIN, folder, args.steps)
        base = yaml.safe_load(base_file.read_text(encoding="utf-8"))
        steps = round(base["analysis"]["duration"] / base["analysis"]["dt"])
        print(f"kernel cache: PFRAME_CACHE_DIR={cache}"
              + ("" if cold else " (NOT empty: the first run is not a cold start)"))
        print(f"scenes: {KELVIN.name} and {len(chosen)} edits of it, {steps} steps each; "
              f"reference: the OpenSeesPy script of {LINEAR.name}")
        print()

        # -- reference: OpenSees script, runs spread between the edits ------------------------
        reference: list[Timing] = []
        opensees = None
        if why_not is not None:
            print(f"OpenSeesPy not available ({why_not}): no ratios")
        else:
            opensees = opensees_script(scene_copy(LINEAR, folder, args.steps), folder)
            _, done = run_timed(opensees, cwd=folder)  # untimed: warms the file cache
            if done.returncode != 0:
                print(f"the OpenSees script failed (exit {done.returncode}); no ratios:\n"
                      + _indent(done.stderr or done.stdout))
                opensees = None
        spread = Counter(math.floor(i * len(chosen) / args.repeats) for i in range(args.repeats))

        def reference_runs(position: int) -> None:
            for _ in range(spread.get(position, 0) if opensees else 0):
                timing, done = run_timed(opensees, cwd=folder)
                if done.returncode != 0:
                    print(f"  [OpenSees script failed (exit {done.returncode})]", flush=True)
                    continue
                reference.append(timing)
                print(f"  [OpenSees script: {timing.wall:.3f} s wall, {timing.cpu:.3f} s CPU]",
                      flush=True)

        # -- first run ------------------------------------------------------------------------
        command = [*cli, "solve", str(base_file), "-o", str(folder / "first.h5"),
                   "--overwrite", "-q"]
        print("first run: " + shlex.join(command).replace(tmp, "$TMP"), flush=True)
        first, done = run_timed(command, cwd=folder, env=env)
        print(f"  {first.wall:.2f} s wall, {first.cpu:.2f} s CPU"
              + ("" if done.returncode == 0 else f", exit {done.returncode}"), flush=True)
        if done.returncode != 0:
            print(_indent(done.stderr or done.stdout))
            return 1
        print(f"  kernel cache now: {_cache_summary(cache)}")
        print()

        # -- edits ----------------------------------------------------------------------------
        print("edits (same cache), each solved once:")
        outcomes = []
        for position, edit in enumerate(chosen):
            reference_runs(position)
            outcome = Outcome(edit)
            outcomes.append(outcome)
            data = copy.deepcopy(base)
            try:
                edit.apply(data, args.records)
            except Skip as reason:
                outcome.status = "skipped"
                print(f"  {edit.name}: skipped: {reason}", flush=True)
                continue
            path = folder / f"edit-{edit.name}.yaml"
            path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
            _, checked = run_timed([*cli, "validate", str(path)], cwd=folder, env=env)
            if checked.returncode != 0:
                outcome.status = "invalid"
                print(f"  {edit.name}: pframe validate exited with {checked.returncode}:\n"
                      + _indent(checked.stderr or checked.stdout), flush=True)
                continue
            outcome.timing, done = run_timed(
                [*cli, "solve", str(path), "-o", str(folder / f"edit-{edit.name}.h5"),
                 "--overwrite", "-q"], cwd=folder, env=env)
            if done.returncode != 0:
                outcome.status = f"exit {done.returncode}"
            print(f"  {edit.name}: {outcome.timing.wall:.2f} s wall, {outcome.timing.cpu:.2f} s "
                  f"CPU ({edit.what})" + ("" if outcome.ok else f": {outcome.status}"), flush=True)
            if not outcome.ok:
                print(_indent(done.stderr or done.stdout), flush=True)
        if not chosen:
            reference_runs(0)
        print(f"  kernel cache now: {_cache_summary(cache)}"
              + (f", kept in {cache}" if args.keep_cache is not None else ""))
    print()

    ref = median_timing(reference) if reference else None
    if ref is not None:
        walls = ", ".join(f"{t.wall:.3f}" for t in reference)
        print(f"reference: OpenSeesPy script of {LINEAR.name}, median of {len(reference)}: "
              f"{ref.wall:.3f} s wall, {ref.cpu:.3f} s CPU (wall: {walls} s)")
    header = ("edit", "pframe wall s", "pframe CPU s", "pframe / OpenSees", "status")
    rows = [(f"(first run, {'cold' if cold else 'NOT empty'} cache)", f"{first.wall:.2f}",
             f"{first.cpu:.2f}", ratio(first.wall, ref and ref.wall), "ok")]
    for o in outcomes:
        t = o.timing
        rows.append((o.edit.name, "-" if t is None else f"{t.wall:.2f}",
                     "-" if t is None else f"{t.cpu:.2f}",
                     ratio(t.wall, ref and ref.wall) if o.ok else "-", o.status))
    print()
    for line in table(header, rows, left=1):
        print(line)
    print()

    ok = [o for o in outcomes if o.ok]
    verdict = {True: "met", False: "NOT met"}
    print(("first run after install (empty kernel cache)" if cold else
           "first run (kernel cache NOT empty: not what a new install sees)")
          + f": {first.wall:.2f} s wall (goal <= {GOAL_FIRST_RUN:.0f} s: "
          f"{verdict[first.wall <= GOAL_FIRST_RUN]})")
    if ref is not None and ok:
        ratios = {o.edit.name: o.timing.wall / ref.wall for o in ok}
        median = statistics.median(ratios.values())
        worst = max(ratios, key=ratios.get)
        print(f"median edit: {median:.2f}x OpenSees over {len(ok)} edits (goal <= "
              f"{GOAL_MEDIAN:.1f}x: {verdict[median <= GOAL_MEDIAN]})")
        print(f"worst edit: {ratios[worst]:.2f}x OpenSees, {worst} (goal <= {GOAL_WORST:.1f}x: "
              f"{verdict[ratios[worst] <= GOAL_WORST]})")
    else:
        print("median and worst edit: no ratio (no OpenSees reference or no successful edit)")
    failed = [o.edit.name for o in outcomes if o.status not in ("ok", "skipped")]
    if failed:
        print(f"failed edits (left out above): {', '.join(failed)}")
    print(f"load average (1, 5, 15 min) at the end: {load_average()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
