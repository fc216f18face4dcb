"""Progress bars (pframe.progress): elapsed time and an estimate while a run lasts; in a
notebook the output ends at the final state (a saved notebook shows 100 %, not the state the
bar had when it first appeared); on a terminal the bar is cleared at the end."""

from __future__ import annotations

import io
import re
import sys
import time
import types

import pytest

from pframe import progress


class _Stream(io.StringIO):
    def isatty(self):
        return True


def _run(bar, total=400, step=100):
    for done in range(0, total + 1, step):
        bar(done, total)
        time.sleep(0.11)  # longer than tqdm's refresh interval: every state is drawn
    bar.close()


def _screen(text: str) -> str:
    """What a terminal or a notebook's text output shows last: the text after the last
    carriage return of each line."""
    text = text.replace("\x1b[A", "")
    return "\n".join(line.split("\r")[-1] for line in text.split("\n"))


def test_a_text_bar_shows_elapsed_time_rate_and_estimate(monkeypatch):
    monkeypatch.setattr(progress, "DELAY", 0.0)
    stream = _Stream()
    bar = progress.Bar("steps", "scene.yaml", stream)
    bar(0, 400)
    time.sleep(0.11)
    bar(100, 400)
    text = stream.getvalue().split("\r")[-1]
    # e.g. "scene.yaml:  25%|██▌       | 100/400 [00:00<00:00, 1.2e+05 steps/s]"
    assert re.search(r"25%.*100/400 \[\d\d:\d\d<\d\d:\d\d, .* steps/s\]", text), text
    bar.close()


@pytest.mark.slow
def test_on_a_terminal_the_bar_is_cleared_at_the_end(monkeypatch):
    monkeypatch.setattr(progress, "DELAY", 0.0)
    stream = _Stream()
    _run(progress.Bar("steps", "run", stream))
    assert _screen(stream.getvalue()).strip() == ""


@pytest.mark.slow
def test_in_a_notebook_without_widgets_the_text_ends_at_the_final_state(monkeypatch):
    monkeypatch.setattr(progress, "DELAY", 0.0)
    monkeypatch.setattr(progress, "in_notebook", lambda: True)
    monkeypatch.setattr(progress, "_widget_bar", lambda **kwargs: None)
    stream = _Stream()
    _run(progress.Bar("steps", "run", stream))
    last = [line for line in _screen(stream.getvalue()).splitlines() if line.strip()][-1]
    assert "100%" in last and "400/400" in last, last


@pytest.mark.slow
def test_in_a_notebook_the_widget_display_is_updated_to_the_final_state(monkeypatch):
    """The widget is displayed with a display id once the run lasts DELAY, and that display
    is updated when the run ends: what a saved notebook keeps is the final state."""
    shown = []

    class Handle:
        def update(self, obj):
            shown.append(("update", repr(obj)))

    def display(obj, display_id=False):
        assert display_id is True
        shown.append(("display", repr(obj)))
        return Handle()

    class Container:
        def __init__(self, bar):
            self.bar = bar

        def __repr__(self):
            return f"{self.bar.n}/{self.bar.total}"

    class Widget:
        def __init__(self, total, initial, **kwargs):
            self.n, self.total = initial, total
            self.container = Container(self)

        def update(self, n):
            self.n += n

        def set_postfix_str(self, *args, **kwargs):
            pass

        def close(self):
            pass

    ipython = types.ModuleType("IPython")
    ipython.display = types.ModuleType("IPython.display")
    ipython.display.display = display
    monkeypatch.setitem(sys.modules, "IPython", ipython)
    monkeypatch.setitem(sys.modules, "IPython.display", ipython.display)
    monkeypatch.setattr(progress, "DELAY", 0.0)
    monkeypatch.setattr(progress, "in_notebook", lambda: True)
    monkeypatch.setattr(progress, "_widget_bar", lambda **kwargs: Widget(**kwargs))
    _run(progress.Bar("steps", "run"))
    assert shown[0] == ("display", "100/400") and shown[-1] == ("update", "400/400")


@pytest.mark.parametrize("show", [False])
def test_silent_when_told(show):
    assert progress.bar(show, "steps") is None
