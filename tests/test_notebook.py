"""docs/python.md in a real Jupyter kernel: a notebook built here and executed headless with
nbclient, as a user's notebook runs, then saved and read back as nbformat keeps it.

- names survive: ``to_series`` and ``to_dataframe`` are indexed by node, contact and building
  names, xarray's legends show them, ``.sel(node="B/3")`` takes them;
- a long solve's progress bar, as the *saved* notebook keeps it, ends at the final state
  (100 %, as many steps done as the run has), once, with no traceback: with ipywidgets (a
  widget, whose saved text form is the last one sent) and without (a text bar).

Skipped, saying why, only when nbclient is absent or a kernel cannot start.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
#: what each fact cell prints, for the test to read
MARK = "FACTS:"

SETUP = """\
import sys, json
sys.path.insert(0, {framework!r})   # this checkout's pframe
{block}
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import pframe
"""

NAMES = """\
scene = pframe.load("models/wu2021-eq14.yaml")
ds = pframe.solve(scene)
series = ds.peak_displacement.to_series()
top = ds.displacement.sel(node="B/3")
lines = ds.displacement.plot.line(x="t")
legend = [t.get_text() for t in plt.gca().get_legend().get_texts()]
plt.close("all")
table = ds[["peak_contact_force", "impact_count"]].to_dataframe()
print("FACTS:" + json.dumps({
    "index": [str(i) for i in series.index],
    "nodes": [str(n) for n in ds.node_name.values],
    "legend": legend,
    "sel_peak": float(abs(top).max()),
    "envelope_peak": float(ds.peak_displacement.sel(node="B/3")),
    "contacts": [str(i) for i in table.index],
    "contact_names": [str(n) for n in ds.contact_name.values],
}))
"""

# the rest of the page's first examples: a scene as a cell's value (its table), selections
# by name, the summary table
OBJECTS = """\
scene
"""
SUMMARY = """\
force = float(ds.contact_force.sel(contact="floor-3").max())
loop = ds[["story_drift", "story_force"]].sel(story="A/1").to_dataframe()
table = pframe.summary(ds)
peaks = table[table.part == "contact"].pivot(index="name", columns="quantity", values="value")
print("FACTS:" + json.dumps({"force": force, "peak": float(ds.peak_contact_force.sel(contact="floor-3")),
                             "loop_columns": [str(c) for c in loop.columns],
                             "summary_contacts": [str(i) for i in peaks.index]}))
"""

SWEEP = """\
sw = pframe.sweep("models/sweeps/wu2021-pi-d.yaml")
lines = sw.building_peak_displacement.plot.line(x="Pi_d")
legend = [t.get_text() for t in plt.gca().get_legend().get_texts()]
plt.close("all")
wide = sw.building_peak_displacement.to_series().unstack()
print("FACTS:" + json.dumps({"legend": legend, "columns": [str(c) for c in wide.columns],
                             "buildings": [str(b) for b in sw.building_name.values]}))
"""

# a run long enough for the bar to appear (pframe.progress.DELAY) whatever the machine's
# speed: the duration is set from the fastest of three short runs' rates, for about three
# seconds in the kernel (one probe slowed by a burst of load on a shared machine made the
# long run shorter than the delay)
LONG = """\
probes = [pframe.solve(scene.model_copy(update={"recorders": [pframe.Envelope(quantities=["displacement"])]}),
                       progress=False) for _ in range(3)]
rate = max(p.attrs["steps"] / max(p.attrs["solve_seconds"], 1e-3) for p in probes)
duration = scene.analysis.dt * max(3.0 * rate, 2e5)
long = scene.model_copy(update={
    "analysis": scene.analysis.model_copy(update={"duration": duration}),
    "recorders": [pframe.Envelope(quantities=["displacement"])]})
done = pframe.solve(long)
"""
LONG_FACTS = """\
print("FACTS:" + json.dumps({"steps": int(done.attrs["steps"]),
                             "seconds": float(done.attrs["solve_seconds"]),
                             "delay": pframe.progress.DELAY}))
"""


def _facts(cell) -> dict:
    for output in cell.outputs:
        if output.get("output_type") == "stream" and MARK in output.get("text", ""):
            return json.loads(output["text"].split(MARK, 1)[1].splitlines()[0])
    raise AssertionError(f"the cell printed no facts: {cell.outputs}")


def _shown(cell) -> list[str]:
    """What a renderer shows of a cell's outputs, as text: streams joined (each line's text
    after its last carriage return, as a terminal or Jupyter draws it) and each display's
    text form."""
    shown, stream = [], ""
    for output in cell.outputs:
        if output["output_type"] == "stream":
            stream += output["text"]
        elif "data" in output:
            shown.append(output["data"].get("text/plain", ""))
        if output["output_type"] == "error":
            shown.append("\n".join(output.get("traceback", [])))
    shown += [line.split("\r")[-1] for line in stream.split("\n")]
    return [s for s in shown if s.strip()]


def _execute(tmp_path: Path, widgets: bool):
    nbclient = pytest.importorskip("nbclient", reason="nbclient runs notebooks headless "
                                   "(pip install -e '.[test]')")
    import nbformat

    block = "" if widgets else "sys.modules['ipywidgets'] = None   # as without ipywidgets"
    sources = [SETUP.format(framework=str(REPO / "framework"), block=block), NAMES, SWEEP,
               LONG, LONG_FACTS, OBJECTS, SUMMARY]
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(s) for s in sources])
    client = nbclient.NotebookClient(nb, timeout=900, kernel_name="python3",
                                     resources={"metadata": {"path": str(REPO)}})
    kernel = client.setup_kernel()
    try:
        kernel.__enter__()
        started = client.kc is not None
    except Exception as exc:  # no kernelspec, no ipykernel, no ports: cannot test here
        pytest.skip(f"a Jupyter kernel could not start: {type(exc).__name__}: {exc}")
    if not started:
        pytest.skip("a Jupyter kernel did not start")
    try:
        for index, cell in enumerate(nb.cells):
            client.execute_cell(cell, index)
    finally:
        kernel.__exit__(None, None, None)
    saved = tmp_path / "python-md.ipynb"
    nbformat.write(nb, saved)
    return nbformat.read(saved, as_version=4)


@pytest.fixture(scope="module", params=["widgets", "text"])
def notebook(request, tmp_path_factory):
    widgets = request.param == "widgets"
    if widgets:
        pytest.importorskip("ipywidgets", reason="the widget bar needs ipywidgets")
    return _execute(tmp_path_factory.mktemp("nb"), widgets), widgets


@pytest.mark.slow
def test_no_cell_shows_a_traceback(notebook):
    nb, _ = notebook
    for cell in nb.cells:
        assert not [o for o in cell.outputs if o["output_type"] == "error"], cell.source
        for text in _shown(cell):
            assert "Traceback" not in text and "Exception ignored" not in text, text


@pytest.mark.slow
def test_names_survive_in_series_legends_and_sel(notebook):
    nb, _ = notebook
    facts = _facts(nb.cells[1])
    assert facts["index"] == facts["nodes"] == facts["legend"]
    assert facts["index"][:3] == ["A/1", "A/2", "A/3"]
    assert facts["contacts"] == facts["contact_names"] and len(facts["contacts"]) == 3
    # .sel(node="B/3") picked B/3's history: its largest |u| is B/3's envelope
    assert facts["sel_peak"] == pytest.approx(facts["envelope_peak"], rel=1e-12)


def test_sweep_legend_and_table_name_the_buildings(notebook):
    nb, _ = notebook
    facts = _facts(nb.cells[2])
    assert facts["legend"] == facts["columns"] == facts["buildings"] == ["A", "B"]


def test_saved_progress_ends_at_the_final_state(notebook):
    nb, widgets = notebook
    facts = _facts(nb.cells[4])
    assert facts["seconds"] > facts["delay"], "the run was too short for a bar to appear"
    bars = [text for text in _shown(nb.cells[3]) if re.search(r"\d+%\|", text)]
    assert len(bars) == 1, f"one bar, at its last state, is kept: {bars}"
    bar = bars[0]
    found = re.search(r"(\d+)%\|.*\| ([\d.]+[kMG]?)/([\d.]+[kMG]?) \[", bar)
    assert found, bar
    assert found.group(1) == "100" and found.group(2) == found.group(3), bar
    total = float(found.group(3).rstrip("kMG")) * {"k": 1e3, "M": 1e6, "G": 1e9}.get(
        found.group(3)[-1], 1)
    assert total == pytest.approx(facts["steps"], rel=0.01)
    outputs = nb.cells[3].outputs
    if widgets:
        assert any("application/vnd.jupyter.widget-view+json" in o.get("data", {})
                   for o in outputs)
    else:  # one text display, no stream of refreshes
        assert not [o for o in outputs if o["output_type"] == "stream"], outputs


def test_a_scene_shows_as_a_table_and_the_summary_names_the_contacts(notebook):
    nb, _ = notebook
    (shown,) = [o for o in nb.cells[5].outputs if o["output_type"] == "execute_result"]
    assert "<table" in shown["data"]["text/html"] and "floor-3" in shown["data"]["text/html"]
    assert shown["data"]["text/plain"].startswith("Scene(")
    facts = _facts(nb.cells[6])
    assert facts["force"] == pytest.approx(facts["peak"], rel=1e-12)  # the envelope is the max
    assert {"story_drift", "story_force"} <= set(facts["loop_columns"])
    assert facts["summary_contacts"] == ["floor-1", "floor-2", "floor-3"]


def test_a_scene_copied_with_numpy_numbers_writes_and_runs():
    """``model_copy(update=...)`` does not validate, so a duration computed with numpy stays
    a numpy float: the scene's YAML (which a run stores in its result) writes it as a
    number, not a yaml RepresenterError (the notebook above met it)."""
    import numpy as np
    import yaml

    import pframe

    scene = pframe.load(REPO / "models" / "wu2021-eq14.yaml")
    copy = scene.model_copy(update={"analysis": scene.analysis.model_copy(
        update={"duration": np.float64(0.5)})})
    again = pframe.load(yaml.safe_load(copy.to_yaml()))
    assert again.analysis.duration == 0.5 and type(again.analysis.duration) is float
