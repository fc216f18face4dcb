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


def _bar_class():
    if in_notebook():
        from tqdm.auto import tqdm
    else:
        from tqdm import tqdm
    return tqdm


class Bar:
    """A progress callback ``bar(done, total[, failed])`` that draws once the run has lasted
    :data:`DELAY` seconds; ``unit``: what is counted (steps, variants)."""

    def __init__(self, unit: str, description: str = "", stream=None):
        self.unit = unit
        self.description = description
        self.stream = sys.stderr if stream is None else stream
        self.bar = None
        self.last = 0

    def __call__(self, done: int, total: int, failed: int = 0) -> None:
        if self.bar is None:
            tqdm = _bar_class()
            self.bar = tqdm(total=total, initial=done, unit=f" {self.unit}", unit_scale=True,
                            desc=self.description or None, file=self.stream, delay=DELAY,
                            dynamic_ncols=True, leave=False, smoothing=0.1)
            self.last = done
            return
        if failed:
            self.bar.set_postfix_str(f"{failed} failed", refresh=False)
        self.bar.update(done - self.last)
        self.last = done

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def bar(show: bool | None, unit: str, description: str = "", stream=None) -> Bar | None:
    """A :class:`Bar`, or None when nothing is to be drawn (see the module docstring)."""
    return Bar(unit, description, stream) if wanted(show, stream) else None
