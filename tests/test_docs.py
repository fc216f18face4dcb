"""The documentation cannot rot.

- ``docs/yaml-reference.md`` equals what ``docs/yaml_reference.py`` (``yaml_reference_markdown``)
  renders from the scene model today;
- every ``yaml`` block in ``docs/*.md`` is valid YAML, and every one that is a scene (it has an
  ``analysis`` key) passes ``pframe.reader.parse_scene``;
- the plug-in package of ``docs/contact-laws.md`` is rebuilt from the page (each file is a code
  block whose first line is ``# <path>``), made visible through a real entry point, and its
  example scene runs and rebounds with the restitution the page promises.
"""

from __future__ import annotations

import importlib
import re
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import record_file

from pframe.errors import InputError
from pframe.reader import parse_scene

DOCS = Path(__file__).resolve().parents[1] / "docs"
sys.path.insert(0, str(DOCS))  # docs/yaml_reference.py: a script of the docs, not of pframe
from yaml_reference import REGENERATE, yaml_reference_markdown  # noqa: E402

CONTACT_LAWS = DOCS / "contact-laws.md"
FENCE = re.compile(r"^```([\w-]*)[^\n]*\n(.*?)^```[ \t]*$", re.M | re.S)
FILE_HEADER = re.compile(r"#\s*([\w./-]+\.(?:py|toml))\s*$")


def _blocks(language: str, pages=None) -> list[tuple[str, int, str]]:
    """(page name, line of the block's first line, text) of every fenced block in a language."""
    out = []
    for page in pages or sorted(DOCS.glob("*.md")):
        text = page.read_text(encoding="utf-8")
        for match in FENCE.finditer(text):
            if match.group(1) == language:
                line = text.count("\n", 0, match.start(2)) + 1
                out.append((page.name, line, match.group(2)))
    return out


def _is_scene(text: str) -> bool:
    data = yaml.safe_load(text)
    return isinstance(data, dict) and "analysis" in data


YAML_BLOCKS = _blocks("yaml")
SCENE_BLOCKS = [b for b in YAML_BLOCKS if _is_scene(b[2])]


def _id(block) -> str:
    return f"{block[0]}:{block[1]}"


def test_yaml_reference_is_current():
    page = DOCS / "yaml-reference.md"
    assert page.exists(), f"docs/yaml-reference.md is missing; write it with:\n{REGENERATE}"
    expected = yaml_reference_markdown()
    assert page.read_text(encoding="utf-8") == expected, (
        f"docs/yaml-reference.md is stale; regenerate it with:\n{REGENERATE}")


def test_every_built_in_law_has_its_section_in_the_docs():
    """docs/theory.md describes every built-in law (architecture.md's recipe, step 3): a
    contact law by its row in the table of ``## Contact laws``, a material by its paragraph
    (``**name**``) under ``## Storey materials`` or, a link's material, by its row in
    docs/links-and-walls.md; the test names each one missing."""
    from pframe.laws.registry import builtin_laws

    theory = (DOCS / "theory.md").read_text(encoding="utf-8")
    contacts = theory[theory.index("## Contact laws"):theory.index("\n## ", theory.index(
        "## Contact laws") + 1)]
    materials = theory[theory.index("## Storey materials"):theory.index("## Contact laws")]
    links = (DOCS / "links-and-walls.md").read_text(encoding="utf-8")
    missing = [f"contact law {law.name} (a row | `{law.name}` | of the table of ## Contact "
               "laws in docs/theory.md)" for law in builtin_laws("contact")
               if f"| `{law.name}` |" not in contacts]
    missing += [f"material {law.name} (a paragraph **{law.name}** under ## Storey materials "
                "in docs/theory.md, or a row of the link materials in docs/links-and-walls.md)"
                for law in builtin_laws("material")
                if f"**{law.name}**" not in materials and f"| `{law.name}` |" not in links]
    assert not missing, "undocumented built-in laws: " + "; ".join(missing)


def test_the_docs_hold_scenes():
    """Guard against a fence pattern that silently finds nothing."""
    pages = {name for name, _, _ in SCENE_BLOCKS}
    assert {"getting-started.md", "contact-laws.md"} <= pages


@pytest.mark.parametrize("block", YAML_BLOCKS, ids=_id)
def test_yaml_blocks_are_yaml(block):
    yaml.safe_load(block[2])


# ---------------------------------------------------------------------------------------------
# the plug-in example of docs/contact-laws.md
# ---------------------------------------------------------------------------------------------

def _example_files() -> dict[str, str]:
    """Relative path -> text of every block of contact-laws.md that starts with '# <path>'."""
    files = {}
    for language in ("python", "toml"):
        for _, _, text in _blocks(language, [CONTACT_LAWS]):
            first, _, _ = text.partition("\n")
            match = FILE_HEADER.fullmatch(first.strip())
            if match:
                files[match.group(1)] = text
    return files


@pytest.fixture(scope="module")
def example_plugin(tmp_path_factory):
    """The example package of contact-laws.md on sys.path, with installed-package metadata
    (a .dist-info folder holding its entry points), as `pip install` would leave it."""
    tomllib = pytest.importorskip("tomllib")
    files = _example_files()
    assert "pyproject.toml" in files, "contact-laws.md lost its '# pyproject.toml' block"
    root = tmp_path_factory.mktemp("example_plugin")
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    project = tomllib.loads(files["pyproject.toml"])["project"]
    groups = project["entry-points"]
    dist = root / f"{project['name'].replace('-', '_')}-{project['version']}.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {project['name']}\nVersion: {project['version']}\n",
        encoding="utf-8")
    (dist / "entry_points.txt").write_text("".join(
        f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in entries.items()) + "\n"
        for group, entries in groups.items()), encoding="utf-8")
    packages = {name.split("/")[0] for name in files if "/" in name}
    with pytest.MonkeyPatch.context() as mp:
        mp.syspath_prepend(str(root))
        importlib.invalidate_caches()
        try:
            yield groups
        finally:
            from pframe.laws import registry

            for group, entries in groups.items():
                kind = {registry.CONTACT_GROUP: "contact",
                        registry.MATERIAL_GROUP: "material"}.get(group)
                for law in entries:
                    if kind is not None and law not in registry.builtin_names(kind):
                        registry._registered[kind].pop(law, None)
            for module in list(sys.modules):
                if module.split(".")[0] in packages:
                    del sys.modules[module]


@pytest.mark.parametrize("block", SCENE_BLOCKS, ids=_id)
def test_scene_blocks_validate(block, example_plugin, tmp_path):
    """Every scene of the docs validates; a record it names is read from the shared records,
    placed where the scene's relative path looks for it (skipped when they are absent)."""
    page, line, text = block
    excitation = (yaml.safe_load(text) or {}).get("excitation") or {}
    base_dir = DOCS
    if excitation.get("kind") == "record" and not (DOCS / excitation["file"]).is_file():
        record = record_file(Path(excitation["file"]).name)
        base_dir = tmp_path / "scene"
        place = base_dir / excitation["file"]
        place.parent.mkdir(parents=True, exist_ok=True)
        place.symlink_to(record)
    parse_scene(text, source=f"docs/{page}, block at line {line}", base_dir=base_dir)


def test_example_plugin_rebounds_with_its_restitution(example_plugin):
    """The impact scene of contact-laws.md with the example law: the two floors separate with
    exactly the restitution asked for (the point of the exact chi), not the ~0.38 of the
    published improved-Kelvin formula for e = 0.4."""
    from pframe.assemble import assemble
    from pframe.kernel import simulate

    law = next(iter(example_plugin["pframe.contact_laws"]))
    blocks = [b for b in SCENE_BLOCKS if b[0] == CONTACT_LAWS.name and f"law: {law}" in b[2]]
    assert len(blocks) == 1, f"expected one scene of contact-laws.md using law {law!r}"
    text = blocks[0][2]
    scene = yaml.safe_load(text)
    target = scene["contacts"][0]["restitution"]
    left, right = scene["contacts"][0]["nodes"]

    plan = assemble(parse_scene(text, base_dir=DOCS).expanded)
    result = simulate(plan)
    assert result.completed(0), result.describe_failure(0)
    assert result.impacts[0].tolist() == [1]
    velocity = result.history["velocity"][0]
    v_left = velocity[:, plan.node_dof[plan.node_names.index(left)]]
    v_right = velocity[:, plan.node_dof[plan.node_names.index(right)]]
    assert result.history["contact_force"][0][-1, 0] == 0.0  # the floors have separated
    assert np.min(result.history["contact_force"][0]) >= 0.0
    restitution = -(v_left[-1] - v_right[-1]) / (v_left[0] - v_right[0])
    assert restitution == pytest.approx(target, abs=1e-5)


def test_theory_rayleigh_coefficients_are_the_codes():
    """docs/theory.md states the paper example's Rayleigh coefficients per building; they are
    the ones the assembly computes (a0 on the masses, a1 on the storeys)."""
    from pframe.assemble import assemble
    from pframe.reader import load_scene

    text = (DOCS / "theory.md").read_text(encoding="utf-8")
    stated = re.search(r"`a0 = ([\d.]+) 1/s`, `a1 = ([\d.e-]+) s` for the left building\s+"
                       r"\(A\) and `a0 = ([\d.]+) 1/s`, `a1 = ([\d.e-]+) s` for the right one "
                       r"\(B\)", text)
    assert stated, "the sentence with the Rayleigh coefficients changed"
    plan = assemble(load_scene(DOCS.parent / "models" / "wu2021-eq14.yaml").expanded)
    for building, (a0, a1) in zip("AB", (stated.groups()[:2], stated.groups()[2:])):
        node = plan.node_names.index(f"{building}/1")
        dof = plan.node_dof[node]
        assert float(a0) == pytest.approx(plan.mass_damping[0, dof] / plan.mass[0, dof],
                                          abs=5e-5)
        story = plan.story_names.index(f"{building}/1")
        assert float(a1) == pytest.approx(plan.story_beta[0, story], abs=5e-8)


#: the system command each test looks up (shutil.which) and the Debian package that has it
COMMANDS = {"node": "nodejs", "ncdump": "netcdf-bin", "chromium": "chromium", "cc": "gcc",
            "gcc": "gcc", "check-jsonschema": None, "mount": None}  # None: pip's, or the base


def test_readme_names_every_system_package_the_tests_use_as_ci_installs_them():
    """A fresh machine that follows the README skips no test it could run: its apt-get line
    names the packages .ci/run installs, and every command a test looks up on the PATH
    comes from one of them (or from pip or the base system, as COMMANDS says)."""
    repo = DOCS.parent
    readme = (repo / "README.md").read_text(encoding="utf-8")
    line = re.search(r"^apt-get install -y ([^\n`]+)$", readme, re.M)
    assert line, "README.md has no 'apt-get install -y ...' line"
    named = line.group(1).split()
    ci = re.search(r'^SYSTEM_PACKAGES="([^"]+)"', (repo / ".ci" / "run").read_text(), re.M)
    assert ci and ci.group(1).split() == named, (named, ci and ci.group(1))
    looked_up = set()
    for path in sorted((repo / "tests").glob("*.py")):
        text = path.read_text(encoding="utf-8")
        looked_up |= set(re.findall(r"""shutil\.which\(["']([\w.-]+)["']\)""", text))
        # a loop over the names a program has (chromium, chromium-browser, ...)
        for names in re.findall(r"for name in \(([^)]*)\):\s*\n\s*found = shutil\.which", text):
            looked_up.add(re.findall(r'"([\w.-]+)"', names)[0])
    unknown = looked_up - set(COMMANDS)
    assert not unknown, f"tests look up {sorted(unknown)}: add them to COMMANDS and README"
    for command in looked_up:
        assert COMMANDS[command] is None or COMMANDS[command] in named, command
    assert "npm install --prefix .venv/node ajv@8" in readme
    assert ".venv/pelicun/bin/pip install pelicun" in readme


def test_example_plugin_without_a_dimension_is_refused_in_another_unit_system(example_plugin):
    """The example law leaves its stiffness's dimension out (N/m^n depends on n): in SI it
    runs; in kN-m-t it is refused naming the field, never read as SI (docs/units.md)."""
    law = next(iter(example_plugin["pframe.contact_laws"]))
    text = next(b[2] for b in SCENE_BLOCKS
                if b[0] == CONTACT_LAWS.name and f"law: {law}" in b[2])
    parse_scene(text, base_dir=DOCS)
    with pytest.raises(InputError) as caught:
        parse_scene("units: kN-m-t\n" + text, source="scene.yaml", base_dir=DOCS)
    message = str(caught.value)
    assert "contacts[0].stiffness: cannot convert this value from kN-m-t to SI" in message
    assert f"field 'stiffness' of contact law '{law}'" in message
