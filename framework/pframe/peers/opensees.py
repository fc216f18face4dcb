"""OpenSeesPy peer: the same scene built from stock OpenSees components.

The peer serves two purposes: an independent check of pframe's kernel and a speed benchmark.
:func:`script_text` writes a self-contained OpenSeesPy script (it never imports pframe), so
the model can be rerun, inspected or timed without pframe installed; :func:`run` executes that
same text in this process and returns its histories.

A planar scene (one DOF per floor) is a 1-D model: node ``i + 1`` is DOF ``i``, with one
fixed ground node. A planar scene with buildings on soil is a 2-D model in the vertical plane
(``-ndm 2 -ndf 3``): each foundation's node sways and rocks (its mass m_f and I_f) on
``zeroLength`` springs to the ground (along x and about z), each floor of its building turns
with it (``equalDOF`` of the rotation, which has no mass) and each of its storeys is a
vertical ``twoNodeLink`` of the storey's height, whose shear deformation is
u_upper - u_lower - h theta (docs/soil.md; the floors are drawn downwards, so that the link's
local y runs along +x and theta is pframe's sign). A scene in plan is a 2-D model
(``-ndm 2 -ndf 3``): node ``f + 1`` is floor ``f`` at its centre of mass with its mass
(m, m, J), and each element end is a node at its point on the element's line of action, tied
to its floor by ``rigidLink beam``, with the element a ``zeroLength`` oriented (``-orient``)
along the element's direction. In 2-D that constraint is exactly pframe's small-rotation map
of a rigid diaphragm, u_P = (u_x - theta (P_y - c_y), u_y + theta (P_x - c_x)), a constant
matrix that the ``Transformation`` handler eliminates exactly; ``rigidDiaphragm`` is the same
map but needs a 3-D model (``-ndm 3 -ndf 6``, the out-of-plane DOFs all fixed) for nothing
more. An end's point is where the element's line of action passes nearest its floor's centre
of mass: a force along n has the same moment about the centre from any point of its line, so
it is the model pframe runs whatever point the scene named on that line. The components the
scene does not move are fixed. The models have:

* storeys (lines of resistance) and links: ``zeroLength`` with each law's twin
  (:mod:`pframe.peers.twins`: ``Elastic``, ``Steel01``, ``BoucWen``, ``ModIMKPeakOriented``,
  ``BWBN``, ``Viscous``, ``Parallel`` ones) from the lower to the upper node, so the element
  deformation is the drift; P-delta (P / h) a ``zeroLength`` of ``Elastic(-P / h)`` beside
  its storey, without Rayleigh damping (pframe damps the material's stiffness only) and added
  after the modes of modal damping are taken (pframe fits them without it);
* contacts: ``zeroLength`` from the left to the right node with the law's twin
  (``ElasticPPGap``, ``Hertzdamp``, ``JankowskiImpact``) and its gap negative; its
  deformation ``u_right - u_left`` falls below ``-gap`` exactly when ``u_left - u_right - gap
  > 0``, and the (negative) material stress is minus the compression force;
* Rayleigh damping: ``alpha_m`` on the building's nodes (in plan their rotational inertia
  too, as pframe; not a foundation's), ``beta_k`` on the initial, current or committed
  stiffness of its storeys that take the stiffness term (``betaKinit``, ``betaK``,
  ``betaKcomm``; ``-doRayleigh``; not its isolators); contacts and links are undamped; or
  modal damping: ``eigen`` of every mode with ``-fullGenLapack`` on the storeys' initial
  stiffness (before the contacts exist), then ``modalDamping`` with the ratio of each mode;
* ground motion: a ``Path`` series driving a ``UniformExcitation`` per site axis it loads
  (load ``-m a_g`` in relative coordinates; in plan along x, y or both), its sample times
  accumulated as OpenSees accumulates time, so that step ``n`` sees ``a_g[n]`` exactly;
  Newton iterations with a ``NormDispIncr`` test, one ``analyze(steps, dt)`` call and
  binary recorders;
* a scene on several supports (docs/supports.md) in total coordinates instead: a ground node
  per support (in plan, per ground end), each support's motion imposed on them by a
  ``MultipleSupport`` pattern, a ``groundMotion`` per support and axis of three ``Path``
  series, pframe's displacement, velocity and acceleration (the trapezoid rule twice from
  rest: OpenSees then imposes pframe's displacement sample for sample, where its own
  integration of ``-accel`` runs at 0.01 s whatever the record's step), ``imposedMotion``
  on the ground nodes (``Transformation`` constraints); each element's ground end on its
  support's node (:mod:`pframe.peers.supports`); the mass-proportional damping, which pframe
  applies to the motion relative to the supports, a ``Viscous`` dashpot (alpha = 1) of
  ``a0 m`` from each DOF to its support's ground instead of the Rayleigh mass term, which
  acts on total velocities; the histories' displacements and velocities made relative to
  each DOF's support, the totals kept (``total_displacement``, ``total_velocity``). Under
  Newmark's average acceleration the two formulations are one model (the supports' motion
  keeps its relations); under another integrator they part by O(dt^2), which the export
  names;
* the integrator: ``Newmark``, ``HHT`` (OpenSees' alpha is 1 - pframe's),
  ``HHTGeneralized`` for generalised-alpha (alpha_I = 1 - alpha_m, alpha_F = 1 - alpha_f,
  Chung & Hulbert's method operation for operation), ``WilsonTheta``, ``TRBDF2`` (Bathe's
  method with gamma = 1/2: OpenSees takes its trapezoidal and backward sub-steps as alternate
  analysis steps of dt / 2, so the script analyses twice the steps at half the step, with the
  ground motion sampled between pframe's samples as pframe interpolates it, linearly, and
  records every second step) or ``NewmarkExplicit`` (gamma = 1/2, a ``Linear`` algorithm) for
  central difference, with its sub-steps.
  Not OpenSees' ``GeneralizedAlpha``: it sets the nodes' accelerations to a(n+1) in its
  Newton update (``GeneralizedAlpha::update``) where its tangent and the method have
  a(n+1-alpha_m); a linear oscillator (w dt = 5, rho_inf = 0.6) grows in amplitude under it,
  where the method's amplification matrix and pframe decay.

Where the script's model is not pframe's, :class:`PeerScene`'s ``differences`` say so, and
the script writes them in its docstring and prints them when run: a twin's own conditions
(:mod:`pframe.peers.twins`), event location (``events: true``: OpenSees steps over contact
events), central difference where forces depend on velocity, and Wilson-theta, which in
OpenSees reads the ground motion at t + theta dt from the record (between the next two
samples) where the method, as pframe has it, extrapolates the step's own samples linearly
(Wilson, Farhoomand & Bathe 1973): the two agree to round-off under a ground motion linear in
time, and differ by O(dt^2) under others. The script also says where a contact pulled (a
Hertzdamp in rebound), from which step on its model left pframe's.

Known difference from pframe, far below any tolerance: ``Steel01`` ignores a trial strain
within ``DBL_EPSILON`` (2.2e-16, here metres of drift) of its committed strain and keeps the
committed force, so a storey whose drift changes by less than that in a step lags by up to
``k * 2.2e-16`` N (visible only in the first steps from rest, as ~1e-12 relative).
"""

from __future__ import annotations

import base64
import os
import pprint
import tempfile
import textwrap

import numpy as np

from pframe.peers import opensees_script
from pframe.peers.scene import PeerScene
from pframe.peers.supports import AXIS_DOF

_IMPORT_HINT = (
    'OpenSeesPy is not importable: install the peers extra (pip install "pframe[peers]") '
    "and the system BLAS/LAPACK (apt-get install libblas3 liblapack3)"
)
_WIDTH = 100  # line length of the generated script


def opensees_integrator(integrator: tuple) -> tuple:
    """OpenSees' ``integrator`` arguments for a :class:`PeerScene` integrator."""
    kind = integrator[0]
    if kind == "trbdf2":
        return ("TRBDF2",)
    if kind == "newmark":
        return ("Newmark", float(integrator[1]), float(integrator[2]))
    if kind == "wilson_theta":
        return ("WilsonTheta", float(integrator[1]))
    if kind == "hht":  # OpenSees weighs the step end by its alpha
        return ("HHT", 1.0 - float(integrator[1]), float(integrator[2]), float(integrator[3]))
    if kind == "generalized_alpha":  # alpha_I, alpha_F: OpenSees' weights of the step end
        alpha_m, alpha_f, gamma, beta = (float(v) for v in integrator[1:])
        return ("HHTGeneralized", 1.0 - alpha_m, 1.0 - alpha_f, beta, gamma)
    if kind == "central_difference":
        return ("NewmarkExplicit", 0.5)
    raise ValueError(f"unknown integrator {kind!r}")


def _pairs(nodes) -> list:
    """An (e, 2) array of nodes as the script's nested lists (none: [])."""
    return np.asarray(nodes if nodes is not None else [], dtype=int).reshape(-1, 2).tolist()


def _numbers(values) -> list:
    """Floats (and integers) as plain Python numbers, whose ``repr`` round-trips."""
    return [int(v) if isinstance(v, (int, np.integer)) else float(v) for v in values]


def _materials(materials) -> list:
    """Twins (:mod:`pframe.peers.twins`) as the script's tuples: the kind, then plain numbers."""
    return [(m[0], *_numbers(m[1:])) for m in materials or []]


def _foundations(scene: PeerScene):
    """The script's FOUNDATIONS (None: fixed bases)."""
    soil = scene.foundations
    if soil is None:
        return None
    grounds = soil.grounds if soil.grounds is not None else np.zeros(len(soil.sway), dtype=int)
    return {"sway": [int(d) for d in soil.sway], "rocking": [int(d) for d in soil.rocking],
            "heights": [float(z) for z in soil.heights],  # (m)
            "story_foundation": [int(f) for f in soil.story_foundation],
            "grounds": [int(s) for s in grounds],  # the support of each one's soil springs
            "sway_materials": _materials(soil.sway_materials),
            "rocking_materials": _materials(soil.rocking_materials)}


def _supports(scene: PeerScene) -> dict:
    """The script's constants of a scene on supports (empty lists on one ground)."""
    on = scene.supports
    if on is None:
        return {"SUPPORTS": [], "CHANNELS": [], "DOF_CHANNEL": [], "DOF_SUPPORT": [],
                "SUPPORT_DAMPING": []}
    return {
        "SUPPORTS": list(on.names),
        # (support, the OpenSees DOF it moves its ground nodes along) of each row of AG
        "CHANNELS": [(int(s), AXIS_DOF[axis]) for s, axis in on.channels],
        "DOF_CHANNEL": [int(c) for c in on.dof_channel],  # -1: a rotation
        "DOF_SUPPORT": [int(s) for s in on.dof_support],
        # mass-proportional damping relative to the support (N s/m, N m s/rad)
        "SUPPORT_DAMPING": [float(c) for c in on.damping],
    }


def _values(scene: PeerScene, out_npz: str | None) -> dict:
    """The script's constants, in the order it lists them."""
    rayleigh = [
        (float(am), float(bk), [int(i) for i in nodes], [int(j) for j in stories], stiffness)
        for am, bk, nodes, stories, stiffness in scene.rayleigh
    ]
    geometric = (np.zeros(len(scene.story_names)) if scene.story_geometric is None
                 else scene.story_geometric)
    return {
        "MASSES": [float(m) for m in scene.masses],
        "STORY_NODES": _pairs(scene.story_nodes),
        "STORY_MATERIALS": _materials(scene.story_materials),
        "STORY_GEOMETRIC": [float(k) for k in geometric],  # P / h (N/m), 0: no P-delta
        "CONTACT_NODES": _pairs(scene.contact_nodes),
        "CONTACT_NAMES": list(scene.contact_names),
        "CONTACT_GAPS": [float(g) for g in scene.contact_gaps],
        "CONTACT_MATERIALS": _materials(scene.contact_materials),
        # (alpha_m, beta_k, nodes, storeys, the stiffness beta_k multiplies)
        "RAYLEIGH": rayleigh,
        "MODAL": [float(r) for r in scene.modal] if scene.modal else [],  # ratio per mode
        "DT": float(scene.dt),
        "STEPS": int(scene.steps),
        "TOL": float(scene.tolerance),
        # OpenSees' Hertzdamp and JankowskiImpact give Newton no damping tangent, so it
        # converges linearly while they are closed (some 60 iterations a step): a wider limit
        # than pframe's, which changes no converged step
        "MAX_ITER": max(int(scene.max_iterations), 1000),
        "INTEGRATOR": opensees_integrator(scene.integrator),
        # an explicit step is one linear solve (NewmarkExplicit takes no Newton iteration)
        "ALGORITHM": "Linear" if scene.integrator[0] == "central_difference" else "Newton",
        "SUBSTEPS": int(scene.substeps),
        "LINK_NODES": _pairs(scene.link_nodes),
        "LINK_MATERIALS": _materials(scene.link_materials),
        "FOUNDATIONS": _foundations(scene),
        **_supports(scene),
        "DIFFERENCES": list(scene.differences),  # where this model is not pframe's
        "OUT_NPZ": out_npz,
    }


def _levers(levers, points) -> np.ndarray:
    return np.zeros(len(points)) if levers is None else np.asarray(levers, dtype=float)


def _plan_values(scene: PeerScene) -> dict:
    """The constants of a scene in plan's script: its floors, and where its elements act."""
    floors = scene.floors

    def points(values) -> list:  # (e, 2, 2) -> [[[x, y], [x, y]], ...]
        return [[[float(v) for v in end] for end in ends] for ends in values]

    def directions(values) -> list:
        return [[float(v) for v in n] for n in values]

    return {
        "FLOOR_NAMES": list(floors.names),
        "CENTRES": [[float(v) for v in c] for c in floors.centres],  # (m)
        "FLOOR_MASSES": [[float(v) for v in m] for m in floors.masses],  # m, m, J
        "MOVES": [[int(v) for v in m] for m in floors.moves],  # u_x, u_y, theta: 0 held
        "DOFS": np.asarray(floors.dofs, dtype=int).reshape(-1, 2).tolist(),  # (floor, c)
        "STORY_POINTS": points(floors.story_points),
        "STORY_DIRECTIONS": directions(floors.story_directions),
        "CONTACT_POINTS": points(floors.contact_points),
        "CONTACT_DIRECTIONS": directions(floors.contact_directions),
        "LINK_POINTS": points(floors.link_points),
        "LINK_DIRECTIONS": directions(floors.link_directions),
        # the lever r of an element on the floors' rotations alone (0: none)
        "STORY_LEVERS": [float(r) for r in _levers(floors.story_levers, floors.story_points)],
        "LINK_LEVERS": [float(r) for r in _levers(floors.link_levers, floors.link_points)],
        "CHANNEL_DOFS": [AXIS_DOF[c.rsplit(":", 1)[-1]] for c in scene.channels],
    }


def _data_block(scene: PeerScene, out_npz: str | None) -> str:
    """Python assignments holding the scene; ``repr`` of floats round-trips exactly."""
    if len(scene.masses) != len(scene.node_names):
        raise ValueError("masses and node_names differ in length")
    rows = scene.floors is not None or scene.supports is not None
    shape = (len(scene.channels), scene.steps + 1) if rows else (scene.steps + 1,)
    if np.shape(scene.ground_acceleration) != shape:
        raise ValueError(f"ground_acceleration must have the shape {shape}")
    values = _values(scene, out_npz)
    if scene.floors is not None:
        values = {k: v for k, v in values.items() if k != "MASSES"} | _plan_values(scene)
    lines = [
        f"{name} = {pprint.pformat(value, width=_WIDTH - len(name) - 3, compact=True)}"
        for name, value in values.items()
    ]
    arrays = {"AG": scene.ground_acceleration}  # m/s^2; on supports also m and m/s
    if scene.supports is not None:
        arrays |= {"GROUND_DISP": scene.supports.displacement,
                   "GROUND_VEL": scene.supports.velocity}
    for name, array in arrays.items():
        lines.append(f"{name} = {_array(array, rows)}")
    if scene.supports is None:
        lines.append("GROUND_DISP = GROUND_VEL = None  # one ground: relative coordinates")
    return "\n".join(lines) + "\n"


def _array(array, rows: bool) -> str:
    """Python source of an array of doubles: base64 keeps a long record compact and
    bit-exact; ``rows``: a row per channel."""
    data = np.ascontiguousarray(array, dtype="<f8")
    text = base64.b64encode(data.tobytes()).decode("ascii")
    chunks = "\n".join(f'        "{text[i : i + 88]}"' for i in range(0, len(text), 88))
    reshape = f".reshape({data.shape[0]}, -1)" if rows else ""
    return (f'np.frombuffer(\n    base64.b64decode(\n{chunks}\n    ),\n    dtype="<f8",\n)'
            f"{reshape}")


def _docstring(scene: PeerScene, written_in: str | None = None) -> str:
    """The script's docstring: what wrote it, its units, and where its model is not
    pframe's."""
    text = ("OpenSeesPy model of one pounding scene, written by pframe.peers.opensees.\n\n"
            "Its numbers are in SI units (N, m, kg, s)"
            + (f": the scene, written in {written_in}, converted." if written_in else "."))
    if not scene.differences:
        return text + "\n\nIt is pframe's model of the scene.\n"
    lines = [text, "", "Where this model is not pframe's:", ""]
    for difference in scene.differences:
        lines += textwrap.wrap(difference, _WIDTH - 4, initial_indent="- ",
                               subsequent_indent="  ")
    return "\n".join(lines).replace('"', "'") + "\n"


def script_text(scene: PeerScene, out_npz: str | None = None,
                written_in: str | None = None) -> str:
    """Return a self-contained OpenSeesPy script for ``scene``.

    Parameters
    ----------
    scene : PeerScene
        The scene to model (planar, or in plan: ``scene.floors``).
    out_npz : str, optional
        Where the script, run as ``__main__``, saves ``time``, ``displacement (steps+1, n)``,
        ``velocity (steps+1, n)``, ``story_force (steps+1, s)`` (material force, without the
        Rayleigh part), ``contact_force (steps+1, c)`` (compression positive), ``link_force``
        and ``analyze_seconds``; a scene in plan also ``story_drift``,
        ``contact_penetration`` and ``link_deformation``, and its DOFs are
        ``scene.floors.dofs``; a scene on supports also ``total_displacement`` and
        ``total_velocity``. Nothing is saved when omitted.
    written_in : str, optional
        The unit system the scene was written in, where it is not SI (docs/units.md): the
        script, in SI, says so.

    Returns
    -------
    str
        Python source importing only the standard library, numpy and ``openseespy``. It
        defines ``build()`` and ``simulate(workdir) -> dict`` and times one
        ``ops.analyze(steps, dt)`` call.
    """
    header = (
        f'"""{_docstring(scene, written_in)}"""\n\n'
        "import base64\nimport os\nimport sys\nimport tempfile\nimport time\n\n"
        "import numpy as np\nimport openseespy.opensees as ops\n\n"
    )
    build = (opensees_script.PLANAR_BUILD if scene.floors is None
             else opensees_script.PLAN_BUILD)
    return (header + _data_block(scene, out_npz) + opensees_script.MATERIALS + build
            + opensees_script.RUN)


def _require_openseespy() -> None:
    """Import openseespy now, turning any failure into an actionable message."""
    try:
        import openseespy.opensees  # noqa: F401
    except Exception as exc:  # a missing liblapack surfaces as ImportError or OSError
        raise RuntimeError(_IMPORT_HINT) from exc


def run(scene: PeerScene, workdir: str | None = None) -> dict:
    """Run ``scene`` with OpenSeesPy in this process.

    Parameters
    ----------
    scene : PeerScene
        The scene to simulate.
    workdir : str, optional
        Directory kept with the script (``opensees_peer.py``) and the recorder files;
        a temporary directory, removed afterwards, when omitted.

    Returns
    -------
    dict
        ``time`` (as accumulated by OpenSees), ``displacement`` and ``velocity`` (relative to
        the ground, ``(steps + 1, n)``; on supports relative to each DOF's support, and
        ``total_displacement``, ``total_velocity`` OpenSees' own), ``story_force``
        (material force, without the Rayleigh part, ``(steps + 1, s)``), ``contact_force``
        (compression positive, ``(steps + 1, c)``), ``link_force``; a scene in plan also
        ``story_drift``, ``contact_penetration`` (0 while open) and ``link_deformation``,
        its DOFs ``scene.floors.dofs``. Row 0 is the state at rest. ``analyze_seconds``
        times the single ``analyze`` call.

    Raises
    ------
    RuntimeError
        If OpenSeesPy cannot be imported or the analysis does not converge.

    Notes
    -----
    The script starts with ``ops.wipe()``: any other OpenSees model in this process is lost.
    """
    _require_openseespy()
    text = script_text(scene)
    with tempfile.TemporaryDirectory(prefix="pframe-opensees-") as tmp:
        base = tmp if workdir is None else os.fspath(workdir)
        os.makedirs(base, exist_ok=True)
        path = os.path.join(base, "opensees_peer.py")
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text)
        namespace = {"__name__": "pframe_opensees_peer", "__file__": path}
        # exec of the very text written above, so the file on disk is what ran
        exec(compile(text, path, "exec"), namespace)
        return namespace["simulate"](base)
