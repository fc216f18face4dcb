"""Write figures to PNG, SVG or PDF.

PDF: one file, one page per figure (floor level). PNG and SVG: one image per figure; when
there are several, ``FIGURE-<level>.png`` beside the name given (``eq14.png`` gives ``eq14-1.png``,
``eq14-2.png``, ...), and the name itself when there is one.
"""

from __future__ import annotations

from pathlib import Path

from pframe import outputs
from pframe.errors import InputError

FORMATS = (".png", ".svg", ".pdf")
#: pixels per inch of PNG images: legible at 100 % on a screen, small enough for docs
PNG_DPI = 100


def output_paths(output: str | Path, levels) -> list[Path]:
    """The files :func:`save` writes for figures of ``levels`` (checks the name and folder)."""
    output = Path(output)
    suffix = output.suffix.lower()
    if suffix not in FORMATS:
        raise InputError(f"{output}: the figure name must end in .png, .svg or .pdf (the "
                         "format is taken from it)")
    if not output.parent.exists():
        raise InputError(f"{output}: the folder {str(output.parent)!r} does not exist")
    if output.is_dir():
        raise InputError(f"{output}: is a folder; give a file name ending in .png, .svg or "
                         ".pdf")
    levels = list(levels)
    if suffix == ".pdf" or len(levels) == 1:
        return [output]
    return [output.with_name(f"{output.stem}-{level}{output.suffix}") for level in levels]


def save(figs: dict, output: str | Path, title: str | None = None, *, overwrite: bool = True,
         inputs=()) -> list[Path]:
    """Write ``level -> Figure`` to ``output`` (.png, .svg or .pdf); existing files are
    replaced only with ``overwrite`` (``pframe plot`` passes its ``--overwrite``), never one
    of ``inputs`` (the result drawn) nor anything but a regular file.

    Parameters
    ----------
    figs : dict
        Figures by level, as :func:`pframe.plot.figures` returns them.
    output : str or Path
        The figure file; its suffix chooses the format (rules in the module docstring).
    title : str, optional
        The document title (PDF, SVG).

    Returns
    -------
    list of Path
        The files written.
    """
    import pframe

    paths = output_paths(output, figs)
    for path in paths:  # every name checked before any is written
        outputs.check_output(path, inputs=inputs, overwrite=overwrite, what="figure")
    if paths[0].suffix.lower() == ".pdf":
        from matplotlib.backends.backend_pdf import PdfPages

        metadata = {"Creator": f"pframe {pframe.__version__} (pframe plot)"}
        if title:
            metadata["Title"] = title
        with outputs.replacing(paths[0]) as tmp, PdfPages(tmp, metadata=metadata) as pdf:
            for fig in figs.values():
                pdf.savefig(fig)
        return paths
    for path, fig in zip(paths, figs.values()):
        kind = path.suffix.lower()[1:]
        options = {"dpi": PNG_DPI} if kind == "png" else {
            "metadata": {"Creator": f"pframe {pframe.__version__} (pframe plot)",
                         **({"Title": title} if title else {})}}
        with outputs.replacing(path) as tmp:
            fig.savefig(tmp, format=kind, **options)
    return paths
