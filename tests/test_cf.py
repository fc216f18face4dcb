"""Result files pass the CF checkers they claim (``Conventions = "CF-1.8"``): the IOOS
``compliance-checker --test=cf:1.8`` and the CF checker ``cfchecks``, with no errors (and no
warnings), on a solve file, a dimensionless file, a sweep file and a gap audit's file.

cfchecks reads the CF standard-name, area-type and region tables; it downloads them unless
given local copies. The standard-name table comes with compliance-checker; the area-type and
region tables are only looked up for attributes pframe never writes, so minimal tables serve
(the test runs offline).
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from pframe.cli import main

REPO = Path(__file__).resolve().parents[1]
TABLE = """<?xml version="1.0"?>
<{root}><version_number>1</version_number><date>2024-01-01</date><entry id="{entry}"></entry></{root}>
"""


def _tool(name: str) -> str:
    found = shutil.which(name) or str(Path(sys.executable).with_name(name))
    if not Path(found).exists():
        pytest.skip(f"{name} is not installed (pip install -e '.[test]')")
    return found


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("cf")
    out = {"solve": folder / "eq14.nc", "pi": folder / "eq14-pi.nc", "sweep": folder / "sweep.nc",
           "gap": folder / "gap.nc", "risk": folder / "risk.nc"}
    assert main(["solve", str(REPO / "models" / "wu2021-eq14.yaml"), "-o", str(out["solve"]),
                 "-q"]) == 0
    assert main(["solve", str(REPO / "models" / "hust-4x3-pi.yaml"), "-o", str(out["pi"]),
                 "-q"]) == 0
    assert main(["sweep", str(REPO / "models" / "sweeps" / "wu2021-pi-d.yaml"), "-o",
                 str(out["sweep"]), "-q"]) == 0
    assert main(["gap", str(REPO / "models" / "wu2021-pulse.yaml"), "--levels", "0.2,0.4",
                 "--gap", "0.1", "-o", str(out["gap"]), "-q"]) == 0
    from test_risk import pulse_study

    assert main(["risk", str(pulse_study(folder)), "-o", str(out["risk"]), "-q"]) == 0
    return out


@pytest.mark.parametrize("kind", ["solve", "pi", "sweep", "gap", "risk"])
def test_compliance_checker_finds_nothing(files, kind):
    done = subprocess.run([_tool("compliance-checker"), "--test=cf:1.8", "--format=text",
                           str(files[kind])], capture_output=True, text=True, timeout=300)
    report = done.stdout + done.stderr
    assert "possibly indicate compliance checker issues" not in report, report
    assert re.search(r"has 0 potential issues|All tests passed", report), report


@pytest.mark.parametrize("kind", ["solve", "pi", "sweep", "gap", "risk"])
def test_cfchecks_finds_nothing(files, kind, tmp_path):
    checker = _tool("cfchecks")
    probe = subprocess.run([sys.executable, "-c", "import cfunits"], capture_output=True,
                           text=True)
    if probe.returncode != 0:
        pytest.skip("cfchecks needs the UDUNITS-2 library (apt-get install libudunits2-0): "
                    + probe.stderr.strip().splitlines()[-1])
    try:
        import compliance_checker
    except ImportError:
        pytest.skip("compliance-checker (which brings the CF standard-name table) is absent")
    names = Path(compliance_checker.__file__).parent / "data" / "cf-standard-name-table.xml"
    area = tmp_path / "area.xml"
    area.write_text(TABLE.format(root="area_type_table", entry="all_area_types"))
    regions = tmp_path / "regions.xml"
    regions.write_text(TABLE.format(root="standardized_region_list", entry="global"))
    done = subprocess.run([checker, "-s", str(names), "-a", str(area), "-r", str(regions),
                           str(files[kind])], capture_output=True, text=True, timeout=300)
    report = done.stdout + done.stderr
    assert "Traceback" not in report, report
    assert "ERRORS detected: 0" in report and "WARNINGS given: 0" in report, report


@pytest.mark.parametrize("kind", ["solve", "pi", "sweep", "gap", "risk"])
def test_every_text_attribute_is_nc_char(files, kind):
    """Text attributes are fixed-length strings (netCDF's NC_CHAR), which every netCDF
    reader reads (Octave's netcdf package cannot read NC_STRING): checked in the HDF5
    types, and by netCDF-C's ncdump when it is installed (it prints NC_STRING attributes
    with a ``string`` type)."""
    import h5py

    texts = 0
    with h5py.File(files[kind], "r") as f:
        objects = [f]
        f.visititems(lambda _, obj: objects.append(obj) if isinstance(obj, h5py.Dataset)
                     else None)
        for obj in objects:
            for name in obj.attrs:
                kind_of = obj.attrs.get_id(name).get_type()
                if isinstance(kind_of, h5py.h5t.TypeStringID):
                    assert not kind_of.is_variable_str(), f"{obj.name}: {name} is NC_STRING"
                    texts += 1
    assert texts > 20  # units, long_name, title, status, history, ...
    ncdump = shutil.which("ncdump")
    if ncdump is None:
        pytest.skip("ncdump is not installed (apt-get install netcdf-bin): HDF5 types checked")
    done = subprocess.run([ncdump, "-h", str(files[kind])], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    header = done.stdout
    assert ":Conventions = \"CF-1.8\" ;" in header and ":units = " in header
    assert not re.search(r"^\s*string \S*:", header, re.MULTILINE), header
