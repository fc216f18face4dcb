"""``pframe opensees MODEL.yaml``: the standalone OpenSeesPy script of a scene."""

from __future__ import annotations


def _opensees(args) -> int:
    from pframe import outputs
    from pframe.api import loaded_scene, run_inputs, to_opensees
    from pframe.commands import write_text_output

    loaded = loaded_scene(args.model)
    if args.output is not None:  # before the script is made: the scene and record stay
        outputs.check_output(args.output, inputs=[args.model, *run_inputs(loaded)],
                             overwrite=args.overwrite, what="script")
    write_text_output(to_opensees(loaded), args.output, args.overwrite,
                      inputs=[args.model, *run_inputs(loaded)])
    return 0


def register(sub) -> None:
    opensees = sub.add_parser(
        "opensees", help="write the standalone OpenSeesPy script of a scene",
        description="Write a Python script that builds and runs the scene with stock OpenSees "
                    "components (zeroLength elements, Elastic/Steel01 storeys, ElasticPPGap "
                    "contacts, Rayleigh damping, Newmark with Newton), without pframe: to "
                    "cross-check pframe with the program you know. A scene in plan: a node "
                    "per floor at its centre of mass, each line of resistance and contact "
                    "point tied to it by rigidLink beam. Linear contacts, elastic or bilinear "
                    "storeys, starting at rest. See docs/python.md.")
    opensees.add_argument("model", help="scene file (YAML)")
    opensees.add_argument("-o", "--output", help="script file (default: standard output)")
    opensees.add_argument("--overwrite", action="store_true", help="replace an existing output")
    opensees.set_defaults(run=_opensees)
