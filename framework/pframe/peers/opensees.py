"""OpenSeesPy peer: the same scene built from stock OpenSees components.

The peer serves two purposes: an independent check of pframe's kernel and a speed benchmark.
:func:`script_text` writes a self-contained OpenSeesPy script (it never imports pframe), so
the model can be rerun, inspected or timed without pframe installed; :func:`run` executes that
same text in this process and returns its histories.

Model (1-D, one DOF per node, node ``i + 1`` is DOF ``i``, one fixed ground node):

* storeys: ``zeroLength`` with ``Elastic``, ``Steel01`` (``b = alpha``, no isotropic
  hardening), ``BoucWen`` (the law ``bouc_wen``, its parameters, tolerance and iterations),
  ``ModIMKPeakOriented`` (imk_peak's 23 numbers) or ``BWBN`` (the law ``bwbn`` without
  degradation: its 12 numbers, tolerance and iterations) from the lower to the upper node,
  so the element deformation is the drift;
* contacts: ``zeroLength`` from the left to the right node with ``ElasticPPGap(k, -huge, -gap)``;
  its deformation ``u_right - u_left`` falls below ``-gap`` exactly when
  ``u_left - u_right - gap > 0``, and the (negative) material stress is minus the
  compression force;
* Rayleigh damping: ``alpha_m`` on the building's nodes, ``beta_k`` on the initial stiffness of
  its storeys that take the stiffness term (``-doRayleigh 1``; not its isolators); contacts
  are undamped; or modal damping: ``eigen`` of every mode with ``-fullGenLapack`` on the
  storeys' initial stiffness (before the contacts exist), then ``modalDamping`` with the
  ratio of each mode;
* ground motion: ``Path`` series driving a ``UniformExcitation`` (load ``-m a_g`` in relative
  coordinates), its sample times accumulated as OpenSees accumulates time, so that step ``n``
  sees ``a_g[n]`` exactly; Newton iterations with a ``NormDispIncr`` test, one
  ``analyze(steps, dt)`` call and binary recorders;
* the integrator: ``Newmark``, ``HHT`` (OpenSees' alpha is 1 - pframe's), ``WilsonTheta`` or
  ``TRBDF2`` (Bathe's method with gamma = 1/2: OpenSees takes its trapezoidal and backward
  sub-steps as alternate analysis steps of dt / 2, so the script analyses twice the steps at
  half the step, with the ground motion sampled between pframe's samples as pframe
  interpolates it, linearly, and records every second step).
  Not generalised-alpha: OpenSees' ``GeneralizedAlpha`` sets the nodes' accelerations to
  a(n+1) in its Newton update (``GeneralizedAlpha::update``) where its tangent and the method
  have a(n+1-alpha_m); a linear oscillator (w dt = 5, rho_inf = 0.6) grows in amplitude under
  it, where the method's amplification matrix and pframe decay.
  OpenSees' Wilson-theta reads the ground motion at t + theta dt from the record (between the
  next two samples) where the method, as pframe has it, extrapolates the step's own samples
  linearly (Wilson, Farhoomand & Bathe 1973): the two agree to round-off under a ground
  motion linear in time, and differ by O(dt^2) under others.

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

import numpy as np

from pframe.peers.scene import PeerScene

_IMPORT_HINT = (
    'OpenSeesPy is not importable: install the peers extra (pip install "pframe[peers]") '
    "and the system BLAS/LAPACK (apt-get install libblas3 liblapack3)"
)
_WIDTH = 100  # line length of the generated script

# Code of the generated script after its data block. It is a plain string so that the
# script stays runnable on its own; ``run`` executes exactly this text.
_BODY = '''
HUGE_FY = 1.0e30  # ElasticPPGap yield force: contacts must never yield


def build():
    """Create the model in the OpenSees domain; return storey, contact and link element tags."""
    n = len(MASSES)
    ground = n + 1
    ops.wipe()
    ops.model("basic", "-ndm", 1, "-ndf", 1)
    for i, m in enumerate(MASSES):
        ops.node(i + 1, 0.0)
        ops.mass(i + 1, m)
    ops.node(ground, 0.0)
    ops.fix(ground, 1)

    stories = []
    for j, ((lower, upper), mat) in enumerate(zip(STORY_NODES, STORY_MATERIALS, strict=True)):
        tag = j + 1
        if mat[0] == "elastic":
            ops.uniaxialMaterial("Elastic", tag, mat[1])
        elif mat[0] == "bouc_wen":
            # alpha, ko, n, gamma, beta, Ao, deltaA, deltaNu, deltaEta, tolerance, maxNumIter
            ops.uniaxialMaterial("BoucWen", tag, *mat[1:])
        elif mat[0] == "imk_peak":  # pframe's packed numbers are OpenSees' 23 arguments
            ops.uniaxialMaterial("ModIMKPeakOriented", tag, *mat[1:])
        elif mat[0] == "bwbn":
            # alpha, ko, n, gamma, beta, Ao, q, zetas, p, Shi, deltaShi, lamda, tol, maxNumIter
            ops.uniaxialMaterial("BWBN", tag, *mat[1:])
        else:
            _, k, fy, alpha = mat
            ops.uniaxialMaterial("Steel01", tag, fy, k, alpha)
        # zeroLength deformation is u_j - u_i: lower -> upper makes it the drift.
        # Without -doRayleigh the element ignores the region's damping factors.
        i_node = ground if lower < 0 else lower + 1
        ops.element("zeroLength", tag, i_node, upper + 1, "-mat", tag, "-dir", 1,
                    "-doRayleigh", 1)
        stories.append(tag)

    if MODAL:
        # every mode of the buildings on their own: before the contacts (and their tangents)
        # join the domain; -fullGenLapack is the solver that gives all n modes
        ops.eigen("-fullGenLapack", n)
        ops.modalDamping(*MODAL)

    contacts = []
    for j, ((left, right), gap, k) in enumerate(
            zip(CONTACT_NODES, CONTACT_GAPS, CONTACT_STIFFNESS, strict=True)):
        tag = len(stories) + j + 1
        # left -> right: deformation u_right - u_left drops below -gap when the floors
        # overlap, where ElasticPPGap (negative Fy and gap) gives stress k (defo + gap) < 0.
        ops.uniaxialMaterial("ElasticPPGap", tag, k, -HUGE_FY, -gap, 0.0)
        # a wall: the ground's node on its side (-1)
        ops.element("zeroLength", tag, ground if left < 0 else left + 1,
                    ground if right < 0 else right + 1, "-mat", tag, "-dir", 1)
        contacts.append(tag)

    links = []
    for j, ((first, second), mat) in enumerate(zip(LINK_NODES, LINK_MATERIALS, strict=True)):
        tag = len(stories) + len(contacts) + j + 1
        if mat[0] == "elastic":
            ops.uniaxialMaterial("Elastic", tag, mat[1])
        elif mat[0] == "bilinear":
            ops.uniaxialMaterial("Steel01", tag, mat[2], mat[1], mat[3])
        elif mat[0] == "viscous":
            ops.uniaxialMaterial("Viscous", tag, mat[1], mat[2])
        else:  # kelvin_voigt: a spring and a dashpot in parallel
            ops.uniaxialMaterial("Elastic", 100000 + tag, mat[1])
            ops.uniaxialMaterial("Viscous", 200000 + tag, mat[2], mat[3])
            ops.uniaxialMaterial("Parallel", tag, 100000 + tag, 200000 + tag)
        # zeroLength deformation is u_j - u_i: first -> second (no Rayleigh on links)
        ops.element("zeroLength", tag, ground if first < 0 else first + 1,
                    ground if second < 0 else second + 1, "-mat", tag, "-dir", 1)
        links.append(tag)

    for b, (alpha_m, beta_k, nodes, story_ids) in enumerate(RAYLEIGH):
        # The "Only" flags matter: a -node region also takes every element whose nodes
        # are all listed, an -ele region takes the elements' nodes, and each region
        # overwrites all four factors of everything it holds.
        if alpha_m != 0.0 and len(nodes) > 0:
            ops.region(2 * b + 1, "-nodeOnly", *[i + 1 for i in nodes],
                       "-rayleigh", alpha_m, 0.0, 0.0, 0.0)
        if beta_k != 0.0 and len(story_ids) > 0:
            ops.region(2 * b + 2, "-eleOnly", *[stories[j] for j in story_ids],
                       "-rayleigh", 0.0, 0.0, beta_k, 0.0)

    # Step n is analysed at OpenSees' accumulated time t_n = t_(n-1) + DT, which drifts from
    # n DT by rounding (about 1e-12 s after 50,000 steps); a "Path -dt" series, interpolating
    # at t_n / DT, would then feed a_g a hair off AG[n] (~1e-11 relative late in a run). Sample
    # times accumulated the same way make step n see AG[n] itself. A Path returns 0 past its
    # last sample: one more sample repeats the last value. With SUBSTEPS analysis steps a step
    # (TRBDF2) the samples between pframe's are its linear interpolation, as pframe has them.
    ag = [float(AG[0])] + [(1.0 - j / SUBSTEPS) * float(a0) + j / SUBSTEPS * float(a1)
                           for a0, a1 in zip(AG[:-1], AG[1:]) for j in range(1, SUBSTEPS + 1)]
    times, t = [], 0.0
    for _ in ag:
        times.append(t)
        t += DT / SUBSTEPS
    ops.timeSeries("Path", 1, "-time", *times, t, "-values", *ag, ag[-1])
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    # OpenSees starts from zero acceleration; equilibrium at rest asks for -a_g(0).
    if ag[0] != 0.0:
        for i in range(n):
            ops.setNodeAccel(i + 1, 1, -ag[0], "-commit")
    return stories, contacts, links


def _read_binary(path, columns):
    """Rows of a ``-binary`` recorder: ``columns`` native doubles then a newline byte."""
    row = np.dtype([("values", "f8", (columns,)), ("eol", "u1")])
    size = os.path.getsize(path)
    if size % row.itemsize:
        raise RuntimeError(f"unexpected recorder layout in {path}")
    data = np.fromfile(path, dtype=row)
    if not np.all(data["eol"] == 10):
        raise RuntimeError(f"unexpected recorder layout in {path}")
    return data["values"]


def simulate(workdir):
    """Build, run one ``analyze(STEPS * SUBSTEPS, DT / SUBSTEPS)`` and return the histories of
    pframe's steps (row 0 is t = 0)."""
    stories, contacts, links = build()
    nodes = list(range(1, len(MASSES) + 1))
    recorders = {
        "displacement": ("Node", nodes, ("-node", *nodes, "-dof", 1, "disp")),
        "velocity": ("Node", nodes, ("-node", *nodes, "-dof", 1, "vel")),
        "story_force": ("Element", stories, ("-ele", *stories, "basicForce")),
        "contact_force": ("Element", contacts, ("-ele", *contacts, "basicForce")),
        "link_force": ("Element", links, ("-ele", *links, "basicForce")),
    }
    for name, (kind, tags, args) in recorders.items():
        if tags:
            path = os.path.join(workdir, name + ".bin")
            ops.recorder(kind, "-binary", path, "-time", *args)

    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", TOL, MAX_ITER)
    ops.algorithm("Newton")
    ops.integrator(*INTEGRATOR)
    ops.analysis("Transient")

    start = time.perf_counter()
    status = ops.analyze(STEPS * SUBSTEPS, DT / SUBSTEPS)
    seconds = time.perf_counter() - start
    reached = ops.getTime()
    ops.wipe()  # closes (flushes) the recorders
    if status != 0:
        raise RuntimeError(f"OpenSees analyze failed (status {status}) at t = {reached}")

    result = {"time": np.arange(STEPS + 1) * DT, "analyze_seconds": seconds}
    for name, (_, tags, _) in recorders.items():
        history = np.zeros((STEPS + 1, len(tags)))
        if tags:
            rows = _read_binary(os.path.join(workdir, name + ".bin"), len(tags) + 1)
            if rows.shape[0] != STEPS * SUBSTEPS:
                raise RuntimeError(f"{name}: {rows.shape[0]} recorded steps, not "
                                   f"{STEPS * SUBSTEPS}")
            rows = rows[SUBSTEPS - 1::SUBSTEPS]  # pframe's steps
            result["time"][1:] = rows[:, 0]
            history[1:] = rows[:, 1:]
        result[name] = history
    # the gap material is negative in compression; 0.0 - x also avoids -0.0
    result["contact_force"] = 0.0 - result["contact_force"]
    return result


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as tmp:
        result = simulate(tmp)
    print(f"analyze({STEPS}, {DT!r}): {result['analyze_seconds']:.4f} s")
    if OUT_NPZ is not None:
        np.savez(OUT_NPZ, **result)
'''


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
    raise ValueError(f"unknown integrator {kind!r}")


def analysis_steps(integrator: tuple) -> int:
    """OpenSees analysis steps per pframe step: 2 for TRBDF2 (a sub-step each), else 1."""
    return 2 if integrator[0] == "trbdf2" else 1


def _data_block(scene: PeerScene, out_npz: str | None) -> str:
    """Python assignments holding the scene; ``repr`` of floats round-trips exactly."""
    if len(scene.masses) != len(scene.node_names):
        raise ValueError("masses and node_names differ in length")
    ag = np.ascontiguousarray(scene.ground_acceleration, dtype="<f8")
    if ag.shape != (scene.steps + 1,):
        raise ValueError(f"ground_acceleration must have steps + 1 = {scene.steps + 1} samples")
    materials = []
    for mat in scene.story_materials:
        if mat[0] == "elastic":
            materials.append(("elastic", float(mat[1])))
        elif mat[0] == "bilinear":
            materials.append(("bilinear", *(float(v) for v in mat[1:4])))
        elif mat[0] == "bouc_wen":  # the 9 parameters, the tolerance, the iterations
            materials.append(("bouc_wen", *(float(v) for v in mat[1:11]), int(mat[11])))
        elif mat[0] == "imk_peak":
            materials.append(("imk_peak", *(float(v) for v in mat[1:24])))
        elif mat[0] == "bwbn":  # the 12 parameters, the tolerance, the iterations
            materials.append(("bwbn", *(float(v) for v in mat[1:14]), int(mat[14])))
        else:
            raise ValueError(f"unknown storey material {mat[0]!r}")
    rayleigh = [
        (float(am), float(bk), [int(i) for i in nodes], [int(j) for j in stories])
        for am, bk, nodes, stories in scene.rayleigh
    ]
    values = {
        "MASSES": [float(m) for m in scene.masses],
        "STORY_NODES": np.asarray(scene.story_nodes, dtype=int).reshape(-1, 2).tolist(),
        "STORY_MATERIALS": materials,
        "CONTACT_NODES": np.asarray(scene.contact_nodes, dtype=int).reshape(-1, 2).tolist(),
        "CONTACT_GAPS": [float(g) for g in scene.contact_gaps],
        "CONTACT_STIFFNESS": [float(k) for k in scene.contact_stiffness],
        "RAYLEIGH": rayleigh,  # (alpha_m, beta_k on initial stiffness, DOFs, storeys)
        "MODAL": [float(r) for r in scene.modal] if scene.modal else [],  # ratio per mode
        "DT": float(scene.dt),
        "STEPS": int(scene.steps),
        "TOL": float(scene.tolerance),
        "MAX_ITER": int(scene.max_iterations),
        "INTEGRATOR": opensees_integrator(scene.integrator),
        "SUBSTEPS": analysis_steps(scene.integrator),
        "LINK_NODES": np.asarray(scene.link_nodes if scene.link_nodes is not None else [],
                                 dtype=int).reshape(-1, 2).tolist(),
        "LINK_MATERIALS": [tuple(m[:1]) + tuple(float(v) for v in m[1:])
                           for m in (scene.link_materials or [])],
        "OUT_NPZ": out_npz,
    }
    lines = [
        f"{name} = {pprint.pformat(value, width=_WIDTH - len(name) - 3, compact=True)}"
        for name, value in values.items()
    ]
    # base64 keeps a long record compact and bit-exact
    text = base64.b64encode(ag.tobytes()).decode("ascii")
    chunks = "\n".join(f'        "{text[i : i + 88]}"' for i in range(0, len(text), 88))
    lines.append(
        f'AG = np.frombuffer(\n    base64.b64decode(\n{chunks}\n    ),\n    dtype="<f8",\n)'
    )
    return "\n".join(lines) + "\n"


def script_text(scene: PeerScene, out_npz: str | None = None) -> str:
    """Return a self-contained OpenSeesPy script for ``scene``.

    Parameters
    ----------
    scene : PeerScene
        The scene to model.
    out_npz : str, optional
        Where the script, run as ``__main__``, saves ``time``, ``displacement (steps+1, n)``,
        ``velocity (steps+1, n)``, ``story_force (steps+1, s)`` (material force, without the
        Rayleigh part), ``contact_force (steps+1, c)`` (compression positive) and
        ``analyze_seconds``. Nothing is saved when omitted.

    Returns
    -------
    str
        Python source importing only the standard library, numpy and ``openseespy``. It
        defines ``build()`` and ``simulate(workdir) -> dict`` and times one
        ``ops.analyze(steps, dt)`` call.
    """
    header = (
        '"""OpenSeesPy model of one pounding scene, written by pframe.peers.opensees."""\n\n'
        "import base64\nimport os\nimport tempfile\nimport time\n\n"
        "import numpy as np\nimport openseespy.opensees as ops\n\n"
    )
    return header + _data_block(scene, out_npz) + _BODY


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
        the ground, ``(steps + 1, n)``), ``story_force`` (material force, without the Rayleigh
        part, ``(steps + 1, s)``), ``contact_force`` (compression positive, ``(steps + 1, c)``);
        row 0 is the state at rest. ``analyze_seconds`` times the single ``analyze`` call.

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
