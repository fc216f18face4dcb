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
PART = 1000000  # tags of the parts of a Parallel material: PART * k + the element's tag


def material(tag, mat):
    """The uniaxialMaterial of a storey or link: pframe's law as its OpenSees twin
    (pframe.peers.twins) with the law's packed numbers."""
    kind = mat[0]
    if kind == "elastic":
        ops.uniaxialMaterial("Elastic", tag, mat[1])
    elif kind == "bilinear":  # kinematic hardening: Steel01 without isotropic hardening
        _, k, fy, alpha = mat
        ops.uniaxialMaterial("Steel01", tag, fy, k, alpha)
    elif kind == "bouc_wen":
        # alpha, ko, n, gamma, beta, Ao, deltaA, deltaNu, deltaEta, tolerance, maxNumIter
        ops.uniaxialMaterial("BoucWen", tag, *mat[1:])
    elif kind == "imk_peak":  # pframe's packed numbers are OpenSees' 23 arguments
        ops.uniaxialMaterial("ModIMKPeakOriented", tag, *mat[1:])
    elif kind == "bwbn":
        # alpha, ko, n, gamma, beta, Ao, q, zetas, p, Shi, deltaShi, lamda, tol, maxNumIter
        ops.uniaxialMaterial("BWBN", tag, *mat[1:])
    elif kind == "viscous":  # c |v|^alpha sign v
        ops.uniaxialMaterial("Viscous", tag, mat[1], mat[2])
    elif kind == "kelvin_voigt":  # a spring and a dashpot in parallel
        ops.uniaxialMaterial("Elastic", PART + tag, mat[1])
        ops.uniaxialMaterial("Viscous", 2 * PART + tag, mat[2], mat[3])
        ops.uniaxialMaterial("Parallel", tag, PART + tag, 2 * PART + tag)
    elif kind == "coulomb_pendulum":
        # Coulomb friction, elastic-perfectly plastic (k0 = k_init - W / R up to mu W),
        # beside the pendulum's restoring stiffness W / R
        _, k0, q_yield, k2 = mat
        ops.uniaxialMaterial("Steel01", PART + tag, q_yield, k0, 0.0)
        ops.uniaxialMaterial("Elastic", 2 * PART + tag, k2)
        ops.uniaxialMaterial("Parallel", tag, PART + tag, 2 * PART + tag)
    else:
        raise ValueError(f"unknown material {kind!r}")


def contact_material(tag, mat, gap):
    """A contact's twin, from the left to the right side: the deformation (u_right - u_left
    along the normal) drops below -gap when the floors overlap, where each material (with its
    gap negative) pushes back with a negative stress."""
    kind = mat[0]
    if kind == "linear":  # ElasticPPGap: stress k (defo + gap) < 0
        ops.uniaxialMaterial("ElasticPPGap", tag, mat[1], -HUGE_FY, -gap, 0.0)
    elif kind == "hertzdamp":  # (K_h + xi delta') delta^n, xi = xi_norm K_h / v0
        _, k, xi_norm, n = mat
        ops.uniaxialMaterial("Hertzdamp", tag, k, xi_norm, -gap, n)
    elif kind == "jankowski":  # beta delta^1.5 + 2 zeta sqrt(beta delta^0.5 m_eff) delta'
        _, beta, zeta, m_eff = mat
        ops.uniaxialMaterial("JankowskiImpact", tag, beta, zeta, m_eff, -gap, 1.5)
    elif kind == "bumper":  # the rubber, and the hard contact once it is crushed
        _, k, chi, n, hard, depth = mat
        ops.uniaxialMaterial("Hertzdamp", PART + tag, k, chi, -gap, n)
        ops.uniaxialMaterial("Hertzdamp", 2 * PART + tag, hard, chi, -(gap + depth), n)
        ops.uniaxialMaterial("Parallel", tag, PART + tag, 2 * PART + tag)
    else:
        raise ValueError(f"unknown contact material {kind!r}")


def rayleigh(stories):
    """alpha_m on the nodes' masses (node i is tag i + 1), beta_k on the initial, current or
    committed stiffness of the storeys: a region per building and stiffness."""
    factors = {"initial": 2, "current": 1, "committed": 3}  # betaKinit, betaK, betaKcomm
    for r, (alpha_m, beta_k, nodes, story_ids, stiffness) in enumerate(RAYLEIGH):
        # The "Only" flags matter: a -node region also takes every element whose nodes
        # are all listed, an -ele region takes the elements' nodes, and each region
        # overwrites all four factors of everything it holds.
        if alpha_m != 0.0 and len(nodes) > 0:
            ops.region(2 * r + 1, "-nodeOnly", *[i + 1 for i in nodes],
                       "-rayleigh", alpha_m, 0.0, 0.0, 0.0)
        if beta_k != 0.0 and len(story_ids) > 0:
            beta = [0.0, 0.0, 0.0]
            beta[factors[stiffness] - 1] = beta_k
            ops.region(2 * r + 2, "-eleOnly", *[stories[j] for j in story_ids],
                       "-rayleigh", 0.0, *beta)


def path(tag, samples):
    """A Path series of pframe's samples at its steps; returns its tag."""
    # Step n is analysed at OpenSees' accumulated time t_n = t_(n-1) + DT, which drifts from
    # n DT by rounding (about 1e-12 s after 50,000 steps); a "Path -dt" series, interpolating
    # at t_n / DT, would then feed a_g a hair off the sample n (~1e-11 relative late in a
    # run). Sample times accumulated the same way make step n see sample n itself. A Path
    # returns 0 past its last sample: one more sample repeats the last value. With SUBSTEPS
    # analysis steps a step (TRBDF2) the samples between pframe's are its linear
    # interpolation, as pframe has them.
    values = [float(samples[0])] + [
        (1.0 - j / SUBSTEPS) * float(a0) + j / SUBSTEPS * float(a1)
        for a0, a1 in zip(samples[:-1], samples[1:]) for j in range(1, SUBSTEPS + 1)]
    times, t = [], 0.0
    for _ in values:
        times.append(t)
        t += DT / SUBSTEPS
    ops.timeSeries("Path", tag, "-time", *times, t, "-values", *values, values[-1])
    return tag


def ground_motion(channels):
    """A UniformExcitation per (OpenSees DOF, samples, nodes it accelerates at t = 0)."""
    for c, (dof, samples, nodes) in enumerate(channels):
        ops.pattern("UniformExcitation", c + 1, dof, "-accel", path(c + 1, samples))
        # OpenSees starts from zero acceleration; equilibrium at rest asks for -a_g(0).
        if samples[0] != 0.0:
            for node in nodes:
                ops.setNodeAccel(node, dof, -float(samples[0]), "-commit")


def ground_node(tag, support, *coordinates):
    """A node of the ground: fixed on one ground; on supports (SUPPORTS) moved along the DOFs
    its support's channels move (support_motion) and fixed along the others."""
    ops.node(tag, *coordinates)
    moved = {dof for s, dof in CHANNELS if s == support}
    held = [0 if dof in moved else 1 for dof in range(1, (1 if len(coordinates) == 1 else 3) + 1)]
    if any(held):
        ops.fix(tag, *held)
    return tag


def support_motion(grounds):
    """A scene on supports, in total coordinates: OpenSees' MultipleSupport pattern with a
    groundMotion per channel imposed on each ground node of its support (grounds: support ->
    nodes) along its axis. Each groundMotion is given its displacement, velocity and
    acceleration (GROUND_DISP, GROUND_VEL, AG: pframe's trapezoid rule twice from rest), so
    that OpenSees imposes pframe's displacement sample for sample and never integrates a
    record itself (which 3.7 does at 0.01 s whatever the record's step, cut to whole seconds);
    the ground nodes' velocities are the series' (ImposedMotionSP), which dashpots and
    stiffness-proportional damping read."""
    ops.pattern("MultipleSupport", 1)
    for c, (support, dof) in enumerate(CHANNELS):
        tags = [path(3 * c + k + 1, rows[c]) for k, rows in enumerate((GROUND_DISP, GROUND_VEL,
                                                                        AG))]
        ops.groundMotion(c + 1, "Plain", "-disp", tags[0], "-vel", tags[1], "-accel", tags[2])
        for node in grounds[support]:
            ops.imposedMotion(node, dof, c + 1)


def support_dashpots(tag, dashpot):
    """pframe's mass-proportional damping on supports acts on each DOF's motion relative to
    its support, where OpenSees' Rayleigh mass term would act on the total velocity (and damp
    the supports' rigid motion): a dashpot (Viscous with alpha = 1: c v exactly) on each DOF
    from its support's ground, made by dashpot(tag, dof); returns the last tag used."""
    for d, c in enumerate(SUPPORT_DAMPING):
        if c != 0.0:
            tag += 1
            ops.uniaxialMaterial("Viscous", tag, c, 1.0)
            dashpot(tag, d)
    return tag


def relative(result):
    """On supports: each DOF's total displacement and velocity (OpenSees') kept as
    total_displacement and total_velocity, and made relative to its support, as pframe
    records them."""
    if not SUPPORTS:
        return
    for name, rows in (("displacement", GROUND_DISP), ("velocity", GROUND_VEL)):
        result["total_" + name] = result[name].copy()
        for d, c in enumerate(DOF_CHANNEL):
            if c >= 0:
                result[name][:, d] -= rows[c]
'''

PLANAR_BUILD = '''
# Buildings on soil (FOUNDATIONS) make the model 2-D, in the vertical plane, with equalDOF
# ties: Transformation eliminates them exactly; otherwise one DOF per node and no constraint.
# A scene on supports imposes their motion on ground nodes (non-homogeneous single-point
# constraints), which Transformation enforces.
CONSTRAINTS = "Plain" if FOUNDATIONS is None and not SUPPORTS else "Transformation"
GEOMETRIC = []  # P-delta's elements, one per storey that has one (build() fills it)


def dof_nodes():
    """(node, OpenSees DOF) of each DOF: node i + 1 along x, a foundation's rocking the
    rotation of its sway's node."""
    out = [(i + 1, 1) for i in range(len(MASSES))]
    if FOUNDATIONS is not None:
        for sway, rocking in zip(FOUNDATIONS["sway"], FOUNDATIONS["rocking"]):
            out[rocking] = (sway + 1, 3)
    return out


def tied_floors():
    """floor -> the sway DOF of the foundation it turns with: each floor of a building on
    soil, whose rotation (without mass) carries its foundation's rocking to the storeys'
    twoNodeLinks."""
    tied = {}
    for (lower, upper), f in zip(STORY_NODES, FOUNDATIONS["story_foundation"]):
        if f >= 0:
            sway = FOUNDATIONS["sway"][f]
            tied.update({node: sway for node in (lower, upper) if node != sway})
    return tied


def add_nodes():
    """The nodes with their masses; on soil, floors drawn downwards (node i at -height):
    a vertical twoNodeLink's local y then runs along +x and its shear deformation is
    u_upper - u_lower - h theta, theta the rotation of the foundation's node, as pframe
    has it (docs/soil.md)."""
    if FOUNDATIONS is None:
        ops.model("basic", "-ndm", 1, "-ndf", 1)
        for i, m in enumerate(MASSES):
            ops.node(i + 1, 0.0)
            ops.mass(i + 1, m)
        return
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    rocking = dict(zip(FOUNDATIONS["sway"], FOUNDATIONS["rocking"]))
    tied = tied_floors()
    for i, m in enumerate(MASSES):
        if i in FOUNDATIONS["rocking"]:
            continue
        ops.node(i + 1, 0.0, -FOUNDATIONS["heights"][i])
        ops.mass(i + 1, m, 0.0, MASSES[rocking[i]] if i in rocking else 0.0)
        ops.fix(i + 1, 0, 1, 0 if i in rocking or i in tied else 1)
    for node, sway in sorted(tied.items()):
        ops.equalDOF(sway + 1, node + 1, 3)


def build():
    """Create the model in the OpenSees domain; return storey, contact and link element tags
    (P-delta's in GEOMETRIC)."""
    n = len(MASSES)
    ops.wipe()
    add_nodes()
    # the ground's node, n + 1; on supports, support s's ground is node n + 1 + s
    for s in range(max(len(SUPPORTS), 1)):
        ground_node(n + 1 + s, s, *((0.0,) if FOUNDATIONS is None else (0.0, 0.0)))

    def joined(tag, i, j, *flags, direction=1):
        # zeroLength deformation is u_j - u_i (-1 - s: support s's ground, node n + 1 + s)
        ops.element("zeroLength", tag, n - i if i < 0 else i + 1, n - j if j < 0 else j + 1,
                    "-mat", tag, "-dir", direction, *flags)
        return tag

    stories = []
    on_soil = (FOUNDATIONS or {}).get("story_foundation", [-1] * len(STORY_NODES))
    for j, ((lower, upper), mat, f) in enumerate(zip(STORY_NODES, STORY_MATERIALS, on_soil,
                                                     strict=True)):
        material(j + 1, mat)
        # lower -> upper makes the deformation the drift; without -doRayleigh the element
        # ignores the region's damping factors
        if f < 0:
            stories.append(joined(j + 1, lower, upper, "-doRayleigh", 1))
        else:  # its lower side holds h theta: a twoNodeLink of length h (add_nodes)
            ops.element("twoNodeLink", j + 1, lower + 1, upper + 1, "-mat", j + 1, "-dir", 2,
                        "-doRayleigh")
            stories.append(j + 1)

    if MODAL:
        # every mode of the buildings on their own: before the contacts (and their tangents)
        # join the domain; -fullGenLapack is the solver that gives all of them
        ops.eigen("-fullGenLapack", len(MODAL))
        ops.modalDamping(*MODAL)

    tag = len(stories)
    contacts = []
    for (left, right), gap, mat in zip(CONTACT_NODES, CONTACT_GAPS, CONTACT_MATERIALS,
                                       strict=True):
        tag += 1
        contact_material(tag, mat, gap)
        contacts.append(joined(tag, left, right))  # a wall: the ground's node on its side
    links = []
    for (first, second), mat in zip(LINK_NODES, LINK_MATERIALS, strict=True):
        tag += 1
        material(tag, mat)  # no Rayleigh on links: a dashpot is in its force
        links.append(joined(tag, first, second))
    GEOMETRIC.clear()
    for j, ((lower, upper), kg) in enumerate(zip(STORY_NODES, STORY_GEOMETRIC, strict=True)):
        if kg != 0.0:  # P-delta: the storey resists (P / h) d less, undamped
            tag += 1
            ops.uniaxialMaterial("Elastic", tag, -kg)
            GEOMETRIC.append((j, joined(tag, lower, upper)))
    if FOUNDATIONS is not None:  # the soil's springs and dashpots, to the ground
        for sway, rock_mat, sway_mat, s in zip(
                FOUNDATIONS["sway"], FOUNDATIONS["rocking_materials"],
                FOUNDATIONS["sway_materials"], FOUNDATIONS["grounds"]):
            for mat, direction in ((sway_mat, 1), (rock_mat, 3)):
                tag += 1
                material(tag, mat)
                joined(tag, -1 - s, sway, direction=direction)

    rayleigh(stories)
    if SUPPORTS:
        def dashpot(tag, d):
            node, dof = dof_nodes()[d]
            joined(tag, -1 - DOF_SUPPORT[d], node - 1, direction=dof)

        support_dashpots(tag, dashpot)
        support_motion({s: [n + 1 + s] for s in range(len(SUPPORTS))})
    else:
        moved = sorted({node for node, dof in dof_nodes() if dof == 1})
        ground_motion([(1, AG, moved)])
    return stories, contacts, links


def recorders(stories, contacts, links):
    """name -> (recorder kind, columns, its arguments)."""
    nodes = sorted({node for node, _ in dof_nodes()})
    dofs = (1,) if FOUNDATIONS is None else (1, 3)
    geometric = [tag for _, tag in GEOMETRIC]
    return {
        "displacement": ("Node", len(dofs) * len(nodes), ("-node", *nodes, "-dof", *dofs,
                                                          "disp")),
        "velocity": ("Node", len(dofs) * len(nodes), ("-node", *nodes, "-dof", *dofs, "vel")),
        "story_force": ("Element", len(stories), ("-ele", *stories, "basicForce")),
        "story_drift": ("Element", len(stories), ("-ele", *stories, "basicDeformation")),
        "geometric_force": ("Element", len(geometric), ("-ele", *geometric, "basicForce")),
        "contact_force": ("Element", len(contacts), ("-ele", *contacts, "basicForce")),
        "link_force": ("Element", len(links), ("-ele", *links, "basicForce")),
    }


def finish(result):
    """pframe's conventions: the DOFs in pframe's order, a storey's force with its P-delta
    part, a contact's force positive in compression (the materials are negative in
    compression; 0.0 - x also avoids -0.0)."""
    nodes = sorted({node for node, _ in dof_nodes()})
    dofs = (1,) if FOUNDATIONS is None else (1, 3)
    columns = [len(dofs) * nodes.index(node) + dofs.index(dof) for node, dof in dof_nodes()]
    for name in ("displacement", "velocity"):
        result[name] = result[name][:, columns]
    for k, (j, _) in enumerate(GEOMETRIC):
        result["story_force"][:, j] += result["geometric_force"][:, k]
    del result["geometric_force"]
    result["contact_force"] = 0.0 - result["contact_force"]
    relative(result)
'''

PLAN_BUILD = '''
# The rigid diaphragms are multi-point constraints: Transformation eliminates the tied DOFs
# exactly (Plain takes single-point constraints only).
CONSTRAINTS = "Transformation"
GEOMETRIC = []  # P-delta's elements, one per line of resistance that has one (build() fills it)


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
    grounds = {}  # support -> its ground's nodes

    def end(floor, point):
        key = (floor, *point)
        if key not in ends:
            ends[key] = tag = len(CENTRES) + len(ends) + 1
            if floor < 0:  # the ground (-1 - s: support s's)
                grounds.setdefault(-1 - floor, []).append(ground_node(tag, -1 - floor, *point))
            else:
                ops.node(tag, *point)
                ops.rigidLink("beam", floor + 1, tag)
        return ends[key]

    def element(tag, nodes, points, direction, *flags):
        # local x along the direction: the deformation is n . (u_second - u_first), the
        # force acts along n; ends apart across the direction only draw a length warning.
        # Direction (0, 0): a spring on the floors' rotations (-dir 3, about z).
        nx, ny = direction
        turning = nx == 0.0 and ny == 0.0
        ops.element("zeroLength", tag, *(end(f, p) for f, p in zip(nodes, points)),
                    "-mat", tag, "-dir", 3 if turning else 1,
                    *(() if turning else ("-orient", nx, ny, 0.0, -ny, nx, 0.0)), *flags)
        return tag

    def turned(mat, lever):
        # an elastic spring on r (theta_2 - theta_1) is r^2 k about the rotation
        return mat if lever == 0.0 else ("elastic", mat[1] * lever * lever)

    stories = []
    for j, (nodes, points, direction, mat, lever) in enumerate(zip(
            STORY_NODES, STORY_POINTS, STORY_DIRECTIONS, STORY_MATERIALS, STORY_LEVERS,
            strict=True)):
        material(j + 1, turned(mat, lever))
        # without -doRayleigh a storey ignores its region's stiffness damping
        stories.append(element(j + 1, nodes, points, direction, "-doRayleigh", 1))

    if MODAL:
        # every mode of the buildings on their own: before the contacts (and their tangents)
        # join the domain; -fullGenLapack is the solver that gives all of them
        ops.eigen("-fullGenLapack", len(MODAL))
        ops.modalDamping(*MODAL)

    tag = len(stories)
    contacts = []
    for nodes, points, direction, gap, mat in zip(CONTACT_NODES, CONTACT_POINTS,
                                                  CONTACT_DIRECTIONS, CONTACT_GAPS,
                                                  CONTACT_MATERIALS, strict=True):
        tag += 1
        contact_material(tag, mat, gap)
        contacts.append(element(tag, nodes, points, direction))
    links = []
    for nodes, points, direction, mat, lever in zip(LINK_NODES, LINK_POINTS, LINK_DIRECTIONS,
                                                    LINK_MATERIALS, LINK_LEVERS, strict=True):
        tag += 1
        material(tag, turned(mat, lever))
        links.append(element(tag, nodes, points, direction))
    GEOMETRIC.clear()
    for j, (nodes, points, direction, kg, lever) in enumerate(zip(
            STORY_NODES, STORY_POINTS, STORY_DIRECTIONS, STORY_GEOMETRIC, STORY_LEVERS,
            strict=True)):
        if kg != 0.0:  # P-delta: the line resists (P / h) d less, undamped
            tag += 1
            material(tag, turned(("elastic", -kg), lever))
            GEOMETRIC.append((j, element(tag, nodes, points, direction)))

    rayleigh(stories)
    if SUPPORTS:
        def dashpot(tag, d):  # along the DOF's component, at its floor's centre
            f, component = DOFS[d]
            ops.element("zeroLength", tag, end(-1 - DOF_SUPPORT[d], CENTRES[f]), f + 1,
                        "-mat", tag, "-dir", component + 1)

        support_dashpots(tag, dashpot)
        support_motion(grounds)
    else:
        # each channel loads (and starts accelerated) the floors that move along its axis
        ground_motion([(dof, samples, [f + 1 for f, moves in enumerate(MOVES)
                                       if moves[dof - 1]])
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
    geometric = [tag for _, tag in GEOMETRIC]
    out["geometric_force"] = ("Element", len(geometric), ("-ele", *geometric, "basicForce"))
    return out


def finish(result):
    """pframe's conventions: the degrees of freedom in DOFS' order; a contact's force positive
    in compression and its penetration n . (u_left - u_right) - gap, 0 while the gap is open
    (0.0 - x avoids -0.0)."""
    columns = [3 * f + c for f, c in DOFS]
    for name in ("displacement", "velocity"):
        result[name] = result[name][:, columns]
    for k, (j, _) in enumerate(GEOMETRIC):  # a line's force with its P-delta part
        result["story_force"][:, j] += result["geometric_force"][:, k]
    del result["geometric_force"]
    for kind, deformation, levers in (("story", "story_drift", STORY_LEVERS),
                                      ("link", "link_deformation", LINK_LEVERS)):
        for j, lever in enumerate(levers):  # a rotational spring's moment and turn
            if lever != 0.0:
                result[kind + "_force"][:, j] /= lever
                result[deformation][:, j] *= lever
    result["contact_force"] = 0.0 - result["contact_force"]
    result["contact_penetration"] = np.maximum(
        0.0 - result["contact_penetration"] - np.asarray(CONTACT_GAPS, dtype=float), 0.0)
    relative(result)
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
    ops.algorithm(ALGORITHM)
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
    pulled(result)
    return result


def pulled(result):
    """Say where a contact pulled: pframe's contact laws never do (their force stays at 0
    where OpenSees' Hertzdamp damping outweighs its spring in rebound), so from there on
    this model is not pframe's."""
    for c, name in enumerate(CONTACT_NAMES):
        steps = np.flatnonzero(result["contact_force"][:, c] < 0.0)
        if len(steps):
            print(f"contact {name!r} pulled at t = {float(result['time'][steps[0]])!r} s "
                  f"({len(steps)} steps): pframe's force is 0 there, and the two differ from "
                  "then on", file=sys.stderr)


if __name__ == "__main__":
    for difference in DIFFERENCES:
        print(f"this model is not pframe's: {difference}", file=sys.stderr)
    with tempfile.TemporaryDirectory() as tmp:
        result = simulate(tmp)
    print(f"analyze({STEPS * SUBSTEPS}, {DT / SUBSTEPS!r}): {result['analyze_seconds']:.4f} s")
    if OUT_NPZ is not None:
        np.savez(OUT_NPZ, **result)
'''
