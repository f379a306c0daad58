"""`tvl explain`: why a run did what it did at one moment, from its trace and its FAM."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.core.contacts import EVENT_ALIASES, EVENT_CHOICES, EVENTS
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fired_rules import Explanation, restricted
from tvl_cli.core.ring import mm_to_ring
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.words import counted
from tvl_cli.io.famfile import read_fam
from tvl_cli.io.json_documents import document, input_file
from tvl_cli.io.logreader import file_sha256
from tvl_cli.io.runfile import RunTrace, read_run, recorded_paths
from tvl_cli.sim.worldmap import parse_world


@dataclass(frozen=True, slots=True)
class Moment:
    """Which step to explain: exactly one of these is given."""

    step: int | None = None  # 0 for the first
    at_s: float | None = None  # simulated seconds, as `tvl replay` lists event times
    event: str | None = None  # one of EVENT_CHOICES
    index: int = 1  # the index-th such event, from 1


@dataclass(frozen=True, slots=True)
class StepExplanation:
    step: int
    time_s: float  # when the step ended, the time `tvl replay` gives its events
    ring_m: list[float] | None  # as read before the step; None if nobody read it
    # What the FAM read of it where that differs: the echo memory's virtual ring; None if the
    # run kept no memory (or the ring was not read)
    perceived_m: list[float] | None
    rotation: int  # the view, in sonar positions counter-clockwise
    velocities_mps: list[float | None]  # perceived in that view; None where none was
    fast: list[str]  # the fast set of that view
    choice: str | None  # the policy's choice
    driven: str | None  # the trajectory driven; None spinning, reversing or trapped
    reflex: str | None  # the reflex that overrode the policy
    events: list[str]  # events the step began
    focus: tuple[str, ...]  # the trajectories explained: the choice and the best rated
    why: Explanation | None  # the FAM's view of the ring, for the focus trajectories
    fam: Path  # the FAM that explains it: the one the run used
    run: Path  # the trace explained
    asked: Moment  # the moment asked for
    # Why another step than the one asked for is explained (--at a step that made no
    # decision: the nearest that did); None if it is the one asked for. Said, not printed.
    moved: str | None = None

    def to_dict(self) -> dict[str, Any]:
        """What was found of the step (the FAM is one of the command's inputs)."""
        found = asdict(self)
        found["focus"] = list(self.focus)
        del found["fam"], found["moved"], found["run"], found["asked"]
        return found

    def document(self) -> dict[str, Any]:
        inputs = {
            "run": input_file(self.run),
            "fam": input_file(self.fam),
            "contacts": False,
            **asdict(self.asked),
        }
        return document("explain", inputs, step=self.to_dict(), autopsy=None)


def explain_run(
    trace_path: Path, moment: Moment, fam_path: Path | None = None, png: Path | None = None
) -> StepExplanation:
    """Explain one step of a recorded run with the FAM that drove it; with `png`, draw it."""
    trace = read_run(trace_path)
    if not trace.has_decisions:
        raise BadInput(f"{trace_path}: a format_version 1 trace records no decisions to explain")
    if trace.steps == 0:
        raise BadInput(f"{trace_path}: the run has no steps")
    step = _step(trace, trace_path, moment)
    moved = None
    if moment.at_s is not None:
        step, moved = _nearest_decision(trace, step)
    used = _fam_of(trace, trace_path, fam_path)
    fam = read_fam(used).fam
    names = fam.trajectory_names
    arrays = trace.arrays
    ring_mm = arrays["ring_mm"][step]
    read = bool(ring_mm.any())
    velocities = arrays["velocities"][step]
    rotation = int(arrays["rotation"][step])
    choice, driven = _name(names, arrays["choice"][step]), _name(names, arrays["trajectory"][step])
    rated = np.where(np.isnan(velocities), -np.inf, velocities)
    best = names[int(np.argmax(rated))] if np.isfinite(rated).any() else None
    focus = tuple(n for n in names if n in (choice, best))
    why = None
    ring = mm_to_ring(ring_mm)
    # Version 3 traces keep what the FAM read, which an echo memory makes of the ring.
    perceived = mm_to_ring(arrays["perceived_mm"][step]) if "perceived_mm" in arrays else ring
    if read:
        # The view of rotation k reads sonar (i + k) mod 16 where view 0 reads sonar i.
        view = perceived.take((np.arange(len(perceived)) + rotation) % len(perceived))
        why = restricted(fam.explain(view), focus or names)
    reflex_index = int(arrays["reflex"][step])
    found = StepExplanation(
        step=step,
        time_s=(step + 1) * trace.period_s,
        ring_m=[float(r) for r in ring] if read else None,
        perceived_m=([float(r) for r in perceived] if read and _remembers(trace) else None),
        rotation=rotation,
        velocities_mps=[None if math.isnan(v) else float(v) for v in velocities],
        fast=[n for n, fast in zip(names, arrays["fast"][step], strict=True) if fast],
        choice=choice,
        driven=driven,
        reflex=trace.reflex_names[reflex_index] if reflex_index >= 0 else None,
        events=[e for i, e in enumerate(EVENTS) if int(arrays["events"][step]) & (1 << i)],
        focus=focus,
        why=why,
        fam=used,
        run=trace_path,
        asked=moment,
        moved=moved,
    )
    if png is not None:
        _draw_moment(trace, found, png)
    return found


def _draw_moment(trace: RunTrace, found: StepExplanation, png: Path) -> None:
    """The --png picture of the explained step, after the path that led to it."""
    from tvl_cli.render.moment import render_moment  # matplotlib only for a picture

    render_moment(
        parse_world(trace.world_text, trace.world_name),
        RobotConfig.from_dict(trace.robot_config),
        trace.arrays["pose"][: found.step + 1],
        float(trace.parameters.get("threshold", 0.0)),
        found,
        png,
        trace.parameters.get("goal"),
    )


def _nearest_decision(trace: RunTrace, step: int) -> tuple[int, str | None]:
    """The step nearest `step` at which the policy perceived and decided (the earlier of two
    as near), and why it is not `step` itself; `step` and None if it decided there, or never
    did. A decision reads the ring and perceives: a spin to face a chosen view, a reflex's
    manoeuvre, and the step that then follows the trajectory chosen carry out a decision
    made before them."""
    arrays = trace.arrays
    read = arrays["ring_mm"].any(axis=1)  # (steps,)
    decided = read & ~np.isnan(arrays["velocities"]).all(axis=1)
    if decided[step]:
        return step, None
    steps = np.flatnonzero(decided)
    if not len(steps):
        return step, None
    nearest = int(steps[np.argmin(np.abs(steps - step))])
    reflex = int(arrays["reflex"][step])
    if reflex >= 0:
        doing = f"the {trace.reflex_names[reflex]} reflex was acting"
    elif arrays["trajectory"][step] >= 0:
        doing = "it followed a trajectory chosen before"
    else:
        doing = "it was spinning"
    period_s = trace.period_s
    return nearest, (
        f"step {step} (ending at {(step + 1) * period_s:.1f} s) made no decision, as "
        f"{doing}; explaining step {nearest} (ending at {(nearest + 1) * period_s:.1f} s), "
        "the nearest that did"
    )


def _remembers(trace: RunTrace) -> bool:
    """Whether the run perceived through an echo memory (traces before it: never)."""
    return trace.method.memory.remembers


def _step(trace: RunTrace, path: Path, moment: Moment) -> int:
    given = [x for x in (moment.step, moment.at_s, moment.event) if x is not None]
    if len(given) != 1:
        raise BadInput("give exactly one of --step, --at and --event")
    last = trace.steps - 1
    if moment.step is not None:
        if not 0 <= moment.step <= last:
            raise BadInput(f"--step {moment.step}: the run has steps 0 to {last}")
        return moment.step
    if moment.at_s is not None:
        end_s = trace.steps * trace.period_s
        if not (math.isfinite(moment.at_s) and 0 <= moment.at_s <= end_s):
            raise BadInput(f"--at {moment.at_s:g}: the run lasted {end_s:g} simulated seconds")
        # The step that ended nearest that moment (replay gives an event's time so).
        return min(max(round(moment.at_s / trace.period_s) - 1, 0), last)
    assert moment.event is not None
    event = EVENT_ALIASES.get(moment.event, moment.event)
    if event not in EVENTS:
        raise BadInput(f"--event {moment.event!r}: choose from {', '.join(EVENT_CHOICES)}")
    steps = trace.event_steps(event)
    if not 1 <= moment.index <= len(steps):
        raise BadInput(
            f"{path}: --index {moment.index}: the run has "
            f"{counted(len(steps), f'{moment.event} event')}"
        )
    return int(steps[moment.index - 1])


def _fam_of(trace: RunTrace, path: Path, fam_path: Path | None) -> Path:
    """The FAM the run used: `fam_path`, else the one it names, if it is still that file."""
    if fam_path is not None:
        _refuse_another_fam(trace, path, fam_path)
        return fam_path
    places = recorded_paths(str(trace.parameters.get("fam", "")), path)
    found = [place for place in places if place.is_file()]
    if not found:
        raise BadInput(f"{path}: the run's FAM {places[0]} is not there; give it with --fam")
    for named in found:
        if file_sha256(named) == trace.parameters.get("fam_sha256"):
            return named
    raise BadInput(
        f"{path}: {found[0]} has changed since the run (another SHA-256); give the FAM "
        "the run used with --fam"
    )


def _refuse_another_fam(trace: RunTrace, path: Path, fam_path: Path) -> None:
    """Another FAM's rules would explain the run wrongly, yet without a word: refuse a FAM
    whose SHA-256 is not the one the trace records (traces that record none: any FAM)."""
    recorded = trace.parameters.get("fam_sha256")
    if recorded is not None and file_sha256(fam_path) != recorded:
        raise BadInput(
            f"{fam_path}: not the FAM {path} was run with (that FAM had another SHA-256); "
            "give the FAM the run used"
        )


def _name(names: tuple[str, ...], index: Any) -> str | None:
    return names[int(index)] if int(index) >= 0 else None
