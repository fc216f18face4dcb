"""From resolved definitions to a :class:`Plan`: flat arrays with a leading batch axis."""

from pframe.assemble.plan import LawGroup, Plan, assemble, assemble_batch, batch_key

__all__ = ["LawGroup", "Plan", "assemble", "assemble_batch", "batch_key"]
