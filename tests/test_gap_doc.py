"""docs/gap-audit.md cannot drift from the code: every number it prints is computed here.

The page's tables sit between ``<!-- BEGIN <name> -->`` and ``<!-- END <name> -->`` markers;
:func:`gap_tables` recomputes them by auditing the paper's pair (models/wu2021-eq14.yaml) and
the HUST pair (models/hust-4x3.yaml) over the suite models/suites/peer-records.yaml, read from
the shared PEER records (../shared/records beside the repository; the test skips, saying so,
without them). After a deliberate change, rewrite the tables and the figures with::

    python tests/test_gap_doc.py
"""

from __future__ import annotations

import re
import sys
from functools import cache
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[1]
PAGE = REPO / "docs" / "gap-audit.md"
SUITE = REPO / "models" / "suites" / "peer-records.yaml"
RECORDS = (REPO / ".." / "shared" / "records").resolve()
BLOCK = re.compile(r"(<!-- BEGIN (?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- END (?P=name) -->)",
                   re.S)
REGENERATE = "python tests/test_gap_doc.py"

#: the two audits of the page: scene, measure, levels (g), provided gap (m), time step (s),
#: the level its separation table shows, EN 1998-1's 0.7 for coinciding floors
AUDITS = {
    "wu2021": ("wu2021-eq14.yaml", "sa:A", [0.25 * i for i in range(1, 11)], 0.1242451014414167,
               0.002, 1.0, False),
    "hust": ("hust-4x3.yaml", "pga", [round(0.02 * i, 2) for i in range(1, 11)], 0.002, 0.001,
             0.1, True),
}

needs_records = pytest.mark.skipif(
    not RECORDS.is_dir(), reason=f"the PEER records folder {RECORDS} (../shared/records beside "
    "the repository) is absent; the page's numbers come from those records")


@cache
def _audit(name: str):
    from pframe.gap import audit

    scene, measure, levels, gap, dt, _, en = AUDITS[name]
    return audit(REPO / "models" / scene, SUITE, records_folder=RECORDS, levels=levels, gap=gap,
                 dt=dt, measure=measure, en_coincident=en, threads=2)


def _table(header: list[str], rows: list[list[str]]) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---:" for _ in header) + "|"]
    return "\n".join(out + ["| " + " | ".join(r) + " |" for r in rows]) + "\n"


def _separations(name: str) -> str:
    ds = _audit(name)
    at = AUDITS[name][5]
    rules = [str(r) for r in ds.rule_name.values]
    stats = ds.gap_statistics.sel(level=at)
    rows = []
    for contact in ds.contact_name.values:
        for statistic in ("median", "p84"):
            row = stats.sel(contact_name=contact, statistic_name=statistic)
            rows.append([f"{contact}", statistic] + [f"{1000 * float(row.sel(rule_name=r)):.1f}"
                                                     for r in rules])
    return _table(["contact", "over the records"] + [f"{r} (mm)" for r in rules], rows)


def _fragility(name: str) -> str:
    ds = _audit(name)
    rows = [[f"{level:g}"] + [f"{float(ds.pounding_fraction.sel(level=level, contact_name=c)):.2f}"
                              for c in ds.contact_name.values]
            + [f"{float(ds.pounding_fraction_any.sel(level=level)):.2f}"]
            for level in ds.level.values]
    table = _table([f"{ds.attrs['measure']} (g)"] + [f"{c}" for c in ds.contact_name.values]
                   + ["any contact"], rows)
    median, beta = float(ds.fragility_median_any), float(ds.fragility_dispersion_any)
    return table + (f"\nLognormal fit (maximum likelihood), pounding at any contact: median "
                    f"**{median:.3f} g**, dispersion **{beta:.3f}**.\n")


def _modes(name: str) -> str:
    ds = _audit(name)
    parts = [f"T_{b} = {float(ds.period.sel(building_name=b)):.3f} s"
             for b in ds.building_name.values]
    rho = ", ".join(f"{float(r):.3f}" for r in np.unique(ds.correlation.values.round(6)))
    return (f"First periods {', '.join(parts)}, damping ratio "
            f"{float(ds.damping_ratio[0]):.3f} at each; rho = {rho}.\n")


def gap_tables() -> dict[str, str]:
    out = {}
    for name in AUDITS:
        out[f"{name}-modes"] = _modes(name)
        out[f"{name}-separations"] = _separations(name)
        out[f"{name}-fragility"] = _fragility(name)
    from pframe.gap.codes import docs_table

    out["code-rules"] = docs_table() + "\n"  # the code rules (tests/test_code_rules.py)
    return out


def _rewrite(text: str, tables: dict[str, str]) -> str:
    def replace(match):
        name = match.group("name")
        return match.group(1) + tables[name] + match.group(4) if name in tables else match.group(0)
    return BLOCK.sub(replace, text)


@pytest.mark.slow
@needs_records
def test_page_holds_exactly_the_computed_tables():
    text = PAGE.read_text(encoding="utf-8")
    tables = gap_tables()
    found = {m.group("name"): m.group("body") for m in BLOCK.finditer(text)}
    assert set(found) == set(tables), "docs/gap-audit.md: table markers differ"
    for name, body in tables.items():
        assert found[name] == body, (f"docs/gap-audit.md, table {name!r} is stale; regenerate "
                                     f"with: {REGENERATE}\n{body}")


@pytest.mark.slow
@needs_records
def test_page_claims():
    """What the prose says: the rules are ordered simulated <= DDC <= SRSS <= ABS on the
    median at every level and contact of both pairs; the paper's pair keeps clear of its own
    gap d = 0.124 m up to 0.6 g PGA; the HUST pair pounds across its 2 mm gap at 0.1 g under
    half of the records at least, and under all of them from 0.2 g."""
    for name in AUDITS:
        med = _audit(name).gap_statistics.sel(statistic_name="median")
        sim, ddc, srss, abs_ = (med.sel(rule_name=r).values for r in ("simulated", "DDC", "SRSS",
                                                                   "ABS"))
        assert np.all(sim <= ddc) and np.all(ddc <= srss) and np.all(srss <= abs_), name
    wu = _audit("wu2021")
    assert float(wu.pounding_fraction_any.sel(level=slice(None, 1.5)).max()) == 0.0
    assert float(wu.pounding_fraction_any.sel(level=slice(1.75, None)).min()) > 0.0
    hust = _audit("hust")
    assert float(hust.pounding_fraction_any.sel(level=0.1)) >= 0.5
    assert float(hust.pounding_fraction_any.sel(level=slice(0.16, None)).min()) == 1.0


def test_page_images_exist():
    for name in AUDITS:
        assert (REPO / "docs" / "img" / f"gap-audit-{name}.png").is_file()


def _write_figures():
    import matplotlib

    matplotlib.use("Agg")
    import tempfile

    from pframe.gap.output import write_dataset
    from pframe.plot.gap import gap_figure

    for name in AUDITS:
        with tempfile.TemporaryDirectory() as folder:
            path = write_dataset(_audit(name), Path(folder) / f"{name}.h5")
            fig, _ = gap_figure(path, statistic="p84", level=AUDITS[name][5])
            fig.savefig(REPO / "docs" / "img" / f"gap-audit-{name}.png", dpi=100)


if __name__ == "__main__":
    if not RECORDS.is_dir():
        sys.exit(f"{RECORDS} is absent: the page's numbers come from those records")
    PAGE.write_text(_rewrite(PAGE.read_text(encoding="utf-8"), gap_tables()), encoding="utf-8")
    _write_figures()
    print(f"rewrote {PAGE} and docs/img/gap-audit-*.png")
