"""Built-in storey materials (force-drift laws of shear springs)."""
