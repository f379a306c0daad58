"""What users look at: GIFs drawn by blitting, the picture of one moment (`tvl explain
--png`), `inspect --png` of any FAM, the walls of the live view, and no window without a
display; through the real command, in-process (CliRunner), on real worlds and files."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle
from matplotlib.text import Text
from matplotlib.transforms import Bbox
from method_samples import LIVE_RING
from PIL import Image
from rich.console import Console

from tvl_cli.cli import main
from tvl_cli.cli.live import LiveView, Sight
from tvl_cli.commands.run import RunRequest, run_fam
from tvl_cli.commands.train import train_from_logs, write_trained
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import MULTI, SINGLE, FamConfig
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.io.famfile import write_fam
from tvl_cli.io.runfile import read_run
from tvl_cli.render import moment
from tvl_cli.render.animate import DPI, FIGURE_SIZE_IN, RAY_COLOUR, Window, _TraceFrame, animate_run
from tvl_cli.render.blit import inks
from tvl_cli.render.formats import save_picture
from tvl_cli.sim.worldmap import load_world

ROOT = Path(__file__).resolve().parents[2]
SQUARE = ROOT / "worlds" / "square.txt"
OBSTACLES = ROOT / "worlds" / "obstacles.txt"


@pytest.fixture(scope="module")
def ran(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A FAM from the example log's first minutes, and a trace of it avoiding in the
    square: it chooses, spins to face what it chose, and drives."""
    return _trained_and_ran(tmp_path_factory.mktemp("pictures"), SINGLE)


def _trained_and_ran(directory: Path, config: FamConfig) -> dict[str, Path]:
    """A FAM of `config` from the example log's first 3 minutes, and 18 s of it avoiding."""
    trained = train_from_logs([ROOT / "logs" / "square-s1.h5"], config, until_minute=3)
    fam = directory / "fam.h5"
    write_trained(fam, trained)
    trace = directory / "run.h5"
    run_fam(RunRequest(fam, SQUARE, "avoid", 0.85, 0.3, seed=1, trace=trace))
    return {"fam": fam, "trace": trace}


def tvl(*args: str | Path) -> tuple[int, str, str]:
    done = CliRunner().invoke(main, [str(a) for a in args], prog_name="tvl")
    return done.exit_code, done.stdout, done.stderr


def test_a_blitted_frame_is_the_whole_figure_drawn(ran: dict[str, Path]) -> None:
    trace = read_run(ran["trace"])
    frame = _TraceFrame(trace, RobotConfig.from_dict(trace.robot_config))
    blitted = frame.draw(120).astype(int)
    for artist in frame.blitter.moving:
        artist.set_animated(False)
    frame.blitter.canvas.draw()
    whole = np.asarray(frame.blitter.canvas.buffer_rgba())[..., :3].astype(int)
    # Only where two moving parts cross may the order they are drawn in tell.
    differs = np.abs(blitted - whole).sum(axis=-1) > 32
    assert differs.mean() < 1e-3


@pytest.mark.slow
def test_a_gif_keeps_its_inks_and_tells_its_progress(ran: dict[str, Path], tmp_path: Path):
    gif, told = tmp_path / "run.gif", []
    frames = animate_run(
        read_run(ran["trace"]),
        gif,
        Window(every=30),
        on_frame=lambda done, total: told.append((done, total)),
    )
    assert frames == 6 and told == [(k, 6) for k in range(1, 7)]
    with Image.open(gif) as image:
        assert image.n_frames == 6
        assert image.size == tuple(round(side * DPI) for side in FIGURE_SIZE_IN)
        image.seek(3)
        colours = {rgb for _, rgb in image.convert("RGB").getcolors(1 << 16)}
    # An echo's ray in its own red, not in the nearest colour of the still background.
    assert tuple(inks(RAY_COLOUR)[0]) in colours


@pytest.mark.slow
def test_replay_draws_a_gif_in_process(ran: dict[str, Path], tmp_path: Path) -> None:
    gif = tmp_path / "r.gif"
    code, _, err = tvl("replay", ran["trace"], "--gif", gif, "--to", "6", "--every", "4")
    assert code == 0, err
    assert err == ""  # no progress bar where stderr is no terminal
    with Image.open(gif) as image:
        assert image.n_frames == 15  # steps 0 to 59, every fourth


def _spin_step(trace_path: Path) -> int:
    """A step that carried out a decision made before it: no ring read, nothing perceived."""
    arrays = read_run(trace_path).arrays
    undecided = ~arrays["ring_mm"].any(axis=1) | np.isnan(arrays["velocities"]).all(axis=1)
    return int(np.flatnonzero(undecided)[0])


def test_at_a_step_that_decided_nothing_explains_the_nearest_that_did(
    ran: dict[str, Path],
) -> None:
    trace = read_run(ran["trace"])
    spin = _spin_step(ran["trace"])
    at = f"{(spin + 1) * trace.period_s:.1f}"
    code, out, err = tvl("explain", ran["trace"], "--at", at, "--json")
    assert code == 0, err
    explained = json.loads(out)["step"]
    decided = trace.arrays["ring_mm"].any(axis=1) & ~np.isnan(trace.arrays["velocities"]).all(1)
    nearest = np.flatnonzero(decided)[np.argmin(np.abs(np.flatnonzero(decided) - spin))]
    assert explained["step"] == nearest and explained["why"]["rules"]
    assert err.startswith(f"step {spin} (ending at {at} s) made no decision")
    assert err.rstrip().endswith(
        f"explaining step {nearest} (ending at {(nearest + 1) / 10:.1f} s), the nearest that did"
    )
    # --step means that step, decision or not.
    code, out, err = tvl("explain", ran["trace"], "--step", str(spin), "--json")
    assert code == 0 and json.loads(out)["step"]["step"] == spin and err == ""


@pytest.mark.slow  # over a second
def test_explain_draws_the_moment(ran: dict[str, Path], tmp_path: Path) -> None:
    png = tmp_path / "moment.png"
    code, out, err = tvl("explain", ran["trace"], "--step", "24", "--png", png)
    assert code == 0, err
    assert "rules that fire" in out
    with Image.open(png) as image:
        assert image.format == "PNG" and image.width > image.height > 500
        colours = {rgb for _, rgb in image.convert("RGB").getcolors(1 << 20)}
    assert tuple(inks(RAY_COLOUR)[0]) in colours  # the rays
    code, _, err = tvl("explain", ran["trace"], "--step", "24", "--png", png)
    assert code == 2 and "already exists" in err
    code, _, err = tvl("explain", ran["trace"], "--contacts", "--png", tmp_path / "c.png")
    assert code == 2 and "--png draws one moment" in err
    # In the format its name's extension says.
    svg = tmp_path / "moment.svg"
    assert tvl("explain", ran["trace"], "--step", "24", "--png", svg)[0] == 0
    assert b"<svg" in svg.read_bytes()[:400]
    code, _, err = tvl("explain", ran["trace"], "--step", "24", "--png", tmp_path / "m.bmp")
    assert code == 2 and ".bmp is no picture format tvl writes" in err


def _moment(
    ran: dict[str, Path], step: int, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> Figure:
    """The figure `tvl explain --step STEP --png` saves, laid out as it was saved."""
    saved: list[Figure] = []

    def keep(figure: Figure, path: Path, **options: Any) -> None:
        saved.append(figure)
        save_picture(figure, path, **options)

    monkeypatch.setattr(moment, "save_picture", keep)
    code, _, err = tvl("explain", ran["trace"], "--step", step, "--png", tmp_path / f"{step}.png")
    assert code == 0, err
    (figure,) = saved
    figure.canvas.draw()
    return figure


def _boxes(texts: list[Text], figure: Figure) -> list[Bbox]:
    """Where each text is drawn, with the box drawn behind it if any."""
    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    return [
        Bbox.union([text.get_window_extent(renderer), *_behind(text, renderer)]) for text in texts
    ]


def _behind(text: Text, renderer: Any) -> list[Bbox]:
    patch = text.get_bbox_patch()
    return [] if patch is None else [patch.get_window_extent(renderer)]


def _apart(boxes: list[Bbox]) -> bool:
    return not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])


def _inside(boxes: list[Bbox], ax: Axes) -> bool:
    frame = ax.bbox
    return all(
        frame.x0 <= b.x0 and b.x1 <= frame.x1 and frame.y0 <= b.y0 and b.y1 <= frame.y1
        for b in boxes
    )


@pytest.mark.slow  # over a second
@pytest.mark.parametrize("step", [0, 24, 60, 120, 170])
def test_the_moment_names_each_trajectory_apart_and_writes_each_rule_within_its_panel(
    ran: dict[str, Path], step: int, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    figure = _moment(ran, step, tmp_path, monkeypatch)
    world_ax, _, rules_ax = figure.axes[:3]
    trajectories = {t.name for t in RobotConfig().trajectories}
    named = _boxes([t for t in world_ax.texts if t.get_text() in trajectories], figure)
    perceived = read_run(ran["trace"]).arrays["velocities"][step]
    assert len(named) == np.isfinite(perceived).sum() > 0
    assert _apart(named) and _inside(named, world_ax)
    rules = _boxes([t for t in rules_ax.texts if t.get_text().startswith("IF ")], figure)
    assert rules and _apart(rules) and _inside(rules, rules_ax)


@pytest.fixture(scope="module")
def ran_multi(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A multi FAM, whose rules read seven sonars (long sentences), and a trace of it."""
    return _trained_and_ran(tmp_path_factory.mktemp("multi-pictures"), MULTI)


@pytest.mark.slow  # trains a multi FAM and draws three moments
@pytest.mark.parametrize("step", [0, 100, 160])
def test_a_multi_fams_long_rules_fold_within_their_panel_as_saved(
    ran_multi: dict[str, Path], step: int, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    figure = _moment(ran_multi, step, tmp_path, monkeypatch)
    assert figure.dpi == moment.MOMENT_DPI  # laid out as it is saved
    rules_ax = figure.axes[2]
    sentences = [t for t in rules_ax.texts if t.get_text().startswith("IF ")]
    assert any("\n" in t.get_text() for t in sentences)  # too long for one line
    assert _inside(_boxes(sentences, figure), rules_ax)


def _start_marks(ax: Axes, robot: RobotConfig) -> tuple[int, list[Line2D]]:
    """How many robot-sized circles an axes draws, and the lines marking a start."""
    bodies = [p for p in ax.patches if isinstance(p, Circle) and p.radius == robot.radius_m]
    return len(bodies), [line for line in ax.lines if line.get_label() == "start"]


@pytest.mark.slow  # over a second
def test_the_start_is_a_small_mark_and_the_robot_is_drawn_once_in_a_moment_and_a_replay(
    ran: dict[str, Path], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    trace = read_run(ran["trace"])
    robot = RobotConfig.from_dict(trace.robot_config)
    start = load_world(SQUARE).start
    explained = _moment(ran, 20, tmp_path, monkeypatch).axes[0]
    replayed = _TraceFrame(trace, robot).frame.artists.world_ax
    marks = []
    for ax in (explained, replayed):
        bodies, (mark,) = _start_marks(ax, robot)
        assert bodies == 1  # the robot itself, and no second one standing at the start
        assert (mark.get_xdata()[0], mark.get_ydata()[0]) == pytest.approx(start[:2])
        # Smaller than the robot's body drawn there.
        scale_pt = ax.transData.transform((1.0, 0.0))[0] - ax.transData.transform((0.0, 0.0))[0]
        body_pt = 2 * robot.radius_m * scale_pt * 72.0 / ax.figure.dpi
        assert mark.get_markersize() < body_pt / 2
        marks.append((mark.get_marker(), mark.get_markersize(), mark.get_markeredgecolor()))
    assert marks[0] == marks[1]  # drawn alike in both


@pytest.mark.slow  # over a second
def test_inspect_draws_a_multi_fam_over_inputs_its_tables_have(tmp_path: Path) -> None:
    fam = tmp_path / "multi.h5"
    robot = RobotConfig()
    write_fam(fam, Fam(MULTI, [t.name for t in robot.trajectories]), robot_config=robot,
              method=LIVE_RING,
              provenance={})  # fmt: skip
    png = tmp_path / "m.png"
    code, _, err = tvl("inspect", fam, "--png", png, "--top", "1")
    assert code == 0, err
    assert png.read_bytes().startswith(b"\x89PNG")


def test_the_live_view_draws_the_walls_around_the_obstacles() -> None:
    view = LiveView(Sight(load_world(OBSTACLES), RobotConfig(), 0.85))
    console = Console(record=True, width=80, height=24, color_system=None)
    console.print(view.panel())
    lines = console.export_text().splitlines()[: view.rows]
    columns = view.columns
    rows = [line[:columns] for line in lines]
    assert rows[0] == rows[-1] == "#" * columns  # the walls north and south
    assert all(row[0] == row[-1] == "#" for row in rows)  # west and east
    assert all(row[1] == " " for row in rows[1:-1])  # the floor inside them


def test_a_window_without_a_display_is_one_line_and_exit_1(
    ran: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    code, out, err = tvl("run", ran["fam"], SQUARE, "--behaviour", "avoid", "--minutes",
                         "0.05", "--view", "window")  # fmt: skip
    assert code == 1 and out == ""
    assert err == (
        "tvl: error: no display to open a window on ($DISPLAY is not set); use --live to "
        "watch in the terminal\n"
    )
    code, _, err = tvl("run", ran["fam"], SQUARE, "--behaviour", "avoid", "--live", "--view",
                       "window")  # fmt: skip
    assert code == 2 and "give --live or --view, not both" in err


def test_a_window_on_a_display_nobody_answers_is_one_line_and_exit_1(
    ran: dict[str, Path], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("DISPLAY", ":77")  # no display server there
    code, out, err = tvl("run", ran["fam"], SQUARE, "--behaviour", "avoid", "--minutes",
                         "0.05", "--view", "window")  # fmt: skip
    assert code == 1 and out == "" and err.count("\n") == 1
    assert err.startswith("tvl: error: no window opens on :77: matplotlib's backend is agg")
