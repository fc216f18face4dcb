"""Independent implementations pframe is checked against (OpenSeesPy, in the ``peers`` extra)."""
