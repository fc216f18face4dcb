"""Scene definitions (pydantic v2): what a YAML file may say, and nothing numerical.

Reading a file into a validated scene is :mod:`pframe.reader` (above this package and the
Pi-form scenes of :mod:`pframe.nondim`).
"""

from typing import TYPE_CHECKING

from pframe.model.expand import Expanded, expand
from pframe.model.scene import QUANTITIES, scene_class

if TYPE_CHECKING:
    from pframe.model.scene import Scene

__all__ = ["QUANTITIES", "Expanded", "Scene", "expand", "scene_class"]


def __getattr__(name: str):
    if name == "Scene":  # built on first use (pframe.model.scene)
        from pframe.model.scene import Scene

        return Scene
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
