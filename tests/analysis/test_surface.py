"""The learnt velocity over two inputs: what `tvl inspect --png` draws."""

from __future__ import annotations

import numpy as np
import pytest

from tvl_cli.analysis.surface import GRID_POINTS, shared_inputs, velocity_surfaces
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fam import Fam
from tvl_cli.core.fam_config import DESIGNED, MULTI, SINGLE, FamConfig, FamTable
from tvl_cli.core.robot_config import RobotConfig

ROBOT = RobotConfig()
SONAR = ROBOT.sonar
NAMES = [t.name for t in ROBOT.trajectories]


def trained(config) -> Fam:
    rng = np.random.default_rng(3)
    fam = Fam(config, NAMES)
    rings = rng.uniform(0.15, 4.0, (3000, 16))
    trajectories = rng.integers(0, 7, 3000)
    fam.train(
        rings, trajectories, rng.uniform(0, 1, 3000) * np.array(ROBOT.v_max_mps)[trajectories]
    )
    return fam


def surfaces(fam: Fam, over, fixed=None):
    return velocity_surfaces(
        fam, over, fixed or {}, SONAR.min_range_m, SONAR.max_range_m, SONAR.count
    )


def test_each_point_is_what_the_fam_perceives_of_such_a_ring() -> None:
    fam = trained(SINGLE)
    found = surfaces(fam, ("front", "front-left"), {"front-right": 0.5})
    assert [s.trajectory for s in found] == NAMES
    surface = found[3]  # T0
    assert surface.velocity_mps.shape == (GRID_POINTS, GRID_POINTS)
    i, j = 7, 41  # a point: front-left at ranges_m[i], front at ranges_m[j]
    ring = np.full(16, SONAR.max_range_m)
    ring[[15, 0, 1]] = surface.ranges_m[j]  # front
    ring[[2, 3, 4]] = surface.ranges_m[i]  # front-left
    ring[[12, 13, 14]] = 0.5  # front-right, held
    assert surface.velocity_mps[i, j] == pytest.approx(fam.velocities(ring)[3], abs=1e-12)


def test_a_multi_fam_draws_every_trajectory_saying_what_its_table_does_not_read() -> None:
    fam = trained(MULTI)
    found = surfaces(fam, ("S0", "S1"))
    assert [s.trajectory for s in found] == NAMES  # none left out
    unread = {s.trajectory: s.unread for s in found if s.unread}
    assert unread == {"T3L": ("S1",), "T2R": ("S1",), "T3R": ("S1",)}
    # Along what a table does not read, its velocity stays the same; along what it reads,
    # each point is what the FAM perceives of such a ring.
    t3l = found[0]
    assert np.ptp(t3l.velocity_mps, axis=0).max() == 0.0  # the same up the S1 axis
    i, j = 11, 37
    ring = np.full(16, SONAR.max_range_m)
    ring[0], ring[1] = t3l.ranges_m[j], t3l.ranges_m[i]
    assert t3l.velocity_mps[i, j] == pytest.approx(fam.velocities(ring)[0], abs=1e-12)
    assert t3l.experience[i, j] == pytest.approx(fam.experience(ring)[0], abs=1e-12)


def test_where_nothing_was_learnt_is_untrained() -> None:
    fam = Fam(SINGLE, NAMES)  # nothing learnt anywhere
    (first, *_) = surfaces(fam, ("front", "front-left"))
    assert first.untrained.all()
    assert first.velocity_mps == pytest.approx(np.full((GRID_POINTS,) * 2, fam.init_velocity_mps))
    # Trained on random rings, a FAM has learnt something over most of every panel.
    learnt = surfaces(trained(SINGLE), ("front", "front-left"))
    assert all(s.untrained.mean() < 0.5 for s in learnt)


def test_by_default_it_draws_over_the_inputs_most_tables_read() -> None:
    assert shared_inputs(SINGLE) == ("front", "front-left")
    # Every table of multi but T0's reads S0 and S3: seven panels, T0's along S0 alone.
    assert shared_inputs(MULTI) == ("S0", "S3")
    drawn = surfaces(trained(MULTI), shared_inputs(MULTI))
    assert [s.unread for s in drawn] == [(), (), (), ("S3",), (), (), ()]
    assert len(surfaces(trained(DESIGNED), shared_inputs(DESIGNED))) == 7
    lone = FamConfig(
        "lone", tuple(FamTable(t.name, t.inputs[:1], t.trajectories) for t in MULTI.tables)
    )
    with pytest.raises(BadInput, match="no table of the lone FAM reads two inputs"):
        shared_inputs(lone)


@pytest.mark.parametrize(
    "over, fixed, message",
    [
        (("front", "left"), {}, "no table of the FAM has the inputs left"),
        (("front", "front"), {}, "two different inputs"),
        (("front", "front-left"), {"rear-left": 9.0}, "--fix rear-left=9: outside"),
    ],
)
def test_inputs_it_cannot_draw_are_refused(over, fixed, message) -> None:
    with pytest.raises(BadInput, match=message):
        surfaces(trained(SINGLE), over, fixed)
