"""Learning logs damaged after they were written: refused on opening, in one line, by both
`tvl train` and the `tvl learn` that would append to them, and left as they were."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import invoke
from test_bad_numbers import SQUARE, assert_one_line_refusal


@pytest.fixture(scope="module")
def good_log(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("log") / "log.h5"
    assert invoke("learn", SQUARE, "--log", path, "--minutes", "1").returncode == 0
    return path


def delete_ring(f: h5py.File) -> None:
    del f["sessions/0000/ring_mm"]


def sessions_as_a_dataset(f: h5py.File) -> None:
    del f["sessions"]
    f["sessions"] = np.zeros(3)


def negative_episode_count(f: h5py.File) -> None:
    table = f["sessions/0000/episodes"]
    row = table[1]
    row["count"] = -5
    table[1] = row


def float_ring(f: h5py.File) -> None:
    group = f["sessions/0000"]
    rings = group["ring_mm"][:].astype(np.float64)
    rings[0, 0] = np.nan
    del group["ring_mm"]
    group["ring_mm"] = rings


def replace(f: h5py.File, name: str, values: np.ndarray) -> None:
    del f[name]
    f[name] = values


def nan_pose(f: h5py.File) -> None:
    pose = f["sessions/0000/pose"][:]
    pose[3, 0] = np.nan
    replace(f, "sessions/0000/pose", pose)


def flat_pose(f: h5py.File) -> None:
    replace(f, "sessions/0000/pose", f["sessions/0000/pose"][:].ravel())


def infinite_episode_end(f: h5py.File) -> None:
    table = f["sessions/0000/episodes"]
    row = table[0]
    row["end_arc_m"] = np.inf
    table[0] = row


def narrow_minutes(f: h5py.File) -> None:
    group = f["sessions/0000"]
    replace(f, "sessions/0000/minutes", group["minutes"][:, :2].copy())


def robot_without_size(f: h5py.File) -> None:
    group = f["sessions/0000"]
    text = group.attrs["robot_config"]
    group.attrs["robot_config"] = text.replace('"radius_m": 0.2', '"radius_m": NaN')


def deeply_nested_parameters(f: h5py.File) -> None:
    f["sessions/0000"].attrs["parameters"] = "[" * 100_000 + "]" * 100_000


def parameters_nested_40_deep(f: h5py.File) -> None:
    f["sessions/0000"].attrs["parameters"] = '{"a": ' * 40 + "1" + "}" * 40


DAMAGE: dict[str, tuple[Callable[[h5py.File], None], str]] = {
    "a NaN in the poses": (nan_pose, "pose holds a value that is not a finite number"),
    "poses as one flat row": (flat_pose, "pose rows hold"),
    "an infinite episode end": (infinite_episode_end, "episodes end_arc_m holds a value"),
    "minutes of two columns": (narrow_minutes, "minutes rows hold (2,) values, not 5"),
    "a robot of no size": (robot_without_size, "robot radius_m is nan, not a positive number"),
    "a deleted dataset": (delete_ring, "session 0000: corrupt (no ring_mm dataset)"),
    "sessions that are not a group": (sessions_as_a_dataset, "/sessions is not a group"),
    "a negative episode count": (negative_episode_count, "negative counts"),
    "sonar readings as floats": (float_ring, "ring_mm holds float64"),
    "parameters nested 100,000 deep": (deeply_nested_parameters, "@parameters: nested too"),
    "parameters nested 40 deep": (parameters_nested_40_deep, "@parameters: nested too"),
}


@pytest.mark.parametrize("case", DAMAGE)
def test_a_damaged_log_is_refused_by_train_and_by_learn(
    invoke_tvl, good_log: Path, tmp_path: Path, case: str
) -> None:
    damage, phrase = DAMAGE[case]
    log = tmp_path / "log.h5"
    shutil.copy(good_log, log)
    with h5py.File(log, "r+") as f:
        damage(f)
    before = log.read_bytes()
    assert_one_line_refusal(invoke_tvl("train", log, "-o", tmp_path / "fam.h5"), str(log), phrase)
    assert not (tmp_path / "fam.h5").exists()
    appended = invoke_tvl("learn", SQUARE, "--log", log, "--minutes", "0.5")
    assert_one_line_refusal(appended, str(log), phrase)
    assert log.read_bytes() == before


def test_a_run_trace_with_a_flat_pose_is_refused_not_drawn(
    invoke_tvl, good_log: Path, tmp_path: Path
) -> None:
    fam, trace = tmp_path / "fam.h5", tmp_path / "run.h5"
    assert invoke_tvl("train", good_log, "-o", fam).returncode == 0
    made = invoke_tvl(
        "run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.2", "--log", trace
    )
    assert made.returncode == 0, made.stderr
    with h5py.File(trace, "r+") as f:
        flat = f["pose"][:].ravel()
        del f["pose"]
        f["pose"] = flat
    result = invoke_tvl("replay", trace, "--png", tmp_path / "path.png")
    assert_one_line_refusal(result, str(trace), "pose is")
    assert not (tmp_path / "path.png").exists()


def _trace(invoke_tvl, log: Path, directory: Path) -> Path:
    fam, trace = directory / "fam.h5", directory / "run.h5"
    assert invoke_tvl("train", log, "-o", fam).returncode == 0
    made = invoke_tvl(
        "run", fam, SQUARE, "--behaviour", "avoid", "--minutes", "0.2", "--log", trace
    )
    assert made.returncode == 0, made.stderr
    return trace


@pytest.mark.parametrize(
    "damage, phrase",
    [
        (lambda f: f["pose"].__setitem__((5, 1), np.inf), "pose holds a value that is not finite"),
        (
            lambda f: f.attrs.__setitem__("metrics", '{"distance_m": Infinity}'),
            "metric distance_m is inf",
        ),
        (lambda f: f.attrs.__setitem__("parameters", "[1, 2]"), "parameters is not a JSON object"),
    ],
)
def test_a_run_trace_with_impossible_values_is_refused(
    invoke_tvl, good_log: Path, tmp_path: Path, damage, phrase: str
) -> None:
    trace = _trace(invoke_tvl, good_log, tmp_path)
    with h5py.File(trace, "r+") as f:
        damage(f)
    for args in (["--json"], ["--png", tmp_path / "path.png"]):
        assert_one_line_refusal(invoke_tvl("replay", trace, *args), str(trace), phrase)
    assert not (tmp_path / "path.png").exists()


def test_a_run_trace_without_a_dataset_of_its_version_is_one_line_naming_it(
    invoke_tvl, good_log: Path, tmp_path: Path
) -> None:
    trace = _trace(invoke_tvl, good_log, tmp_path)
    for dataset in ("fast", "reflex"):
        damaged = tmp_path / f"no-{dataset}.h5"
        shutil.copy(trace, damaged)
        with h5py.File(damaged, "r+") as f:
            del f[dataset]
        for command in (["explain", damaged, "--step", "0"], ["replay", damaged, "--json"]):
            refused = invoke_tvl(*command)
            assert_one_line_refusal(refused, f"{damaged}: run trace has no {dataset} dataset")


@pytest.mark.parametrize(
    "velocities, phrase",
    [
        (lambda v: v - 5.0, "holds speeds outside 0 to each trajectory's maximum"),
        (lambda v: v * 1e300, "holds speeds outside 0 to each trajectory's maximum"),
        (lambda v: (v * 10).astype(np.int8), "holds int8, not floats"),
    ],
)
def test_a_fam_with_velocities_it_could_not_have_learnt_is_refused(
    invoke_tvl, good_log: Path, tmp_path: Path, velocities, phrase: str
) -> None:
    fam = tmp_path / "fam.h5"
    assert invoke_tvl("train", good_log, "-o", fam).returncode == 0
    with h5py.File(fam, "r+") as f:
        replace(f, "fams/all/velocity", velocities(f["fams/all/velocity"][()]))
    for args in (["inspect", fam], ["run", fam, SQUARE, "--behaviour", "avoid"]):
        assert_one_line_refusal(invoke_tvl(*args), str(fam), phrase)
