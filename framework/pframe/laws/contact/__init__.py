"""Built-in contact laws (compression positive, deformation = penetration)."""
