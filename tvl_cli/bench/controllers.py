"""What a user scores beside ours: `--controller [NAME=]SPEC`, where SPEC is

- a method: a preset (`paper`, `default`) or a method file (`FILE.toml`), learnt in each world
  and trial and trained into each configuration, as ours is;
- a FAM file (`FILE.h5`), learnt elsewhere: run in each world as it is;
- a Gymnasium policy (`MODULE:CALLABLE` or `FILE.py:CALLABLE`) taking what `tvl/SonarRing-v0`
  observes;
- a saved Stable-Baselines3 model (`ALGORITHM:FILE.zip`, e.g. `PPO:ppo.zip`).

Each is checked here, before any cell runs: a bad one is one line, and nothing is written.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from tvl_cli.commands.run import run_robot
from tvl_cli.core.errors import BadInput
from tvl_cli.core.method import PRESETS, Method
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.logreader import file_sha256
from tvl_cli.io.methodfile import resolve_method

METHOD, FAM, POLICY, MODEL = "method", "fam", "policy", "model"
GYM_EXTRA = "pip install 'tvl[gym]'"
FORMS = (
    "a method (paper, default or FILE.toml), a FAM file (FILE.h5), a Gymnasium policy "
    "(MODULE:CALLABLE or FILE.py:CALLABLE) or a Stable-Baselines3 model (ALGORITHM:FILE.zip)"
)


@dataclass(frozen=True, slots=True)
class Controller:
    name: str  # its rows' entry
    kind: str  # METHOD, FAM, POLICY or MODEL
    spec: str  # as the cells take it: files made absolute
    method: Method | None = None  # a method's
    # The file it is read from (a FAM, a model, a policy's FILE.py), as (absolute path,
    # SHA-256) when the bench found it: its cells are known by the digest, so that a file
    # made again at the same path runs again rather than reading back the old one's rows.
    source: tuple[str, str] | None = None

    @property
    def label(self) -> str:
        """What it is, for people."""
        shown = {METHOD: "method", FAM: "FAM file", POLICY: "policy", MODEL: "model"}
        return f"{shown[self.kind]} {self.spec}"


def parse_controller(text: str) -> Controller:
    """A `--controller` as given, checked; BadInput naming it and what is wrong."""
    name, equals, spec = text.partition("=")
    if not equals or "/" in name or ":" in name:
        name, spec = "", text
    if not spec:
        raise BadInput(f"--controller {text!r}: give [NAME=]SPEC, SPEC {FORMS}")
    if spec in PRESETS or spec.endswith(".toml"):
        method = resolve_method(spec, label="--controller")
        return Controller(name or Path(spec).stem, METHOD, spec, method)
    if spec.endswith(".h5"):
        path = Path(spec).absolute()
        fam_file = read_fam(path)  # FormatError naming the file
        run_robot(fam_file.robot_config, None, path, DEFAULT_ROBOT)  # the benchmark robot only
        return Controller(name or path.stem, FAM, str(path), source=_source(path))
    if ":" in spec:
        return _gym(name, spec)
    raise BadInput(f"--controller {text!r}: not {FORMS}")


def _gym(name: str, spec: str) -> Controller:
    """A policy or a model, loaded once here to be refused before anything runs."""
    prefix, _, rest = spec.partition(":")
    read_from = None  # a module's policy: installed, no file of its own to know it by
    if rest.endswith(".zip"):
        read_from = Path(rest).absolute()
        spec = f"{prefix}:{read_from}"
    elif prefix.endswith(".py"):
        read_from = Path(prefix).absolute()
        spec = f"{read_from}:{rest}"
    try:
        from tvl_cli.gym.scoring import is_model_spec, load_controller
    except ImportError:
        raise BadInput(f"--controller {spec}: a policy needs Gymnasium ({GYM_EXTRA})") from None
    load_controller(spec)
    kind = MODEL if is_model_spec(spec) else POLICY
    fallback = Path(rest).stem if kind == MODEL else rest.rsplit(".", 1)[-1]
    source = _source(read_from) if read_from is not None else None
    return Controller(name or fallback, kind, spec, source=source)


def _source(path: Path) -> tuple[str, str]:
    return (str(path), file_sha256(path))
