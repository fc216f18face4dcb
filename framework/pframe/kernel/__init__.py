"""The compiled time-stepping kernel and its driver.

The algorithm is ordinary compiled Python, one idea per module: :mod:`~pframe.kernel.loop`
(the time loop, the entry point), :mod:`~pframe.kernel.implicit` (a generalised-alpha step
with sub-step retries), :mod:`~pframe.kernel.newton`, :mod:`~pframe.kernel.explicit`,
:mod:`~pframe.kernel.events`, :mod:`~pframe.kernel.assembly` (residual, tangents, the band),
:mod:`~pframe.kernel.energy` (commit and energy bookkeeping), :mod:`~pframe.kernel.record`,
:mod:`~pframe.kernel.banded` and :mod:`~pframe.kernel.dispatch` (the law switch), over the
named arrays of :mod:`~pframe.kernel.state`. It is compiled once per installed version and
cached (:mod:`~pframe.kernel.cache`); :func:`simulate` (:mod:`~pframe.kernel.run`) drives it.
"""

from pframe.kernel import cache

cache.skip_blas_probe()
#: where this installation's kernel is cached
FOLDER = cache.folder(cache.source_key())

with cache.caching_into(FOLDER):  # every kernel function is decorated inside this block
    from pframe.kernel import (  # noqa: F401  # noqa: F401  # noqa: F401
        assembly,
        banded,
        dispatch,
        energy,
        events,
        explicit,
        implicit,
        loop,
        newton,
        record,
    )

from pframe.kernel.run import Result, simulate  # noqa: E402

__all__ = ["FOLDER", "Result", "simulate"]
