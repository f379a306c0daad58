"""Method files (`--method FILE.toml`): a method's fields as TOML keys, those not given ours.

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
from tvl_cli.core.method import PRESETS, Method, method_from_dict
from tvl_cli.io.tomlfile import read_toml


def read_method(path: Path) -> Method:
    """The method of a TOML file; BadInput naming the file and the key at the first fault."""
    return method_from_dict(read_toml(path, "method"), str(path))


def chosen_method(text: str) -> Method:
    """A preset by name (paper, default), else the method file of that name."""
    if text in PRESETS:
        return PRESETS[text]
    path = Path(text)
    if not path.exists():
        raise BadInput(
            f"--method {text}: neither a preset nor a method file "
            f"({did_you_mean(text, list(PRESETS))})"
        )
    return read_method(path)
