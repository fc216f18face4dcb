"""Material and contact laws: one small module each, registered by name.

Built-in laws are listed in :data:`BUILTIN_CONTACT_LAWS` / :data:`BUILTIN_MATERIALS`;
third-party laws arrive through the entry-point groups ``pframe.contact_laws`` and
``pframe.materials`` and are loaded only when a scene names them.
"""

from pframe.laws.registry import (
    CONTACT_GROUP,
    MATERIAL_GROUP,
    ContactContext,
    HertzContact,
    Law,
    SpringContact,
    StoreyContext,
    all_contact_laws,
    all_materials,
    available_names,
    contact_law,
    get_law,
    material,
)

__all__ = [
    "CONTACT_GROUP",
    "MATERIAL_GROUP",
    "ContactContext",
    "HertzContact",
    "Law",
    "SpringContact",
    "StoreyContext",
    "all_contact_laws",
    "all_materials",
    "available_names",
    "contact_law",
    "get_law",
    "material",
]
