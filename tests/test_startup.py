"""What a ``pframe solve`` of a plain scene imports: the modules of the laws it names and not those of
every law, nor what only another kind of scene needs (a stochastic motion's generator, numpy's
masked arrays). Each was a few ms of every short ``pframe solve`` (benchmarks/opensees_speed.py)."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

from pframe.laws.registry import builtin_names

SCENE = Path(__file__).parents[1] / "models" / "wu2021-eq14-linear.yaml"


@pytest.fixture(scope="module")
def imported(tmp_path_factory) -> tuple[set, list, int, list]:
    """The modules a ``pframe solve`` of the paper's linear scene (bilinear storeys, linear
    contacts, a sine) holds at its end, the contact laws it lists then, how many of
    tokenize's patterns it compiled, and which of the scene's optional models have their
    validators built."""
    out = tmp_path_factory.mktemp("startup") / "out.nc"
    code = ("import sys\n"
            "from pframe.cli import main\n"
            f"assert main(['solve', {str(SCENE)!r}, '-o', {str(out)!r}, '-q']) == 0\n"
            "from pframe.laws.registry import available_names\n"
            "print(sorted(sys.modules))\n"
            "print(available_names('contact'))\n"
            "import tokenize\n"
            "print(tokenize._compile.cache_info().currsize)\n"
            "from pframe.model.plan import FloorPlan\n"
            "from pframe.model.scene import (InitialConditions, Node, Output, OutputScales,\n"
            "                                SiteColumn, Support)\n"
            "print([m.__name__ for m in (Node, Support, SiteColumn, FloorPlan, OutputScales,\n"
            "                            InitialConditions, Output) if m.__pydantic_complete__])\n")
    lines = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           check=True).stdout.splitlines()
    return (set(ast.literal_eval(lines[0])), ast.literal_eval(lines[1]), int(lines[2]),
            ast.literal_eval(lines[3]))


@pytest.mark.slow
def test_a_run_loads_the_modules_of_its_own_laws_only(imported):
    modules, listed, _, _ = imported
    laws = {m.split(".", 2)[2] for m in modules
            if m.startswith(("pframe.laws.contact.", "pframe.laws.material."))}
    # the soil's springs (kelvin_voigt, which imports viscous) are looked up for a scene on
    # soil only
    assert laws == {"contact.linear", "material.bilinear"}
    assert listed == builtin_names("contact")  # every law still listed


#: module a plain run (a sine, SI, no soil, limits, P-delta or damage index) leaves out ->
#: what loads it instead
LEFT_OUT = {
    "pframe.excitation.stochastic": "a stochastic motion's generator",
    "numpy.ma": "masked arrays (the stochastic generator's)",
    "pframe.excitation.records": "a record's parsers and their patterns",
    "pframe.model.scene_motions": "the models of records, pulses, stochastic and combined "
                                  "motions (a third of the scene's fields)",
    "pframe.model.scene_options": "the models of soil, a foundation, limits and a Park-Ang "
                                  "index (model.tagged.lazy_model fields)",
    "pframe.model.soil": "the soil's cone model",
    "pframe.laws.material.elastic": "the elastic law of P-delta in plan",
    "pframe.limits": "the drift and acceleration limits of ASCE 7",
    "pframe.nondim.scene_variables": "the listing of every governing variable (pframe pi)",
    "pframe.nondim.buckingham": "the Buckingham machinery of pframe pi",
    "pframe.nondim.dimensions": "the parser of units (a file in another unit system)",
}


@pytest.mark.slow
@pytest.mark.parametrize("module", sorted(LEFT_OUT))
def test_a_plain_run_leaves_out_what_other_scenes_need(imported, module):
    modules, _, _, _ = imported
    assert module not in modules, f"{module}: {LEFT_OUT[module]}"


@pytest.mark.slow
def test_a_run_parses_no_text_signature(imported):
    """Pydantic reads each default factory's signature; a builtin's is text that tokenize
    parses, compiling its patterns (about 2 ms): the Scene's defaults are plain functions."""
    assert imported[2] == 0


@pytest.mark.slow
def test_a_run_finds_its_reference_scales_in_nondim_reference(imported):
    """A result file's reference scales come from nondim.reference (the variable listing is
    left out: LEFT_OUT)."""
    assert "pframe.nondim.reference" in imported[0]


@pytest.mark.slow
def test_a_scene_without_nodes_supports_or_plans_builds_none_of_their_validators(imported):
    """Generic nodes, supports (and their soil columns), a floor plan, output scales, initial
    conditions and output units are validated by their models' validators, built at a
    field's first value (lazy_model), not with every scene's; the defaults of the last two
    are made without them."""
    assert imported[3] == []


@pytest.mark.slow
def test_a_run_loads_the_module_of_its_own_integrator_only(imported):
    """The kernel's schemes are listed from pframe.integrators.SCHEME and the scene's
    integrator union makes a model when a scene names it: the other five integrators'
    modules are not imported."""
    modules, _, _, _ = imported
    loaded = {m.rsplit(".", 1)[1] for m in modules if m.startswith("pframe.integrators.")}
    assert loaded == {"_base", "coefficients", "tableau", "newmark"}


@pytest.mark.slow
def test_the_pframe_command_imports_no_package_metadata(tmp_path):
    """Package metadata (importlib.metadata, with the email package that parses it, about
    15 ms) is read by neither pydantic's plug-in loader, left out while
    PYDANTIC_DISABLE_PLUGINS is ``__all__`` (what a short command sets), nor the file's
    provenance, which reads numba's version from its .dist-info as importlib.metadata would:
    the file states the same version. Nor is tempfile, imported where a folder is made (a
    sweep without an output, the records of a loaded result, the plug-in laws' cache)."""
    out = tmp_path / "out.nc"
    code = ("import sys\n"
            "from pframe.cli import console_main\n"
            f"sys.argv = ['pframe', 'solve', {str(SCENE)!r}, '-o', {str(out)!r}, '-q']\n"
            "assert console_main() == 0\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('email', 'tempfile')\n"
            "             or m.startswith('importlib.metadata')))\n"
            "from pydantic.plugin._loader import PYDANTIC_ENTRY_POINT_GROUP, get_plugins\n"
            "print(list(get_plugins()), PYDANTIC_ENTRY_POINT_GROUP)\n")
    lines = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           check=True, env={**os.environ, "PYDANTIC_DISABLE_PLUGINS": "__all__"}
                           ).stdout.splitlines()
    assert lines[0] == "[]"
    assert lines[1] == "[] pydantic"  # the loader's other names: the real module's
    from importlib.metadata import version

    import h5py

    with h5py.File(out, "r") as f:
        software = f.attrs["software"]
    software = software.decode() if isinstance(software, bytes) else software
    assert f"numba {version('numba')};" in software


@pytest.mark.parametrize("name", ["numba", "numpy", "PyYAML", "typing-extensions",
                                  "pydantic_core", "pframe", "no-such-distribution"])
def test_installed_version_is_importlib_metadata_s(name):
    from importlib.metadata import PackageNotFoundError, version

    from pframe.record.netcdf import installed_version

    try:
        expected = version(name)
    except PackageNotFoundError:
        expected = "not installed"
    assert installed_version(name) == expected
