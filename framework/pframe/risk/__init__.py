"""Risk-based gap design (docs/risk.md): analysis designs over a record suite (multiple
stripes, IDA on a grid, cloud), lognormal fragilities by maximum likelihood, hazard curves,
mean annual frequencies, the gap at a target annual frequency of pounding; Latin hypercube
and subset simulation for random scene parameters::

    import pframe
    ds = pframe.risk("models/risk/wu2021-msa.yaml")
    float(ds.gap_at_target)

Imported by ``pframe risk`` and ``pframe.risk`` only (not by ``import pframe``).
"""

from pframe._callable import make_callable
from pframe.risk.fragility import Fragility, fit_capacities, fit_cloud, fit_msa
from pframe.risk.hazard import (
    HazardCurve,
    closed_form_maf,
    mean_annual_frequency,
    probability_in_years,
    read_hazard,
)
from pframe.risk.pelicun import demand_table, export_pelicun
from pframe.risk.sampling import Uncertain, crude_monte_carlo, latin_hypercube, subset_simulation
from pframe.risk.study import risk

__all__ = ["Fragility", "HazardCurve", "Uncertain", "closed_form_maf", "crude_monte_carlo",
           "demand_table", "export_pelicun", "fit_capacities", "fit_cloud", "fit_msa",
           "latin_hypercube", "mean_annual_frequency", "probability_in_years", "read_hazard",
           "risk", "subset_simulation"]


make_callable(__name__, "pframe.risk.study", "risk")  # pframe.risk(...) runs a study
