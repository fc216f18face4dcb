"""The compiled time-stepping kernel: code generation, caching and the chunked driver.

Imports numpy and numba only (never pydantic, yaml or h5py).
"""

from pframe.kernel.run import Result, simulate

__all__ = ["Result", "simulate"]
