"""Gap audit: how far apart two adjacent buildings must stand (docs/gap-audit.md).

For each contact level and each record of a suite (scaled to intensity levels), the minimum
separations (ABS, SRSS, DDC, and the building codes' rules of :mod:`pframe.gap.codes`) from the
two buildings' peak displacements run without contact, beside the simulated critical gap
g_req = max_t (u_left - u_right); with a provided gap, the fraction of records that pound and
a lognormal fragility::

    from pframe.gap import audit

    ds = audit("models/gap-audit.yaml", "records/suite.yaml", gap=0.05, levels=[0.1, 0.2])
    ds.gap_statistics.sel(statistic_name="p84")      # (level, contact, rule)

Imported by ``pframe gap`` only (not by ``import pframe``).
"""

from pframe.gap.audit import audit, prepare
from pframe.gap.codes import CODES, separation, separation_from_peaks
from pframe.gap.fragility import fit_lognormal, lognormal_probability
from pframe.gap.rules import RULES, cqc_correlation, separations

__all__ = ["CODES", "RULES", "audit", "cqc_correlation", "fit_lognormal",
           "lognormal_probability", "prepare", "separation", "separation_from_peaks",
           "separations"]
