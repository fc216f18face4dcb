"""Progress of runs and sweeps, drawn by tqdm on a terminal and in a notebook.

tqdm rather than rich: it imports in a few tens of milliseconds (rich.progress several times
that), draws a widget in Jupyter through ``tqdm.auto`` and a text bar elsewhere, sizes the bar
to the terminal on every refresh (``dynamic_ncols``), and is silent when told to be. A bar
appears only once a run has lasted ``DELAY`` seconds: short runs print nothing.

``show``: True draws, False stays silent, None (the default) draws when the output is a
terminal or a notebook, and stays silent otherwise (logs, pipes, CI).
"""

from __future__ import annotations

import sys
import time

#: seconds a run must last before its bar appears
DELAY = 1.0


def in_notebook() -> bool:
    """True inside a Jupyter kernel (IPython with a ZMQ shell)."""
    shell = sys.modules.get("IPython")
    if shell is None:
        return False
    try:
        return type(shell.get_ipython()).__name__ == "ZMQInteractiveShell"
    except Exception:
        return False


def wanted(show: bool | None, stream=None) -> bool:
    if show is not None:
        return bool(show)
    stream = sys.stderr if stream is None else stream
    return in_notebook() or bool(getattr(stream, "isatty", lambda: False)())


def _widget_bar(**kwargs):
    """A notebook widget bar that pframe displays itself (None without ipywidgets)."""
    try:
        # without ipywidgets tqdm's notebook bar fails half-built, and its destructor then
        # prints a traceback into the cell's output: it is not made at all
        import ipywidgets  # noqa: F401
    except ImportError:
        return None
    try:
        from tqdm.notebook import tqdm as notebook_tqdm

        widget = notebook_tqdm(display=False, delay=0, leave=True, **kwargs)
    except ImportError:  # ipywidgets too old or broken: tqdm says "IProgress not found"
        return None
    return widget if hasattr(widget, "container") else None


class _DisplayedText:
    """A file for a tqdm text bar in a notebook without ipywidgets: each state the bar writes
    replaces one text display (shown once the bar first draws, updated by its display id),
    so the cell keeps one line, the bar's last state, not one stream output per refresh
    (which renderers that do not interpret carriage returns show all of, and a saved
    notebook keeps)."""

    encoding = "utf-8"  # tqdm draws the bar in block characters, not '#'

    def __init__(self):
        self.handle = None
        self.text = ""

    def write(self, text: str) -> int:
        state = text.rsplit("\r", 1)[-1].strip("\n")
        if state.strip():
            self.text = state
            from IPython.display import display

            shown = {"text/plain": state}
            if self.handle is None:
                self.handle = display(shown, raw=True, display_id=True)
            else:
                self.handle.update(shown, raw=True)
        return len(text)

    def flush(self) -> None:
        pass


class Bar:
    """A progress callback ``bar(done, total[, failed])`` that draws once the run has lasted
    :data:`DELAY` seconds; ``unit``: what is counted (steps, variants). The bar shows the
    elapsed time, the rate and an estimate of the time left.

    In a notebook the bar is kept when the run ends, at its final state: a widget is
    displayed with a display id and its display updated on :meth:`close`, so the saved
    notebook (whose text form of a widget is the one last sent) ends at 100 %, not at the
    state when it first appeared; without ipywidgets a text bar is drawn into one text
    display, updated in place, so the cell keeps one line: the bar's last state.
    On a terminal the bar is cleared when the run ends (the command prints a summary)."""

    def __init__(self, unit: str, description: str = "", stream=None):
        self.unit = unit
        self.description = description
        self.stream = sys.stderr if stream is None else stream
        self.bar = None
        self.last = 0
        self.handle = None  # the notebook display of a widget bar
        self.widget = False
        self.started = 0.0

    def _make(self, done: int, total: int):
        kwargs = {"total": total, "initial": done, "unit": f" {self.unit}", "unit_scale": True,
                  "desc": self.description or None, "dynamic_ncols": True, "smoothing": 0.1}
        notebook = in_notebook()
        if notebook:
            widget = _widget_bar(**kwargs)
            if widget is not None:
                self.widget = True
                return widget
        from tqdm import tqdm

        if notebook and self.stream is sys.stderr:  # a text bar as one display, kept updated
            kwargs.update(dynamic_ncols=False, ncols=100)
            return tqdm(file=_DisplayedText(), delay=DELAY, leave=True, **kwargs)
        return tqdm(file=self.stream, delay=DELAY, leave=notebook, **kwargs)

    def __call__(self, done: int, total: int, failed: int = 0) -> None:
        if self.bar is None:
            self.started = time.monotonic()
            self.bar = self._make(done, total)
            self.last = done
            return
        if failed:
            self.bar.set_postfix_str(f"{failed} failed", refresh=False)
        self.bar.update(done - self.last)
        self.last = done
        if self.widget and self.handle is None and time.monotonic() - self.started >= DELAY:
            from IPython.display import display

            self.handle = display(self.bar.container, display_id=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            if self.handle is not None:  # the saved output: the final state
                self.handle.update(self.bar.container)
            self.bar = None
            self.handle = None


def bar(show: bool | None, unit: str, description: str = "", stream=None) -> Bar | None:
    """A :class:`Bar`, or None when nothing is to be drawn (see the module docstring)."""
    return Bar(unit, description, stream) if wanted(show, stream) else None
