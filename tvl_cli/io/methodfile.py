"""Method files (`--method FILE.toml`): a method's fields as TOML keys, those not given ours
(and so the echo memory's settings a file's `memory` leaves out); and the one resolver of a
method as a user names it: a preset, a file, or a Method.

# The paper's method, remembering echoes as patches.
decel_mps2 = 0.2
margin_m = 0.05
near_m = 0.0                    # collision points at bumps alone
exploration = "least-experience"
reflexes = []                   # or "all", "none", ["bump", "tie"]
memory = { kind = "patches", window_s = 20.0 }
"""

from __future__ import annotations

from pathlib import Path

from tvl_cli.core.errors import BadInput, did_you_mean
from tvl_cli.core.method import DEFAULT, PRESETS, Method, method_from_dict
from tvl_cli.io.tomlfile import read_toml


def read_method(path: Path) -> Method:
    """The method of a TOML file; BadInput naming the file and the key at the first fault."""
    # A memory the file names takes ours for each setting it leaves out, as the method takes
    # ours for each field. (A memory recorded in a log or FAM without a clearing was made
    # before clearing was a choice, and so never cleared: core.memory.)
    return method_from_dict(read_toml(path, "method"), str(path), memory_omitted=DEFAULT.memory)


def resolve_method(
    named: Method | str | Path, folder: Path | None = None, label: str = ""
) -> Method:
    """The method a user names, for the command line, a sweep's grid and the Gymnasium
    environment alike: a Method as given; a preset by name (paper, default); else the method
    file at that path (relative to `folder` where given: a grid's). BadInput, led by `label`
    (the option or key that named it), for a name that is neither."""
    if isinstance(named, Method):
        return named
    if isinstance(named, str) and named in PRESETS:
        return PRESETS[named]
    path = Path(named) if folder is None else folder / named
    if not path.is_file():
        lead = f"{label} {named}" if label else f"method {str(named)!r}"
        raise BadInput(
            f"{lead}: neither a preset ({', '.join(PRESETS)}) nor a method file "
            f"({did_you_mean(str(named), list(PRESETS))})"
        )
    return read_method(path)
