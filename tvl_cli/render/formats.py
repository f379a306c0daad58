"""The picture formats an output's extension names, and writing a figure in one.

Kept apart from the drawing modules, and importing matplotlib only to write, so that the
command line can refuse a picture's name before any work without loading matplotlib.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from tvl_cli.core.errors import BadInput
from tvl_cli.io.atomic import atomic_output

if TYPE_CHECKING:
    from matplotlib.figure import Figure

# Extension -> the format matplotlib's savefig writes for it.
PICTURE_FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf", ".jpg": "jpeg", ".jpeg": "jpeg"}
# What savefig would otherwise stamp into a vector picture: the time it was written (and, in
# an SVG, random ids), so that the same inputs draw the same bytes.
_NO_DATE = {"svg": {"Date": None}, "pdf": {"CreationDate": None}}
_SVG_ID_SALT = "tvl"


def picture_format(path: Path | str) -> str:
    """The format the extension of `path` names; BadInput naming the ones there are."""
    extension = Path(path).suffix.lower()
    if extension not in PICTURE_FORMATS:
        problem = (
            f"{extension} is no picture format tvl writes"
            if extension
            else "no extension names its picture format"
        )
        raise BadInput(f"{path}: {problem} (give {', '.join(PICTURE_FORMATS)})")
    return PICTURE_FORMATS[extension]


def refuse_other_extension(path: Path | str, *extensions: str, kind: str = "") -> None:
    """An output of one fixed format (an animation, a log, a trace) is named for it by one
    of `extensions` (the first the usual one), so that its name does not promise another.
    `kind` names the format where its extension does not (HDF5 for .h5)."""
    if Path(path).suffix.lower() not in extensions:
        written = kind or extensions[0]
        named = " or ".join(extensions)
        raise BadInput(f"{path}: it is written as {written}; give it the extension {named}")


def save_picture(figure: Figure, path: Path | str, **savefig_options: Any) -> None:
    """Write `figure` to `path`, whole or not at all, in the format its extension names."""
    import matplotlib  # loaded already by whoever drew the figure

    form = picture_format(path)
    with matplotlib.rc_context({"svg.hashsalt": _SVG_ID_SALT}), atomic_output(path) as temporary:
        figure.savefig(temporary, format=form, metadata=_NO_DATE.get(form), **savefig_options)
