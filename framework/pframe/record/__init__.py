"""Writing results: netCDF4-compatible HDF5 that xarray, ncdump and MATLAB read as is."""

from pframe.record.hdf5 import UNITS, ResultWriter, write_result

__all__ = ["UNITS", "ResultWriter", "write_result"]
