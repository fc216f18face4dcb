"""docs/risk.md cannot drift from the code: its worked study's numbers are computed here.

The page's tables sit between ``<!-- BEGIN <name> -->`` and ``<!-- END <name> -->`` markers;
:func:`risk_tables` recomputes them by running models/risk/wu2021-msa.yaml over the shared
PEER records (../shared/records beside the repository; the test skips, saying so, without
them). After a deliberate change, rewrite the tables with::

    python tests/test_risk_doc.py
"""

from __future__ import annotations

import math
import sys
from functools import cache
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
PAGE = REPO / "docs" / "risk.md"
STUDY = REPO / "models" / "risk" / "wu2021-msa.yaml"
RECORDS = (REPO / ".." / "shared" / "records").resolve()
REGENERATE = "python tests/test_risk_doc.py"

needs_records = pytest.mark.skipif(
    not RECORDS.is_dir(), reason=f"the PEER records folder {RECORDS} (../shared/records beside "
    "the repository) is absent; the page's numbers come from those records")


@cache
def _study():
    import warnings

    from pframe.risk import risk

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        return risk(STUDY, records_folder=RECORDS, threads=2)


@cache
def _check():
    from pframe.risk.firstpassage import tubaldi_check

    return tubaldi_check(threads=2)


def _mm(x: float) -> str:
    return f"{1000 * x:.1f}" if math.isfinite(x) else "-"


def risk_tables() -> dict[str, str]:
    from pframe.risk.output import summary

    ds = _study()
    gap = (f"Gap at an annual frequency of pounding of {float(ds.target_annual_frequency):.4g} "
           f"per year (IM there {float(ds.intensity_at_target):.3f} g): "
           f"**{_mm(float(ds.gap_at_target))} mm** (90 % record bootstrap "
           f"{_mm(float(ds.gap_at_target_low))}-{_mm(float(ds.gap_at_target_high))} mm; "
           f"regression {_mm(float(ds.gap_at_target_regression))} mm).\n")
    if "rule_separation_at_target" in ds:
        gap += ("Code rules at that IM, median over the records: " + ", ".join(
            f"{r} {_mm(float(v))} mm" for r, v in
            zip(ds.rule_name.values, ds.rule_separation_at_target.values)) + ".\n")
    from pframe.risk.firstpassage import check_text

    return {"summary": "```text\n" + summary(ds) + "\n```\n", "gap": gap,
            "tubaldi": "```text\n" + check_text(_check()) + "\n```\n"}


def _rewrite(text: str, tables: dict[str, str]) -> str:
    import re

    block = re.compile(r"(<!-- BEGIN (?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- END (?P=name) -->)",
                       re.S)

    def replace(match):
        name = match.group("name")
        return match.group(1) + tables[name] + match.group(4) if name in tables else match.group(0)
    return block.sub(replace, text), {m.group("name"): m.group("body")
                                      for m in block.finditer(text)}


@pytest.mark.slow
@needs_records
def test_page_holds_the_computed_study():
    text = PAGE.read_text(encoding="utf-8")
    tables = risk_tables()
    _, found = _rewrite(text, {})
    assert set(found) == set(tables), "docs/risk.md: markers differ"
    for name, body in tables.items():
        assert found[name] == body, (f"docs/risk.md, block {name!r} is stale; regenerate with: "
                                     f"{REGENERATE}\n{body}")


@pytest.mark.slow
@needs_records
def test_page_claims():
    """What the prose says: the gap at 1/475 per year is below the scene's gap of 124 mm and
    below the ABS rule at the same intensity; pounding is rarer than the target at the scene's
    gap."""
    ds = _study()
    assert float(ds.gap_at_target) < float(ds.limit_value.sel(limit_name="pounding"))
    assert float(ds.gap_at_target) < float(ds.rule_separation_at_target.sel(rule_name="ABS"))
    maf = float(ds.annual_frequency.sel(limit_name="pounding", condition_name="without_pounding"))
    assert maf < float(ds.target_annual_frequency)


if __name__ == "__main__":
    new, _ = _rewrite(PAGE.read_text(encoding="utf-8"), risk_tables())
    PAGE.write_text(new, encoding="utf-8")
    sys.exit(0)
