"""Ground motions: a sine pulse or a recorded accelerogram, sampled on the analysis time grid.

The names below load their modules on first use: a scene whose motion is a function of time
reads no record (``pframe.excitation.records`` is not imported).
"""

#: public name -> module that defines it
_NAMES = {"ground_acceleration": "sample", "read_record": "records"}

__all__ = ["ground_acceleration", "read_record"]


def __getattr__(name: str):
    module = _NAMES.get(name)
    if module is None:
        raise AttributeError(f"module 'pframe.excitation' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(f"pframe.excitation.{module}"), name)
    globals()[name] = value
    return value
