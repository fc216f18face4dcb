"""The code of the OpenSeesPy script that :mod:`pframe.peers.opensees` writes, after its data
block: plain strings, so that the script stays runnable on its own (it never imports pframe)
and ``run`` executes exactly the text written.

The script is :data:`MATERIALS` (the uniaxial materials, Rayleigh regions and ground motion
both models share), then the model's ``build()`` (:data:`PLANAR_BUILD`: one DOF per floor;
:data:`PLAN_BUILD`: floors in plan), then :data:`RUN` (recorders, analysis, ``__main__``).
"""

from __future__ import annotations

MATERIALS = '''
HUGE_FY = 1.0e30  # ElasticPPGap yield force: contacts must never yield


def story_material(tag, mat):
    """The uniaxialMaterial of a storey: pframe's law and its packed numbers."""
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


def gap_material(tag, gap, k):
    """A contact: from the left to the right side, the deformation (u_right - u_left along the
    normal) drops below -gap when the floors overlap, where ElasticPPGap (negative Fy and gap)
    gives stress k (defo + gap) < 0."""
    ops.uniaxialMaterial("ElasticPPGap", tag, k, -HUGE_FY, -gap, 0.0)


def link_material(tag, mat):
    """The uniaxialMaterial of a link (no Rayleigh damping: a dashpot is in its force)."""
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


def rayleigh(stories):
    """One pair of regions per building: alpha_m on its nodes' masses, beta_k on the initial
    stiffness of its storeys (node i is tag i + 1)."""
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


def ground_motion(channels):
    """A UniformExcitation per (OpenSees DOF, samples, nodes it accelerates at t = 0)."""
    for c, (dof, samples, nodes) in enumerate(channels):
        # Step n is analysed at OpenSees' accumulated time t_n = t_(n-1) + DT, which drifts
        # from n DT by rounding (about 1e-12 s after 50,000 steps); a "Path -dt" series,
        # interpolating at t_n / DT, would then feed a_g a hair off the sample n (~1e-11
        # relative late in a run). Sample times accumulated the same way make step n see
        # sample n itself. A Path returns 0 past its last sample: one more sample repeats
        # the last value. With SUBSTEPS analysis steps a step (TRBDF2) the samples between
        # pframe's are its linear interpolation, as pframe has them.
        ag = [float(samples[0])] + [
            (1.0 - j / SUBSTEPS) * float(a0) + j / SUBSTEPS * float(a1)
            for a0, a1 in zip(samples[:-1], samples[1:]) for j in range(1, SUBSTEPS + 1)]
        times, t = [], 0.0
        for _ in ag:
            times.append(t)
            t += DT / SUBSTEPS
        ops.timeSeries("Path", c + 1, "-time", *times, t, "-values", *ag, ag[-1])
        ops.pattern("UniformExcitation", c + 1, dof, "-accel", c + 1)
        # OpenSees starts from zero acceleration; equilibrium at rest asks for -a_g(0).
        if ag[0] != 0.0:
            for node in nodes:
                ops.setNodeAccel(node, dof, -ag[0], "-commit")
'''

PLANAR_BUILD = '''
CONSTRAINTS = "Plain"  # no multi-point constraint: one DOF per node


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
        story_material(tag, mat)
        # zeroLength deformation is u_j - u_i: lower -> upper makes it the drift.
        # Without -doRayleigh the element ignores the region's damping factors.
        i_node = ground if lower < 0 else lower + 1
        ops.element("zeroLength", tag, i_node, upper + 1, "-mat", tag, "-dir", 1,
                    "-doRayleigh", 1)
        stories.append(tag)

    if MODAL:
        # every mode of the buildings on their own: before the contacts (and their tangents)
        # join the domain; -fullGenLapack is the solver that gives all of them
        ops.eigen("-fullGenLapack", len(MODAL))
        ops.modalDamping(*MODAL)

    contacts = []
    for j, ((left, right), gap, k) in enumerate(
            zip(CONTACT_NODES, CONTACT_GAPS, CONTACT_STIFFNESS, strict=True)):
        tag = len(stories) + j + 1
        gap_material(tag, gap, k)
        # a wall: the ground's node on its side (-1)
        ops.element("zeroLength", tag, ground if left < 0 else left + 1,
                    ground if right < 0 else right + 1, "-mat", tag, "-dir", 1)
        contacts.append(tag)

    links = []
    for j, ((first, second), mat) in enumerate(zip(LINK_NODES, LINK_MATERIALS, strict=True)):
        tag = len(stories) + len(contacts) + j + 1
        link_material(tag, mat)
        # zeroLength deformation is u_j - u_i: first -> second (no Rayleigh on links)
        ops.element("zeroLength", tag, ground if first < 0 else first + 1,
                    ground if second < 0 else second + 1, "-mat", tag, "-dir", 1)
        links.append(tag)

    rayleigh(stories)
    ground_motion([(1, AG, range(1, n + 1))])
    return stories, contacts, links


def recorders(stories, contacts, links):
    """name -> (recorder kind, columns, its arguments)."""
    nodes = list(range(1, len(MASSES) + 1))
    return {
        "displacement": ("Node", len(nodes), ("-node", *nodes, "-dof", 1, "disp")),
        "velocity": ("Node", len(nodes), ("-node", *nodes, "-dof", 1, "vel")),
        "story_force": ("Element", len(stories), ("-ele", *stories, "basicForce")),
        "contact_force": ("Element", len(contacts), ("-ele", *contacts, "basicForce")),
        "link_force": ("Element", len(links), ("-ele", *links, "basicForce")),
    }


def finish(result):
    """pframe's conventions: the gap material is negative in compression (0.0 - x also
    avoids -0.0)."""
    result["contact_force"] = 0.0 - result["contact_force"]
'''

PLAN_BUILD = '''
# The rigid diaphragms are multi-point constraints: Transformation eliminates the tied DOFs
# exactly (Plain takes single-point constraints only).
CONSTRAINTS = "Transformation"


def build():
    """Create the model in the OpenSees domain; return storey, contact and link element tags.

    Node f + 1 is floor f at its centre of mass with its mass (m, m, J), the components the
    scene does not move fixed. Every element end is a node of its own at the end's point,
    tied to its floor by a rigidLink beam (in 2-D the exact small-rotation map u_P = (u_x -
    theta dy, u_y + theta dx, theta), dx, dy from the floor's node to the point) or fixed (the
    ground); a zeroLength along the element's direction (-orient) joins two ends.
    """
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for f, ((x, y), masses, moves) in enumerate(zip(CENTRES, FLOOR_MASSES, MOVES, strict=True)):
        ops.node(f + 1, x, y)
        ops.mass(f + 1, *masses)
        if not all(moves):
            ops.fix(f + 1, *[0 if m else 1 for m in moves])
    ends = {}  # (floor, x, y) -> node: elements meeting at a point of a floor share it

    def end(floor, point):
        key = (floor, *point)
        if key not in ends:
            ends[key] = tag = len(CENTRES) + len(ends) + 1
            ops.node(tag, *point)
            if floor < 0:  # the ground
                ops.fix(tag, 1, 1, 1)
            else:
                ops.rigidLink("beam", floor + 1, tag)
        return ends[key]

    def element(tag, nodes, points, direction, *flags):
        # local x along the direction: the deformation is n . (u_second - u_first), the
        # force acts along n; ends apart across the direction only draw a length warning
        nx, ny = direction
        ops.element("zeroLength", tag, *(end(f, p) for f, p in zip(nodes, points)),
                    "-mat", tag, "-dir", 1, "-orient", nx, ny, 0.0, -ny, nx, 0.0, *flags)
        return tag

    stories = []
    for j, (nodes, points, direction, mat) in enumerate(zip(
            STORY_NODES, STORY_POINTS, STORY_DIRECTIONS, STORY_MATERIALS, strict=True)):
        story_material(j + 1, mat)
        # without -doRayleigh a storey ignores its region's stiffness damping
        stories.append(element(j + 1, nodes, points, direction, "-doRayleigh", 1))

    if MODAL:
        # every mode of the buildings on their own: before the contacts (and their tangents)
        # join the domain; -fullGenLapack is the solver that gives all of them
        ops.eigen("-fullGenLapack", len(MODAL))
        ops.modalDamping(*MODAL)

    contacts = []
    for j, (nodes, points, direction, gap, k) in enumerate(zip(
            CONTACT_NODES, CONTACT_POINTS, CONTACT_DIRECTIONS, CONTACT_GAPS,
            CONTACT_STIFFNESS, strict=True)):
        gap_material(len(stories) + j + 1, gap, k)
        contacts.append(element(len(stories) + j + 1, nodes, points, direction))
    links = []
    for j, (nodes, points, direction, mat) in enumerate(zip(
            LINK_NODES, LINK_POINTS, LINK_DIRECTIONS, LINK_MATERIALS, strict=True)):
        tag = len(stories) + len(contacts) + j + 1
        link_material(tag, mat)
        links.append(element(tag, nodes, points, direction))

    rayleigh(stories)
    # each channel loads (and starts accelerated) the floors that move along its axis
    ground_motion([(dof, samples, [f + 1 for f, moves in enumerate(MOVES) if moves[dof - 1]])
                   for dof, samples in zip(CHANNEL_DOFS, AG, strict=True)])
    return stories, contacts, links


def recorders(stories, contacts, links):
    """name -> (recorder kind, columns, its arguments); the floors' u_x, u_y, theta."""
    floors = list(range(1, len(CENTRES) + 1))
    out = {}
    for name, response in (("displacement", "disp"), ("velocity", "vel")):
        out[name] = ("Node", 3 * len(floors), ("-node", *floors, "-dof", 1, 2, 3, response))
    for kind, tags, deformation in (("story", stories, "story_drift"),
                                    ("contact", contacts, "contact_penetration"),
                                    ("link", links, "link_deformation")):
        out[kind + "_force"] = ("Element", len(tags), ("-ele", *tags, "basicForce"))
        out[deformation] = ("Element", len(tags), ("-ele", *tags, "basicDeformation"))
    return out


def finish(result):
    """pframe's conventions: the degrees of freedom in DOFS' order; a contact's force positive
    in compression and its penetration n . (u_left - u_right) - gap, 0 while the gap is open
    (0.0 - x avoids -0.0)."""
    columns = [3 * f + c for f, c in DOFS]
    for name in ("displacement", "velocity"):
        result[name] = result[name][:, columns]
    result["contact_force"] = 0.0 - result["contact_force"]
    result["contact_penetration"] = np.maximum(
        0.0 - result["contact_penetration"] - np.asarray(CONTACT_GAPS, dtype=float), 0.0)
'''

RUN = '''

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
    """Build, run one ``analyze(STEPS * SUBSTEPS, DT / SUBSTEPS)`` and return the histories
    of pframe's steps (row 0 is t = 0)."""
    stories, contacts, links = build()
    recorded = recorders(stories, contacts, links)
    for name, (kind, columns, args) in recorded.items():
        if columns:
            path = os.path.join(workdir, name + ".bin")
            ops.recorder(kind, "-binary", path, "-time", *args)

    ops.constraints(CONSTRAINTS)
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
    for name, (_, columns, _) in recorded.items():
        history = np.zeros((STEPS + 1, columns))
        if columns:
            rows = _read_binary(os.path.join(workdir, name + ".bin"), columns + 1)
            if rows.shape[0] != STEPS * SUBSTEPS:
                raise RuntimeError(f"{name}: {rows.shape[0]} recorded steps, not "
                                   f"{STEPS * SUBSTEPS}")
            rows = rows[SUBSTEPS - 1::SUBSTEPS]  # pframe's steps
            result["time"][1:] = rows[:, 0]
            history[1:] = rows[:, 1:]
        result[name] = history
    finish(result)
    return result


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as tmp:
        result = simulate(tmp)
    print(f"analyze({STEPS * SUBSTEPS}, {DT / SUBSTEPS!r}): {result['analyze_seconds']:.4f} s")
    if OUT_NPZ is not None:
        np.savez(OUT_NPZ, **result)
'''
