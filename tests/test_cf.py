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

import numpy as np
import pytest

from pframe.cli import main
from pframe.kernel.state import ENERGY_TERMS

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
    # floor-to-column contacts (their struck points, the column shear of each impact), under
    # a sine rather than the example's record
    import yaml

    scene = yaml.safe_load((REPO / "models" / "floor-to-column.yaml").read_text())
    scene["excitation"] = {"kind": "sine", "amplitude": 4.0, "frequency": 9.0}
    scene["analysis"]["duration"] = 3.0
    (folder / "column.yaml").write_text(yaml.safe_dump(scene))
    out["column"] = folder / "column.nc"
    assert main(["solve", str(folder / "column.yaml"), "-o", str(out["column"]), "-q"]) == 0
    # a file in another unit system (docs/units.md): kip, in, kip in, in/s^2
    scene = yaml.safe_load((REPO / "models" / "mid-rise-pair-kN-m-t.yaml").read_text())
    scene["units"] = "kip-in-s"
    scene["excitation"] = {"kind": "sine", "amplitude": 100.0, "frequency": 9.0}
    scene["analysis"]["duration"] = 2.0
    (folder / "kip.yaml").write_text(yaml.safe_dump(scene))
    out["kip"] = folder / "kip.nc"
    assert main(["solve", str(folder / "kip.yaml"), "-o", str(out["kip"]), "-q"]) == 0
    return out


KINDS = ["solve", "pi", "sweep", "gap", "risk", "column", "kip"]
HEADER = "IOOS Compliance Checker Report"


@pytest.fixture(scope="module")
def compliance_reports(files) -> dict[str, str]:
    """The IOOS compliance checker's CF 1.8 report on each file, from one run over all of them
    (it prints one report per file, in the order given; a run costs seconds of imports)."""
    done = subprocess.run([_tool("compliance-checker"), "--test=cf:1.8", "--format=text",
                           *(str(files[kind]) for kind in KINDS)], capture_output=True,
                          text=True, timeout=600)
    output = done.stdout + done.stderr
    reports = output.split(HEADER)[1:]
    assert len(reports) == len(KINDS), output
    assert "Traceback" not in output, output
    return dict(zip(KINDS, reports))


@pytest.mark.slow
@pytest.mark.parametrize("kind", KINDS)
def test_compliance_checker_finds_nothing(compliance_reports, kind):
    report = compliance_reports[kind]
    assert "possibly indicate compliance checker issues" not in report, report
    assert re.search(r"has 0 potential issues|All tests passed", report), report


@pytest.mark.slow
@pytest.mark.parametrize("kind", KINDS)
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


@pytest.mark.slow
@pytest.mark.parametrize("kind", KINDS)
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


# -- units of numeric attributes --------------------------------------------------------------


def _global_attributes(path: Path) -> dict:
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf", decode_times=False) as ds:
        return dict(ds.attrs)


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["solve", "pi", "sweep", "gap"])
def test_every_numeric_attribute_with_a_unit_names_it(files, kind):
    """CF has no units for attributes: each float attribute has ``<name>_units`` beside it
    (docs/netcdf.md), a unit UDUNITS parses; counts and flags (integers) have none."""
    cf_units = pytest.importorskip("cf_units", reason="cf_units (with compliance-checker, "
                                   "the test extra) parses the units")
    attrs = _global_attributes(files[kind])
    floats = [k for k, v in attrs.items() if not isinstance(v, str)
              and np.asarray(v).dtype.kind == "f"]
    assert floats
    for name in floats:
        unit = attrs.get(f"{name}_units")
        assert isinstance(unit, str), f"{kind}: {name} has no {name}_units"
        cf_units.Unit(unit)  # raises on a unit UDUNITS does not know
    for name, value in attrs.items():
        if not isinstance(value, str) and np.asarray(value).dtype.kind in "iu":
            assert f"{name}_units" not in attrs, name
    if "dt" in attrs:
        assert attrs["dt_units"] == "s"


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["solve", "pi"])
def test_attribute_units_agree_with_the_physics(files, kind):
    """The units are the right ones, not just units: the PGA in its unit converts to the
    PGA in g's unit; l_e = a_p / w_p^2 holds through the units of the three scales; the
    energies are J in an SI file and 1 in a dimensionless one."""
    cf_units = pytest.importorskip("cf_units", reason="cf_units parses the units")
    attrs = _global_attributes(files[kind])

    def value_in(name, unit):
        return cf_units.Unit(attrs[f"{name}_units"]).convert(float(attrs[name]),
                                                             cf_units.Unit(unit))

    assert value_in("excitation_pga", attrs["excitation_pga_g_units"]) == pytest.approx(
        float(attrs["excitation_pga_g"]), rel=1e-12)
    prefix = "reference" if kind == "solve" else "scale"
    a = cf_units.Unit(attrs[f"{prefix}_a_p_units"])
    w = cf_units.Unit(attrs[f"{prefix}_w_p_units"])
    l_e = float(attrs[f"{prefix}_a_p"]) / float(attrs[f"{prefix}_w_p"]) ** 2
    assert (a / w**2).convert(l_e, cf_units.Unit(attrs[f"{prefix}_l_e_units"])) == \
        pytest.approx(float(attrs[f"{prefix}_l_e"]), rel=1e-12)
    energies = {k: v for k, v in attrs.items() if k.startswith("energy_") and k.endswith("_units")
                and k != "energy_balance_error_units"}
    assert len(energies) == len(ENERGY_TERMS)
    assert set(energies.values()) == {"J" if kind == "solve" else "1"}


# -- a second independent reader: netCDF-C (netCDF4-python, ncdump) -------------------------


def _same(a, b) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype.kind in "OUS" or b.dtype.kind in "OUS":
        return a.shape == b.shape and all(str(x) == str(y) for x, y in zip(a.ravel(), b.ravel()))
    return a.shape == b.shape and np.array_equal(a, b, equal_nan=True)


@pytest.mark.parametrize("kind", ["solve", "pi", "sweep", "gap"])
def test_netcdf_c_reads_what_xarray_reads(files, kind):
    """netCDF4-python (netCDF-C underneath, nothing of h5py or h5netcdf) reads every
    attribute, text or number, of the file and of each variable, and every variable's values
    (names from their character arrays included), and agrees with xarray."""
    netCDF4 = pytest.importorskip("netCDF4", reason="netCDF4-python is in the test extra")
    import xarray as xr

    with netCDF4.Dataset(files[kind]) as nc, xr.open_dataset(
            files[kind], engine="h5netcdf", decode_times=False, mask_and_scale=False) as ds:
        nc.set_auto_maskandscale(False)
        names = nc.ncattrs()
        assert names == list(ds.attrs), "the same attributes, in the same order"
        texts = 0
        for name in names:
            value = nc.getncattr(name)
            texts += isinstance(value, str)
            assert _same(value, ds.attrs[name]), (name, value, ds.attrs[name])
        assert set(nc.variables) >= set(ds.variables)
        for name in ds.variables:
            var = nc.variables[name]
            for attr in var.ncattrs():
                if attr in ("_Encoding", "coordinates", "_FillValue"):
                    continue  # xarray turns these into encoding and coordinates
                texts += isinstance(var.getncattr(attr), str)
                assert _same(var.getncattr(attr), ds[name].attrs[attr]), (name, attr)
            assert _same(var[...], ds[name].values), name
        assert texts > 20


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["solve", "pi", "sweep", "gap"])
def test_ncdump_prints_every_attribute(files, kind):
    """netCDF-C's ncdump prints every global attribute with the value xarray reads: numbers
    equal, one-line texts equal, and the names along each named dimension."""
    ncdump = shutil.which("ncdump")
    if ncdump is None:
        pytest.skip("ncdump is not installed (apt-get install netcdf-bin)")
    done = subprocess.run([ncdump, "-h", str(files[kind])], capture_output=True, text=True,
                          timeout=60)
    assert done.returncode == 0, done.stderr
    header = done.stdout
    attrs = _global_attributes(files[kind])
    for name, value in attrs.items():
        found = re.search(rf"^\t\t:{re.escape(name)} = (.*?) ;$", header, re.M | re.S)
        assert found, f"ncdump does not print {name}"
        printed = found.group(1)
        if isinstance(value, str):
            if value and "\n" not in value and '"' not in value and "\\" not in value:
                assert printed == f'"{value}"', name
        else:
            assert float(re.sub(r"(LL|b|s|f)$", "", printed)) == pytest.approx(
                float(np.asarray(value).item()), rel=1e-14), name
    labels = [v for v in ("node_name", "contact_name", "building_name") if f"\t{v}(" in header
              or f" {v}(" in header]
    assert labels
    import xarray as xr

    with xr.open_dataset(files[kind], engine="h5netcdf") as ds:
        for label in labels:
            done = subprocess.run([ncdump, "-v", label, str(files[kind])], capture_output=True,
                                  text=True, timeout=60)
            data = done.stdout.split("data:", 1)[1]
            for text in ds[label].values:
                assert f'"{text}"' in data, (label, text)


@pytest.mark.parametrize("kind, names", [
    ("gap", ("level", "intensity", "fragility_median", "fragility_median_any")),
    ("risk", ("level", "intensity", "fragility_median", "fragility_median_low",
              "peak_floor_acceleration", "intensity_at_target", "hazard_im"))])
def test_intensities_are_accelerations_not_grams(files, kind, names):
    """An intensity or acceleration "in g" is written as one standard gravity in UDUNITS'
    terms: UDUNITS (and every reader converting with it) reads the unit ``g`` as the gram."""
    cf_units = pytest.importorskip("cf_units", reason="cf_units parses the units")
    import xarray as xr

    with xr.open_dataset(files[kind], engine="h5netcdf") as ds:
        for name in names:
            unit = cf_units.Unit(ds[name].attrs["units"])
            assert unit.convert(1.0, cf_units.Unit("m/s^2")) == pytest.approx(9.80665), name
        for var in ds.variables.values():  # and every unit of the file parses
            if "units" in var.attrs:
                cf_units.Unit(var.attrs["units"])
