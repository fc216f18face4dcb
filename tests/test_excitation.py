"""Ground motions: records read from files reproduce the motion they sample."""

import numpy as np
import pytest

from pframe.assemble import assemble
from pframe.excitation import read_record
from pframe.excitation.records import G
from pframe.kernel import simulate
from pframe.reader import parse_scene

SCENE = """
buildings:
  - {{name: A, floors: 2, mass: 1000.0, story: {{material: elastic, stiffness: 4.0e5}}}}
excitation: {excitation}
analysis: {{dt: 0.002, duration: 4.0}}
recorders:
  - {{kind: history, quantities: [displacement, ground_acceleration]}}
"""


def _run(excitation: str, base_dir):
    loaded = parse_scene(SCENE.format(excitation=excitation), base_dir=base_dir)
    result = simulate(assemble(loaded.expanded))
    return result.history["displacement"][0], result.history["ground_acceleration"][0]


def test_sampled_sine_equals_sine(tmp_path):
    """A two-column record sampled at the analysis step gives the sine's response exactly,
    and the same record in g in an AT2 file gives it to the file's printed precision."""
    t = np.arange(0, 4.0 + 1e-9, 0.002)
    a = 3.0 * np.sin(5.0 * t)
    np.savetxt(tmp_path / "sine.txt", np.column_stack([t, a]), header="time acc",
               fmt="%.17g")
    with open(tmp_path / "sine.AT2", "w") as f:
        f.write("PEER NGA STRONG MOTION DATABASE RECORD\nsynthetic sine\n"
                "ACCELERATION TIME SERIES IN UNITS OF G\n"
                f"NPTS= {t.size}, DT= .0020 SEC\n")
        for row in (a / G).reshape(-1, 1):
            f.write(" ".join(f"{x:.10E}" for x in row) + "\n")
    u_sine, ag_sine = _run("{kind: sine, amplitude: 3.0, frequency: 5.0}", tmp_path)
    u_rec, ag_rec = _run("{kind: record, file: sine.txt}", tmp_path)
    u_at2, _ = _run("{kind: record, file: sine.AT2}", tmp_path)
    assert np.max(np.abs(ag_rec - ag_sine)) <= 1e-14 * 3.0
    assert np.max(np.abs(u_rec - u_sine)) <= 1e-12 * np.max(np.abs(u_sine))
    assert np.max(np.abs(u_at2 - u_sine)) <= 1e-9 * np.max(np.abs(u_sine))


def test_scale_and_interpolation(tmp_path):
    """A coarse record is interpolated linearly, scaled, and zero after it ends."""
    (tmp_path / "ramp.txt").write_text("0 0\n1 2\n2 0\n")
    _, ag = _run("{kind: record, file: ramp.txt, scale: 0.5}", tmp_path)
    t = np.arange(ag.size) * 0.002
    expected = 0.5 * np.interp(t, [0, 1, 2], [0, 2, 0], right=0.0)
    assert np.allclose(ag, expected, rtol=0, atol=1e-15)
    assert np.all(ag[t > 2.0] == 0.0)


@pytest.mark.parametrize("text, message", [
    ("0 1\n1\n", "two columns"),
    ("0 1\n0 2\n", "increase"),
    ("0 1\n1 x\n", "two numbers"),
])
def test_malformed_columns(tmp_path, text, message):
    (tmp_path / "bad.txt").write_text(text)
    with pytest.raises(ValueError, match=message):
        read_record(tmp_path / "bad.txt")
