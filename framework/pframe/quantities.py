"""The quantities a recorder can ask for: dimension, units and meaning (pure data)."""

#: name -> (dimension it runs along besides time, units, long name)
QUANTITIES = {
    "displacement": ("node", "m", "floor displacement relative to the ground"),
    "velocity": ("node", "m/s", "floor velocity relative to the ground"),
    "acceleration": ("node", "m/s^2", "floor acceleration relative to the ground"),
    "story_drift": ("story", "m", "storey drift (upper minus lower floor displacement)"),
    "story_force": ("story", "N", "storey shear force of the material (damping excluded; with "
                    "P-delta, net of P drift / h)"),
    "contact_force": ("contact", "N", "contact force, compression positive"),
    "contact_penetration": ("contact", "m", "contact penetration (0 while the gap is open)"),
    "ground_acceleration": (None, "m/s^2", "ground acceleration"),
    "story_drift_ratio": ("story", "1", "storey drift ratio (drift over storey height)"),
    "link_deformation": ("link", "m", "link deformation (second minus first node displacement)"),
    "link_force": ("link", "N", "link force, tension positive (the material's force at the "
                   "link's deformation and rate)"),
    "foundation_sway": ("foundation", "m", "sway of a foundation on soil relative to the "
                        "ground"),
    "foundation_rocking": ("foundation", "rad", "rocking rotation of a foundation on soil "
                           "(positive: the top moves the positive way)"),
    "absolute_acceleration": ("node", "m/s^2", "floor absolute acceleration (relative "
                              "acceleration plus ground acceleration)"),
    "point_displacement": ("point", "m", "displacement of a named plan point of a floor (a "
                           "corner) relative to the ground, along its building's x and y "
                           "axes"),
    "point_drift": ("point", "m", "storey drift at a named plan point: the floor's point less "
                    "the same plan point of the floor below, along its building's x and y "
                    "axes"),
    "ground_displacement": (None, "m", "ground displacement (a record's displacement file, "
                            "or the acceleration integrated twice by the trapezoid rule from "
                            "rest)"),
    "contact_ground_displacement": ("contact", "m", "ground displacements' part of a "
                                    "contact's closing: the left side's support's less the "
                                    "right side's, along the normal (0 on one support)"),
}
