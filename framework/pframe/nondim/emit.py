"""Writing a scene (YAML data) back as YAML text, with a schema line and a header."""

from __future__ import annotations

import yaml

SCHEMA_LINE = "# yaml-language-server: $schema="


def dump_scene(data: dict, header: list[str], schema: str) -> str:
    """YAML text of ``data``: the ``$schema`` line, ``#`` header lines, then the scene.

    Floats are written with ``repr`` (PyYAML's default), so every number reads back exactly;
    mappings and lists of plain values are written inline, as in the shipped models.
    """
    body = yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=100,
                          allow_unicode=True)
    lines = [f"{SCHEMA_LINE}{schema}", "#"] + [f"# {line}".rstrip() for line in header]
    return "\n".join(lines) + "\n" + body
