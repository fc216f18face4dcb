"""``pframe compile``: compile the kernel ahead of time (installers, CI, shared machines).

pframe compiles its kernel once per installed version, the first time any scene runs; this
command does it on purpose, so that nobody's first run waits for it. It runs a two-step scene
that takes every part of the kernel into the compiled code (the kernel is the same for every
scene) and prints where the compiled kernel is cached.
"""

from __future__ import annotations

import sys
import time

#: two buildings and a contact, two steps: enough for numba to compile the whole kernel
_SCENE = """
buildings:
  - {name: A, floors: 1, mass: 1000.0, story: {material: elastic, stiffness: 1.0e6}}
  - {name: B, floors: 1, mass: 1000.0, story: {material: elastic, stiffness: 2.0e6}}
contacts: [{name: c, nodes: [A/1, B/1], gap: 0.01, law: linear, stiffness: 1.0e8}]
excitation: {kind: sine, amplitude: 1.0, frequency: 5.0}
analysis: {dt: 0.01, duration: 0.02}
recorders: [{kind: envelope, quantities: [displacement]}]
"""


def _compile(args) -> int:
    from pframe.assemble import assemble
    from pframe.kernel import FOLDER, cache, simulate
    from pframe.reader import parse_scene

    was_compiled = cache.is_compiled(FOLDER)
    start = time.perf_counter()
    simulate(assemble(parse_scene(_SCENE, source="<pframe compile>").expanded), threads=1,
             announce=lambda message: print(f"pframe: {message}", file=sys.stderr, flush=True))
    seconds = time.perf_counter() - start
    if was_compiled:
        print(f"the kernel was already compiled for this installation ({FOLDER}); "
              f"loaded in {seconds:.2f} s")
    else:
        print(f"compiled the kernel in {seconds:.1f} s; cached in {FOLDER}")
    return 0


def register(sub) -> None:
    parser = sub.add_parser("compile", help="compile the kernel now (once per installation)")
    parser.set_defaults(run=_compile)
