"""``pframe pi MODEL.yaml``: the scene's governing variables and Pi groups."""

from __future__ import annotations


def _number(value: float) -> str:
    return f"{value:.10g}"


def _in_system(variable, system) -> tuple[float, str]:
    """A governing variable's (value, units) in the scene's unit system (docs/units.md)."""
    mass, length, time = variable.dimension.exponents
    if system.si or not (mass or length):
        return variable.value, variable.units
    return variable.value / system.factor(mass, length), system.symbol(mass, length, time)


def _print(report, source: str, system) -> None:
    n, groups = len(report.variables), report.groups
    print(f"{source}: {n} governing variables, {n - len(groups)} reference dimensions, "
          f"{len(groups)} Pi groups")
    print(f"repeating variables: {', '.join(report.repeating)}")
    width = max(len(v.name) for v in report.variables)
    dims = max(len(str(v.dimension)) for v in report.variables) + 2
    print("\nvariables")
    for v in report.variables:
        value, units = _in_system(v, system)
        print(f"  {v.name:<{width}}  {_number(value):>16} {units:<8} "
              f"{'[' + str(v.dimension) + ']':<{dims}}  {v.description}")
    name_width = max((len(g.name) for g in groups), default=0)
    formula_width = max((len(g.formula()) for g in groups), default=0)
    print("\nPi groups")
    for g in groups:
        print(f"  {g.name:<{name_width}} = {g.formula():<{formula_width}}  "
              f"{_number(report.values[g.name])}")
    print("\ndiscrete parameters")
    for line in report.discrete:
        print(f"  {line}")
    numerics = report.numerics
    if "dtau" in numerics:
        print(f"\nanalysis: dtau = w_p dt = {_number(numerics['dtau'])}, "
              f"tau = w_p t_end = {_number(numerics['tau'])}")
    for note in report.notes:
        print(f"\nnote: {note}")


def _pi(args) -> int:
    import json

    from pframe.nondim import scene_pi
    from pframe.reader import load_scene

    loaded = load_scene(args.model)
    repeating = None
    if args.repeating:
        repeating = [r.strip() for r in args.repeating.split(",") if r.strip()]
    from pframe.errors import InputError

    try:
        report = scene_pi(loaded.scene, loaded.expanded, repeating)
    except InputError as exc:  # what the scene as a whole cannot give: name its file
        message = str(exc)
        raise InputError(message if message.startswith(str(loaded.source))
                         else f"{loaded.source}: {message}") from None
    if args.json:
        # the variables' values in SI, whatever the scene's units (docs/units.md)
        print(json.dumps({"source": str(loaded.source), "units_system": "N-m-kg"}
                         | report.as_dict(), indent=2))
    else:
        _print(report, str(loaded.source), loaded.system)
    return 0


def register(sub) -> None:
    pi = sub.add_parser("pi", help="print a scene's governing variables and Pi groups")
    pi.add_argument("model", help="scene file (YAML, dimensional or Pi form)")
    pi.add_argument("--repeating", metavar="A,B,C",
                    help="repeating variables (default: m_b,a_p,w_p, the paper's choice)")
    pi.add_argument("--json", action="store_true", help="print JSON for machines")
    pi.set_defaults(run=_pi)
