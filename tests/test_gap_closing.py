"""The kernel's running maximum of a contact's closing (simulate's ``closing``) against the
maximum of the streamed displacements, to the bit.

pframe.gap.runs.GapSink keeps max_t (u_left - u_right) of each contact from the streamed
history; where every side is one DOF (a planar pair on one ground) the kernel keeps it itself
(GapSink.run) and no history is streamed. Both subtract the same doubles and take their
maximum, so the gaps must be the same bits, whatever the calls' sizes and threads.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import WU2021

from pframe.gap.runs import GapSink, batch_plan, contact_pairs
from pframe.kernel import simulate
from pframe.reader import load_scene

STEPS, DT = 1500, 0.002


@pytest.fixture(scope="module")
def runs():
    """The paper's pair without contacts under four random motions, the displacements'
    history recorded whole."""
    loaded = load_scene(WU2021)
    rng = np.random.default_rng(3)
    motions = rng.normal(0.0, 3.0, (4, STEPS + 1)).cumsum(axis=1) * 0.1
    plan = batch_plan(loaded, motions, STEPS, dt=DT)
    return loaded, plan, simulate(plan, threads=1)


def _bits(array):
    return np.ascontiguousarray(array, dtype=float).view(np.uint64)


@pytest.mark.slow
def test_kernel_closing_is_the_streamed_maximum(runs):
    loaded, plan, whole = runs
    sink = GapSink(plan, contact_pairs(loaded))
    dofs = sink.closing_dofs()
    assert dofs is not None and dofs.shape == (3, 2)
    # each pair both ways round: a signed maximum, not a peak of |u_i - u_j|
    pairs = np.vstack([dofs, dofs[:, ::-1]])
    u = whole.history["displacement"]
    expected = np.max(u[:, :, pairs[:, 0]] - u[:, :, pairs[:, 1]], axis=1)
    # calls of a few steps each, in two threads: the maxima carried from call to call
    kept = simulate(plan, threads=2, chunk_seconds=1e-4, closing=pairs)
    np.testing.assert_array_equal(_bits(kept.closing), _bits(expected))
    assert np.all(expected[:, :3] > 0) and np.all(expected[:, 3:] > 0)
    # the run itself is untouched: envelopes, energies, counters of the evaluations
    for name, peaks in whole.envelope.items():
        np.testing.assert_array_equal(_bits(kept.envelope[name]), _bits(peaks))
    np.testing.assert_array_equal(_bits(kept.energy), _bits(whole.energy))


@pytest.mark.slow
def test_gap_sink_without_the_stream_gives_the_streamed_gaps(runs):
    loaded, plan, whole = runs
    streamed = GapSink(plan, contact_pairs(loaded))
    simulate(plan, threads=2, chunk_seconds=1e-4, sink=streamed)
    kept = GapSink(plan, contact_pairs(loaded))
    result = kept.run(plan, threads=2)
    np.testing.assert_array_equal(_bits(kept.gap), _bits(streamed.gap))
    assert result.history == {}  # nothing recorded for the sink
    left, right = kept.peaks(result.envelope["displacement"])
    np.testing.assert_array_equal(_bits(left), _bits(streamed.peaks(
        whole.envelope["displacement"])[0]))
    # a sink from a later step on cannot be the kernel's (it keeps every step's)
    assert GapSink(plan, contact_pairs(loaded), start=1).closing_dofs() is None
