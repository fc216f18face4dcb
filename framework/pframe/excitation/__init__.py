"""Ground motions: a sine pulse or a recorded accelerogram, sampled on the analysis time grid."""

from pframe.excitation.records import read_record
from pframe.excitation.sample import ground_acceleration

__all__ = ["ground_acceleration", "read_record"]
