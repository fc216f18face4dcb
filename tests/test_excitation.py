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


# ---------------------------------------------------------------------------------------------
# units of records: read from the header, refused when the scene contradicts them
# ---------------------------------------------------------------------------------------------

def _at2(path, values, units_line: str, dt: float = 0.01):
    """A PEER-style .AT2 file of ``values`` with the given third header line."""
    values = np.asarray(values, dtype=float)
    rows = [" ".join(f"{x: .7E}" for x in values[i:i + 5]) for i in range(0, values.size, 5)]
    path.write_text("PEER STRONG MOTION DATABASE RECORD (test)\nSYNTHETIC 01/01/00, TEST\n"
                    f"{units_line}\nNPTS= {values.size}, DT= {dt:.5f} SEC\n"
                    + "\n".join(rows) + "\n", encoding="utf-8")
    return path


def _record_scene(file: str, extra: str = "", duration: float = 4.0) -> str:
    return (f"buildings:\n  - {{name: A, floors: 1, mass: 1000.0, story: {{material: elastic, "
            f"stiffness: 4.0e5}}}}\nexcitation: {{kind: record, file: {file}{extra}}}\n"
            f"analysis: {{dt: 0.01, duration: {duration}}}\n")


def test_a_header_in_cm_per_s2_is_read_in_cm_per_s2(tmp_path):
    """'UNITS OF CM/SEC/SEC' (older PEER files): 127.6 in the file is 1.276 m/s^2 = 0.13 g,
    not 127.6 g (the reader took every .AT2 for g)."""
    values = 127.6 * np.sin(np.linspace(0.0, 6.0 * np.pi, 301)) * np.hanning(301)
    _at2(tmp_path / "cm.AT2", values, "ACCELERATION TIME HISTORY IN UNITS OF CM/SEC/SEC")
    t, a = read_record(tmp_path / "cm.AT2")
    assert np.max(np.abs(a)) == pytest.approx(0.01 * np.max(np.abs(values)), rel=1e-7)
    loaded = parse_scene(_record_scene("cm.AT2"), base_dir=tmp_path)
    peak = np.max(np.abs(loaded.expanded.ground_acceleration))
    assert peak == pytest.approx(0.01 * np.max(np.abs(values)), rel=1e-6)
    assert peak / G < 0.14
    from pframe.commands.validate import record_lines

    line = record_lines(loaded)[0]
    assert "in cm/s^2" in line and "as its header states (line 3, 'CM/SEC/SEC')" in line


@pytest.mark.parametrize("written, name", [
    ("ACCELERATION TIME SERIES IN UNITS OF G", "g"), ("The units are (g)", "g"),
    ("UNITS OF CM/SEC/SEC", "cm/s2"), ("in units of cm/s^2", "cm/s2"), ("UNITS: GAL", "gal"),
    ("units: m/s**2", "m/s2"), ("UNITS OF MM/S/S", "mm/s2"), ("UNITS OF IN/SEC2", "in/s2"),
    ("UNITS OF FT/S^2", "ft/s2")])
def test_header_units_are_converted_to_si(tmp_path, written, name):
    from pframe.excitation.records import UNITS, read_record_file

    values = [0.0, 1.0, -2.0, 0.5]
    record = read_record_file(_at2(tmp_path / "r.AT2", values, written))
    assert record.units == name and record.units_from == "header, line 3"
    assert np.max(np.abs(record.acceleration)) == pytest.approx(2.0 * UNITS[name], rel=1e-14)


def test_the_shared_record_written_in_cm_per_s2_gives_its_pga_in_g(tmp_path):
    """Borrego Mountain 1968 (A-ELC180, 0.130 g) rewritten in cm/s^2 with an older PEER
    header: the same PGA, not 980.665 times it."""
    from conftest import record_file

    original = record_file("A-ELC180.AT2")
    _, a_g = read_record(original)
    lines = original.read_text().splitlines()
    values = np.array(" ".join(lines[4:]).split(), dtype=float) * 980.665
    _at2(tmp_path / "cm.AT2", values, "ACCELERATION TIME HISTORY IN UNITS OF CM/SEC/SEC")
    _, a_cm = read_record(tmp_path / "cm.AT2")
    assert np.max(np.abs(a_g)) / G == pytest.approx(0.1301, abs=5e-5)
    assert np.max(np.abs(a_cm)) == pytest.approx(np.max(np.abs(a_g)), rel=1e-6)


def test_scene_units_that_contradict_the_header_are_refused(tmp_path):
    from pframe.errors import InputError

    _at2(tmp_path / "cm.AT2", [0.0, 100.0, -50.0], "ACCELERATION IN UNITS OF CM/SEC/SEC")
    with pytest.raises(InputError) as caught:
        parse_scene(_record_scene("cm.AT2", ", units: g"), source="scene.yaml",
                    base_dir=tmp_path)
    message = str(caught.value)
    assert "scene.yaml, line 3" in message and "cm.AT2, line 3" in message
    assert "cm/s^2" in message and "'g'" in message
    # the same units written another way are no conflict
    loaded = parse_scene(_record_scene("cm.AT2", ", units: gal"), base_dir=tmp_path)
    assert np.max(np.abs(loaded.expanded.ground_acceleration)) == pytest.approx(1.0)


def test_a_record_without_stated_units_says_it_took_the_default(tmp_path):
    from pframe.commands.validate import record_lines

    _at2(tmp_path / "none.AT2", [0.0, 0.1, -0.2], "NO STATEMENT OF THE SCALE HERE")
    line = record_lines(parse_scene(_record_scene("none.AT2"), base_dir=tmp_path))[0]
    assert "units g by default: the file states none" in line
    (tmp_path / "cols.txt").write_text("# units: cm/s2\n0 0\n0.01 150\n0.02 -300\n")
    loaded = parse_scene(_record_scene("cols.txt"), base_dir=tmp_path)
    assert np.max(np.abs(loaded.expanded.ground_acceleration)) == pytest.approx(3.0)
    assert "as its header states (line 1, 'cm/s2')" in record_lines(loaded)[0]


def test_a_header_in_units_pframe_does_not_read_needs_the_scene_units(tmp_path):
    from pframe.errors import InputError

    _at2(tmp_path / "v.AT2", [0.0, 1.0, -2.0], "VELOCITY TIME HISTORY IN UNITS OF CM/SEC")
    with pytest.raises(InputError, match=r"v.AT2, line 3: the header states the units 'CM/SEC'"):
        parse_scene(_record_scene("v.AT2"), base_dir=tmp_path)


# ---------------------------------------------------------------------------------------------
# the motion actually applied: stated after every scaling, in the line and in the file
# ---------------------------------------------------------------------------------------------

def _g(value: float) -> str:
    return f"{value:.4g} m/s^2 ({value / G:.4g} g)"


def test_the_record_line_states_the_pga_applied_after_scaling(tmp_path):
    """pga: 0.4 is 0.4 m/s^2 (0.0408 g): the line said the file's 0.3188 g before."""
    from conftest import record_file

    from pframe.commands.validate import record_lines

    record = record_file("elCentro.AT2")
    text = _record_scene(str(record), ", pga: 0.4", duration=6.0)
    loaded = parse_scene(text, base_dir=tmp_path)
    line = record_lines(loaded)[0]
    assert "PGA applied 0.4 m/s^2 (0.04079 g) at t = 2.02 s" in line
    assert "the file's PGA 3.127 m/s^2 (0.3188 g)" in line
    # the samples the kernel is given reach that PGA (dt = 0.01 hits every record sample)
    assert np.max(np.abs(loaded.expanded.ground_acceleration)) == pytest.approx(0.4, rel=1e-12)
    # time scaling moves the peak: w_p doubled, the peak comes at half the time
    half = parse_scene(_record_scene(str(record), ", scale: 2.0, frequency: 2.0", 6.0),
                       base_dir=tmp_path)
    facts = half.expanded.record
    line = record_lines(half)[0]
    peak_time = 2.02 * facts.time_factor
    file_pga = np.max(np.abs(read_record(record)[1]))
    assert f"PGA applied {_g(2.0 * file_pga)} at t = {peak_time:.4g} s" in line
    assert "for frequency 2 rad/s" in line


def test_the_result_file_states_the_motion_applied(tmp_path):
    from conftest import record_file

    from pframe.record.hdf5 import record_attributes

    loaded = parse_scene(_record_scene(str(record_file("elCentro.AT2")), ", pga: 0.4", 6.0),
                         base_dir=tmp_path)
    attrs = record_attributes(loaded)
    assert attrs["excitation_pga"] == pytest.approx(0.4, rel=1e-12)
    assert attrs["excitation_pga_g"] == pytest.approx(0.4 / G, rel=1e-12)
    assert attrs["excitation_pga_time"] == pytest.approx(2.02)
    assert "PGA applied 0.4 m/s^2" in attrs["record_read_as"]
    sine = parse_scene(SCENE.format(excitation="{kind: sine, amplitude: 3.0, frequency: 5.0}"))
    attrs = record_attributes(sine)
    assert attrs["excitation_pga"] == pytest.approx(3.0, rel=1e-9)
    assert attrs["excitation_pga_time"] == pytest.approx(np.pi / 10.0, rel=1e-6)
    assert "sine a_p = 3 m/s^2 (0.3059 g)" in attrs["excitation_applied"]


@pytest.mark.parametrize("pulse, peak_time", [
    ("{kind: cycloidal, type: A, amplitude: 2.0, period: 0.5}", 0.125),
    ("{kind: cycloidal, type: B, amplitude: 2.0, period: 0.5}", 0.0),
    ("{kind: ricker, amplitude: 2.0, period: 0.5}", 0.75)])
def test_pulses_state_their_amplitude_and_peak(pulse, peak_time):
    from pframe.commands.validate import excitation_lines

    loaded = parse_scene(SCENE.format(excitation=pulse))
    line = excitation_lines(loaded)[0]
    assert "a_p = 2 m/s^2 (0.2039 g)" in line
    assert f"peak 2 m/s^2 (0.2039 g) at t = {peak_time:.4g} s" in line


def test_an_analysis_that_stops_before_the_pga_is_warned_of(tmp_path):
    """A-ELC180's PGA is at 8.59 s: a 3 s analysis applies 5 % of it."""
    from conftest import record_file

    from pframe.assemble import assemble

    cut = parse_scene(_record_scene(str(record_file("A-ELC180.AT2")), ", pga: 0.4", 3.0),
                      base_dir=tmp_path)
    warnings = [w for w in assemble(cut.expanded).warnings if "before the record's peak" in w]
    assert len(warnings) == 1
    assert "at t = 8.59 s" in warnings[0] and "analysis.duration to at least 8.59 s" in warnings[0]
    whole = parse_scene(_record_scene(str(record_file("A-ELC180.AT2")), ", pga: 0.4", 9.0),
                        base_dir=tmp_path)
    assert not [w for w in assemble(whole.expanded).warnings if "peak" in w]
