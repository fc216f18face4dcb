"""Scene definitions (pydantic v2): what a YAML file may say, and nothing numerical."""

from pframe.model.expand import Expanded, expand
from pframe.model.load import load_scene, parse_scene
from pframe.model.scene import QUANTITIES, Scene, scene_class

__all__ = ["QUANTITIES", "Expanded", "Scene", "expand", "load_scene", "parse_scene", "scene_class"]
