"""``pframe opensees MODEL.yaml``: the standalone OpenSeesPy script of a scene."""

from __future__ import annotations


def _opensees(args) -> int:
    import sys

    from pframe import outputs
    from pframe.api import loaded_scene, opensees_script, run_inputs
    from pframe.commands import write_text_output

    loaded = loaded_scene(args.model)
    if args.output is not None:  # before the script is made: the scene and record stay
        outputs.check_output(args.output, inputs=[args.model, *run_inputs(loaded)],
                             overwrite=args.overwrite, what="script")
    text, differences = opensees_script(loaded)
    for difference in differences:
        print(f"pframe: warning: {loaded.source}: the OpenSees script's model is not "
              f"pframe's: {difference}", file=sys.stderr)
    write_text_output(text, args.output, args.overwrite,
                      inputs=[args.model, *run_inputs(loaded)])
    return 0


def register(sub) -> None:
    opensees = sub.add_parser(
        "opensees", help="write the standalone OpenSeesPy script of a scene",
        description="Write a Python script that builds and runs the scene with stock OpenSees "
                    "components (zeroLength elements, each law as its OpenSees twin: Steel01, "
                    "BoucWen, ModIMKPeakOriented, BWBN, Viscous, ElasticPPGap, Hertzdamp, "
                    "JankowskiImpact; Rayleigh or modal damping, P-delta, soil, the scene's "
                    "integrator), without pframe: to cross-check pframe with the program you "
                    "know. A scene in plan: a node per floor at its centre of mass, each line "
                    "of resistance and contact point tied to it by rigidLink beam. A scene "
                    "on several supports: total coordinates, each support's motion imposed "
                    "on its ground by a MultipleSupport pattern. Where the "
                    "script's model is not pframe's it says so (a warning here, and in the "
                    "script); a scene it cannot model is refused with every reason. See "
                    "docs/python.md#a-scene-for-opensees.")
    opensees.add_argument("model", help="scene file (YAML)")
    opensees.add_argument("-o", "--output", help="script file (default: standard output)")
    opensees.add_argument("--overwrite", action="store_true", help="replace an existing output")
    opensees.set_defaults(run=_opensees)
