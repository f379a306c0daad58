"""`tvl run`, the baselines and `tvl world show|render|export` take a world as `tvl learn`
does: a file, a generated world (KIND:SEED) or a bundled world's name. The world made from a
name drives, shows and exports exactly as the same world written to a file does, and a
document records it by its name and the digest of its text."""

from __future__ import annotations

import hashlib
import subprocess
from collections.abc import Callable
from pathlib import Path

import pytest
from conftest import invoke
from json_schemas import valid

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE_LOG = ROOT / "logs" / "square-s1.h5"
Tvl = Callable[..., subprocess.CompletedProcess[str]]
SEED = "4321"  # a rooms world of neither benchmark set


@pytest.fixture(scope="module")
def fam(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("fam") / "single.h5"
    done = invoke("train", EXAMPLE_LOG, "-o", path)
    assert done.returncode == 0, done.stderr
    return path


@pytest.fixture(scope="module")
def written(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The rooms world of SEED written to a file by `tvl world new`."""
    path = tmp_path_factory.mktemp("world") / "rooms.txt"
    done = invoke("world", "new", "rooms", "--seed", SEED, "-o", path)
    assert done.returncode == 0, done.stderr
    return path


def _metrics(document: dict[str, object]) -> dict[str, object]:
    return {k: v for k, v in document.items() if k not in ("inputs", "outputs", "tvl_version")}


def test_a_generated_world_runs_as_its_file_does(invoke_tvl: Tvl, fam: Path, written: Path) -> None:
    args = ("--behaviour", "avoid", "--minutes", "0.3", "--seed", "2", "--json")
    named = valid("run", invoke_tvl("run", fam, f"rooms:{SEED}", *args).stdout)
    filed = valid("run", invoke_tvl("run", fam, written, *args).stdout)
    assert named["sim_s"] > 0 and _metrics(named) == _metrics(filed)
    # Recorded by the name of the world made and the digest of its text: the file's bytes.
    digest = hashlib.sha256(written.read_bytes()).hexdigest()
    assert named["inputs"]["world"] == {"path": f"rooms-s{SEED}", "sha256": digest}
    assert filed["inputs"]["world"] == {"path": str(written), "sha256": digest}


def test_a_bundled_world_runs_by_its_name(invoke_tvl: Tvl, fam: Path) -> None:
    done = invoke_tvl("run", fam, "square", "--behaviour", "avoid", "--minutes", "0.2", "--json")
    assert done.returncode == 0, done.stderr
    assert Path(valid("run", done.stdout)["inputs"]["world"]["path"]).name == "square.txt"


def test_a_baseline_takes_a_generated_world(invoke_tvl: Tvl, written: Path) -> None:
    args = ("--minutes", "0.2", "--json")
    named = valid("baseline dwa", invoke_tvl("baseline", "dwa", f"rooms:{SEED}", *args).stdout)
    filed = valid("baseline dwa", invoke_tvl("baseline", "dwa", written, *args).stdout)
    assert _metrics(named) == _metrics(filed)


@pytest.mark.parametrize(
    ("world", "message"),
    [
        ("rooms:1-3", "world 'rooms:1-3': 3 worlds; name one (KIND:SEED)"),
        ("nowhere.txt", "world 'nowhere.txt': no such world file nowhere.txt"),
        ("hills:3", "world 'hills:3': no world kind 'hills'"),
    ],
)
def test_a_world_named_wrongly_is_one_line_and_exit_2(
    invoke_tvl: Tvl, fam: Path, world: str, message: str
) -> None:
    for command in (("run", fam, world, "--behaviour", "avoid"), ("baseline", "dwa", world)):
        done = invoke_tvl(*command)
        assert done.returncode == 2, done.stdout
        assert done.stderr.startswith(f"tvl: error: {message}"), done.stderr
        assert done.stderr.count("\n") == 1


def test_world_show_render_and_export_take_a_generated_world(
    invoke_tvl: Tvl, written: Path, tmp_path: Path
) -> None:
    named = valid("world show", invoke_tvl("world", "show", f"rooms:{SEED}", "--json").stdout)
    filed = valid("world show", invoke_tvl("world", "show", written, "--json").stdout)
    assert named["world"] == filed["world"]
    assert named["inputs"]["world"]["sha256"] == filed["inputs"]["world"]["sha256"]
    drawn = invoke_tvl("world", "render", f"rooms:{SEED}", "-o", tmp_path / "rooms.png")
    assert drawn.returncode == 0, drawn.stderr
    assert (tmp_path / "rooms.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for world, out in ((f"rooms:{SEED}", "named.yaml"), (written, "filed.yaml")):
        done = invoke_tvl("world", "export", world, "-o", tmp_path / out)
        assert done.returncode == 0, done.stderr
    pgm = tmp_path / "named.pgm"
    assert pgm.read_bytes() == (tmp_path / "filed.pgm").read_bytes() and pgm.stat().st_size
