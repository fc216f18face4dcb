"""docs/validation.md cannot drift from the code: every number it prints is computed here.

The page holds tables between ``<!-- BEGIN <name> -->`` and ``<!-- END <name> -->`` markers;
:func:`validation_tables` recomputes each of them from the Pi-form models
(models/wu2021-eq14-pi.yaml, section 3 of Wu et al. 2021; models/hust-4x3-pi.yaml, section
4.4), and the test fails when the page differs. After a deliberate change, rewrite the tables
with::

    python tests/test_validation_doc.py

The prose around the tables states what the paper reports and what pframe finds; the
``test_*_claims`` tests assert those statements, so the prose cannot drift either.
"""

from __future__ import annotations

import json
import re
import sys
from functools import cache
from pathlib import Path

import h5py
import numpy as np
import pytest
import xarray as xr
import yaml

REPO = Path(__file__).resolve().parents[1]
PAGE = REPO / "docs" / "validation.md"
EQ14 = REPO / "models" / "wu2021-eq14-pi.yaml"
HUST = REPO / "models" / "hust-4x3-pi.yaml"
BLOCK = re.compile(r"(<!-- BEGIN (?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- END (?P=name) -->)",
                   re.S)
REGENERATE = "python tests/test_validation_doc.py"


# ---------------------------------------------------------------------------------------------
# runs (dimensionless result files, read back as a user would)
# ---------------------------------------------------------------------------------------------

def _variant(path: Path, law: str | None = None, keep_tension: bool = False,
             pounding: bool = True, stiffness: str | None = None) -> str:
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    if stiffness is not None:  # the Rayleigh damping's stiffness (eq. 5b reading)
        data.setdefault("damping", {})["stiffness"] = stiffness
    if law is not None:
        data["contacts"]["law"] = law
    if keep_tension:
        data["contacts"]["keep_tension"] = True
    if not pounding:
        data["contacts"]["floors"] = []
        for key in ("Pi_wcon", "Pi_e", "Pi_d"):
            data["pi"].pop(key)
    return json.dumps(data)


@cache
def _run(model: str, law: str | None = None, keep_tension: bool = False,
         pounding: bool = True, stiffness: str | None = None) -> dict:
    """Solve a variant of a Pi-form model; {variable: array} of its dimensionless file."""
    import tempfile

    from pframe.assemble import assemble
    from pframe.kernel import simulate
    from pframe.reader import parse_scene
    from pframe.record import write_result

    path = {"eq14": EQ14, "hust": HUST}[model]
    loaded = parse_scene(_variant(path, law, keep_tension, pounding, stiffness),
                         source=path.name, base_dir=path.parent)
    result = simulate(assemble(loaded.expanded))
    assert result.completed(0), result.describe_failure(0)
    with tempfile.TemporaryDirectory() as folder:
        out = write_result(Path(folder) / "run.h5", result, loaded)
        with h5py.File(out, "r") as f:
            assert f.attrs["units_system"] == b"dimensionless"  # NC_CHAR: bytes in h5py
            run = {name: f[name][()] for name in f}
        with xr.open_dataset(out, engine="h5netcdf") as ds:  # names: decoded char arrays
            for key in ("node", "story", "contact"):
                if f"{key}_name" in ds:
                    run[key] = [str(s) for s in ds[f"{key}_name"].values]
    run["pi"] = _pi_values(path)
    return run


def _pi_values(path: Path) -> dict[str, float]:
    from pframe.nondim import scene_pi
    from pframe.reader import load_scene

    loaded = load_scene(path)
    report = scene_pi(loaded.scene, loaded.expanded)
    return {g.name: report.values[g.name] for g in report.groups}


def _column(run: dict, variable: str, name: str) -> np.ndarray:
    dimension = {"displacement": "node", "velocity": "node", "acceleration": "node",
                 "story_drift": "story", "story_force": "story",
                 "contact_force": "contact"}[variable]
    return run[variable][:, run[dimension].index(name)]


def _g(x: float) -> str:
    """Four significant digits, as the page prints numbers."""
    return f"{x:.4g}"


def _table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------------
# section 3: eq. (14)
# ---------------------------------------------------------------------------------------------

def _pi_table(model: str, printed: dict) -> str:
    values = _run(model)["pi"]
    return _table(["Group", "Printed in the paper", "`pframe pi` on the model"],
                  [[f"`{k}`", _g(v), _g(values[k])] for k, v in printed.items()])


EQ14_PRINTED = {"Pi_m": 0.25, "Pi_k": 5, "Pi_mu": 10, "Pi_uya": 0.1, "Pi_uyb": 0.06,
                "Pi_xi": 0.05, "Pi_alpha": 0.1, "Pi_wcon": 65, "Pi_e": 0.4, "Pi_d": 0.5}
HUST_PRINTED = {"Pi_m": 1, "Pi_k": 17.5, "Pi_mu": 1, "Pi_xi": 0.05, "Pi_wcon": 65,
                "Pi_e": 0.4, "Pi_d": 0.41}
LAWS = {"improved Kelvin": ("improved_kelvin", False), "Kelvin (clipped)": ("kelvin", False),
        "Kelvin (`keep_tension`)": ("kelvin", True)}


def _eq14(label: str) -> dict:
    law, keep = LAWS[label]
    return _run("eq14", law, keep)


def eq14_impacts() -> str:
    contacts = _eq14("improved Kelvin")["contact"]
    rows = [[label] + [str(n) for n in _eq14(label)["impact_count"]] for label in LAWS]
    rows.append(["Wu et al. (2021), Figures 3-6"] + ["8"] * len(contacts))
    return _table(["Contact law"] + [f"`{c}`" for c in contacts], rows)


def _yield_ratios(run: dict) -> dict[str, float]:
    pi = run["pi"]
    yield_drift = {"A": pi["Pi_uya"], "B": pi["Pi_uyb"]}  # in units of l_e, as the file
    return {s: float(np.max(np.abs(_column(run, "story_drift", s)))) / yield_drift[s[0]]
            for s in run["story"]}


def eq14_yielding() -> str:
    runs = {label: _eq14(label) for label in ("improved Kelvin", "Kelvin (clipped)")}
    ratios = {label: _yield_ratios(run) for label, run in runs.items()}
    rows = []
    for storey in runs["improved Kelvin"]["story"]:
        pi = runs["improved Kelvin"]["pi"]
        u_y = pi["Pi_uya"] if storey.startswith("A") else pi["Pi_uyb"]
        peak = float(np.max(np.abs(_column(runs["improved Kelvin"], "story_drift", storey))))
        row = [f"`{storey}`", _g(u_y), _g(peak)]
        for label in runs:
            r = ratios[label][storey]
            row.append(f"{r:.2f} ({'yields' if r > 1 else 'elastic'})")
        rows.append(row)
    return _table(["Storey", "Yield drift u_y / l_e", "Peak drift / l_e (improved Kelvin)",
                   "Peak / yield drift, improved Kelvin", "Peak / yield drift, Kelvin"], rows)


#: the stiffness of the beta K term of Rayleigh damping (eq. 5b: K(t)), as the model reads it
READINGS = {"initial": "initial stiffness", "current": "current stiffness K(t) (the model)"}


def eq14_damping() -> str:
    """Both readings of eq. (5b), improved Kelvin and Kelvin: impacts and peak / yield drift."""
    rows = []
    for stiffness, label in READINGS.items():
        for law, name in (("improved_kelvin", "improved Kelvin"), ("kelvin", "Kelvin")):
            run = _run("eq14", law, stiffness=stiffness)
            ratios = _yield_ratios(run)
            rows.append([label, name, "/".join(str(n) for n in run["impact_count"])]
                        + [f"{ratios[s]:.3f}" for s in run["story"]]
                        + [", ".join(s for s in run["story"] if ratios[s] > 1)])
    stories = _run("eq14")["story"]
    return _table(["Rayleigh on the", "Contact law", "Impacts per floor"]
                  + [f"`{s}` peak / yield drift" for s in stories] + ["Storeys that yield"],
                  rows + [["Wu et al. (2021)", "improved Kelvin", "8/8/8"] + [""] * len(stories)
                          + ["A/1, A/2, B/1, B/2"]])


def _force_stats(run: dict, contact: str) -> tuple[float, float]:
    force = _column(run, "contact_force", contact)
    return float(np.max(force)), float(np.min(force))


def eq14_forces() -> str:
    rows = []
    for label in LAWS:
        run = _eq14(label)
        for contact in run["contact"]:
            peak, low = _force_stats(run, contact)
            rows.append([label, f"`{contact}`", _g(peak), _g(low),
                         f"{100 * low / peak:.1f} %"])
    return _table(["Contact law", "Contact", "Peak compression F / (m_b a_p)",
                   "Minimum F / (m_b a_p)", "Minimum / peak"], rows)


def eq14_velocities() -> str:
    ik, kelvin = _eq14("improved Kelvin"), _eq14("Kelvin (`keep_tension`)")
    rows = []
    for node in ("A/3", "B/3"):
        a, b = _column(ik, "velocity", node), _column(kelvin, "velocity", node)
        rms = float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(a**2)))
        rows.append([f"`{node}`", _g(float(np.max(np.abs(a)))),
                     _g(float(np.max(np.abs(b)))),
                     f"{100 * float(np.max(np.abs(a - b))) / float(np.max(np.abs(a))):.1f} %",
                     f"{100 * rms:.1f} %"])
    return _table(["Floor", "Peak velocity, improved Kelvin", "Peak velocity, Kelvin "
                   "(`keep_tension`)", "Largest difference / peak",
                   "RMS difference / RMS"], rows)


def _displacement_stats(run: dict, node: str) -> tuple[float, float]:
    x = _column(run, "displacement", node)
    return float(np.max(x)), float(np.min(x))


def eq14_pounding() -> str:
    pounding, free = _eq14("improved Kelvin"), _run("eq14", pounding=False)
    rows = []
    for node in ("A/1", "A/2", "A/3", "B/1", "B/2", "B/3"):
        (p_max, p_min), (f_max, f_min) = (_displacement_stats(r, node) for r in (pounding, free))
        rows.append([f"`{node}`", _g(p_max), _g(f_max), _g(p_min), _g(f_min),
                     _g(max(p_max, -p_min)), _g(max(f_max, -f_min))])
    return _table(["Floor", "Max x, pounding", "Max x, no contacts", "Min x, pounding",
                   "Min x, no contacts", "Peak abs x, pounding", "Peak abs x, no contacts"],
                  rows)


# ---------------------------------------------------------------------------------------------
# section 4.4: the HUST model
# ---------------------------------------------------------------------------------------------

def _peak(run: dict, variable: str, node: str) -> float:
    """From the envelope: the peak over every step (the history keeps every 10th)."""
    return float(run[f"peak_{variable}"][run["node"].index(node)])


def hust_response() -> str:
    pounding, free = _run("hust"), _run("hust", pounding=False)
    rows = []
    for node in ("A/4", "A/3"):
        for variable, symbol in (("displacement", "x"), ("acceleration", "a / a_p")):
            peaks = [_peak(r, variable, node) for r in (pounding, free)]
            rows.append([f"`{node}`", f"peak abs {symbol}", _g(peaks[0]), _g(peaks[1]),
                         f"{peaks[0] / peaks[1]:.2f}"])
    return _table(["Floor", "Quantity", "Pounding (gap Pi_d = 0.41)", "No contacts",
                   "Ratio"], rows)


def hust_contacts() -> str:
    run = _run("hust")
    drift = float(np.max(run["peak_story_drift"]))
    rows = [[f"`{c}`", str(n), _g(float(run["peak_contact_force"][i]))]
            for i, (c, n) in enumerate(zip(run["contact"], run["impact_count"]))]
    return (_table(["Contact", "Impacts in tau = 0 .. 100", "Peak force F / (m_b a_p)"], rows)
            + f"\nLargest storey drift: {_g(drift)} l_e (storeys elastic).\n")


def validation_tables() -> dict[str, str]:
    """Every table of docs/validation.md, by marker name."""
    return {
        "eq14-pi": _pi_table("eq14", EQ14_PRINTED),
        "eq14-impacts": eq14_impacts(),
        "eq14-yielding": eq14_yielding(),
        "eq14-damping": eq14_damping(),
        "eq14-forces": eq14_forces(),
        "eq14-velocities": eq14_velocities(),
        "eq14-pounding": eq14_pounding(),
        "hust-pi": _pi_table("hust", HUST_PRINTED),
        "hust-response": hust_response(),
        "hust-contacts": hust_contacts(),
    }


def _rewrite(text: str, tables: dict[str, str]) -> str:
    def replace(match):
        name = match.group("name")
        return match.group(1) + tables[name] + match.group(4) if name in tables else match[0]

    return BLOCK.sub(replace, text)


# ---------------------------------------------------------------------------------------------
# tests
# ---------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_page_holds_exactly_the_computed_tables():
    text = PAGE.read_text(encoding="utf-8")
    tables = validation_tables()
    found = {m.group("name"): m.group("body") for m in BLOCK.finditer(text)}
    assert set(found) == set(tables), f"markers in the page: {sorted(found)}"
    for name, table in tables.items():
        assert found[name] == table, (
            f"docs/validation.md, table {name!r} is stale; regenerate with: {REGENERATE}\n"
            f"expected:\n{table}")


@pytest.mark.slow
def test_eq14_claims():
    """What section 3 of the page says about eq. (14)."""
    for label in LAWS:
        assert _eq14(label)["impact_count"].tolist() == [8, 8, 8], label
    for label in ("improved Kelvin", "Kelvin (clipped)"):
        # the paper: storeys 1 and 2 of both buildings yield, storey 3 stays elastic
        ratios = _yield_ratios(_eq14(label))
        assert ratios["A/1"] > 1 and ratios["A/2"] > 1 and ratios["A/3"] < 1, label
        assert ratios["B/1"] > 1 and ratios["B/2"] > 1 and ratios["B/3"] < 1, label
    for law in ("improved_kelvin", "kelvin"):  # on the initial stiffness B/2 stays elastic
        initial = _run("eq14", law, stiffness="initial")
        assert initial["impact_count"].tolist() == [8, 8, 8], law
        ratios = _yield_ratios(initial)
        assert ratios["A/1"] > 1 and ratios["A/2"] > 1 and ratios["B/1"] > 1, law
        assert 0.9 < ratios["B/2"] < 1 and ratios["A/3"] < 1 and ratios["B/3"] < 1, law
    for contact in ("floor-1", "floor-2", "floor-3"):
        assert _force_stats(_eq14("improved Kelvin"), contact)[1] >= 0.0
        assert _force_stats(_eq14("Kelvin (clipped)"), contact)[1] >= 0.0
        peak, low = _force_stats(_eq14("Kelvin (`keep_tension`)"), contact)
        assert -0.35 * peak < low < -0.2 * peak  # "about a quarter"
        assert (_force_stats(_eq14("Kelvin (clipped)"), contact)[0]
                < 0.8 * _force_stats(_eq14("improved Kelvin"), contact)[0])
    for node in ("A/3", "B/3"):
        a = _column(_eq14("improved Kelvin"), "velocity", node)
        b = _column(_eq14("Kelvin (`keep_tension`)"), "velocity", node)
        assert np.sqrt(np.mean((a - b) ** 2)) < 0.05 * np.sqrt(np.mean(a**2))
    pounding, free = _eq14("improved Kelvin"), _run("eq14", pounding=False)
    for node in ("A/1", "A/2", "A/3"):  # A's positive displacement suppressed, its peak lower
        assert _displacement_stats(pounding, node)[0] < 0.7 * _displacement_stats(free, node)[0]
        assert (np.max(np.abs(_column(pounding, "displacement", node)))
                < np.max(np.abs(_column(free, "displacement", node))))
    for level in (1, 2, 3):  # A's negative displacement far larger than B's
        assert (_displacement_stats(pounding, f"A/{level}")[1]
                < 3 * _displacement_stats(pounding, f"B/{level}")[1])
    for node in ("B/1", "B/2", "B/3"):  # B's positive displacement grows
        assert _displacement_stats(pounding, node)[0] > 1.4 * _displacement_stats(free, node)[0]


@pytest.mark.slow
def test_hust_claims():
    """What section 4.4 of the page says about the HUST model."""
    pounding, free = _run("hust"), _run("hust", pounding=False)
    assert sum(pounding["impact_count"]) > 8  # impacts at several cycles
    for node in ("A/4", "A/3"):  # pounding raises the accelerations of floors 3 and 4
        assert _peak(pounding, "acceleration", node) > 1.3 * _peak(free, "acceleration", node)
    assert _peak(pounding, "acceleration", "A/3") > 5 * _peak(free, "acceleration", "A/3")
    for node in ("A/4", "A/3"):  # while the peak displacements of A are a little lower
        assert _peak(pounding, "displacement", node) < _peak(free, "displacement", node)
    assert pounding["impact_count"].tolist()[1] > 10 * pounding["impact_count"].tolist()[0]



def test_no_text_calls_the_borrego_mountain_record_el_centro():
    """A-ELC180.AT2 is Borrego Mountain 1968 (recorded at the El Centro Array #9 station), not
    the 1940 Imperial Valley El Centro record of Chopra and the pounding papers
    (elCentro.AT2): wherever the repository names it beside "El Centro", it says Borrego."""
    offenders = []
    for folder in ("docs", "tests", "models", "benchmarks", "framework"):
        for path in sorted((REPO / folder).rglob("*")):
            if path.suffix not in (".md", ".py", ".yaml", ".yml", ".txt") or path == Path(__file__):
                continue
            lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
            for i, line in enumerate(lines):
                context = " ".join(lines[max(0, i - 1):i + 2]).lower()
                if "a-elc180" in line.lower() and "el centro" in context and "borrego" not in context:
                    offenders.append(f"{path.relative_to(REPO)}:{i + 1}: {line.strip()}")
    assert not offenders, "\n".join(offenders)


IMAGE = re.compile(r'!\[[^\]]*\]\((?P<md>[^)\s]+)\)|<img\s[^>]*?src="(?P<html>[^"]+)"')


def test_page_images_exist():
    """Every figure the page shows (Markdown or <img>) is a file beside it, under docs/img."""
    text = PAGE.read_text(encoding="utf-8")
    images = [m.group("md") or m.group("html") for m in IMAGE.finditer(text)]
    assert images, "docs/validation.md shows no figures"
    missing = [name for name in images if not (PAGE.parent / name).is_file()]
    assert not missing, f"docs/validation.md shows figures that do not exist: {missing}"
    assert all(name.startswith("img/") for name in images), images


if __name__ == "__main__":
    text = PAGE.read_text(encoding="utf-8")
    PAGE.write_text(_rewrite(text, validation_tables()), encoding="utf-8")
    print(f"rewrote the tables of {PAGE}", file=sys.stderr)
