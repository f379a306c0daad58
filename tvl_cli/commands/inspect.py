"""`tvl inspect`: a FAM file's rules, one ring explained in them, or its learnt velocity drawn."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from tvl_cli.analysis.rules import Rule, parse_ring, select_rules
from tvl_cli.analysis.surface import shared_inputs, velocity_surfaces
from tvl_cli.core.errors import BadInput
from tvl_cli.core.fired_rules import Explanation
from tvl_cli.io.famfile import FamFile, read_fam
from tvl_cli.io.json_documents import document, input_file, output_path


@dataclass(frozen=True, slots=True)
class InspectRequest:
    fam: Path
    trajectory: str | None = None  # only this trajectory's rules
    top: int = 20  # how many rules (0: all)
    sort: str = "experience"  # one of analysis.rules.SORT_KEYS
    untrained: bool = False  # the rules no exemplar has reached
    explain: str | None = None  # "R0,...,R15": one ring of ranges (m) to explain instead
    png: Path | None = None  # where to draw the learnt velocity over two inputs
    over: tuple[str, str] | None = None  # those two inputs (None: the pair most tables read)
    fix: tuple[tuple[str, float], ...] = ()  # other inputs held at a range (m) for the picture


@dataclass(frozen=True, slots=True)
class Inspected:
    """The FAM file read, and either its rules or one ring's explanation (the other None);
    with a picture, the two inputs it was drawn over."""

    request: InspectRequest
    loaded: FamFile
    ring: np.ndarray | None
    explanation: Explanation | None
    rules: list[Rule] | None
    over: tuple[str, str] | None = None

    def document(self) -> dict[str, Any]:
        """A FAM's configuration and provenance, and its rules or one ring explained
        (--explain), the other null."""
        r = self.request
        drawn_over = self.over or r.over
        inputs = {
            "fam": input_file(r.fam),
            "trajectory": r.trajectory,
            "top": r.top,
            "sort": r.sort,
            "untrained": r.untrained,
            "over": None if drawn_over is None else list(drawn_over),
            "fix": dict(r.fix),
            "explain_ring_m": None if self.ring is None else [float(x) for x in self.ring],
        }
        return document(
            "inspect",
            inputs,
            outputs={"png": output_path(r.png)},
            config=self.loaded.fam.config.to_dict(),
            method=self.loaded.made_by.record(),
            provenance=self.loaded.provenance,
            rules=None if self.rules is None else [rule.to_dict() for rule in self.rules],
            explanation=None if self.explanation is None else self.explanation.to_dict(),
        )


def inspect_fam(request: InspectRequest) -> Inspected:
    """Read the FAM file; draw its surfaces if a picture is asked for; select its rules, or
    explain the ring given in them."""
    if request.png is None and (request.over or request.fix):
        # They choose what the picture shows; silently ignored they would look obeyed.
        raise BadInput("--over and --fix choose what the --png picture shows; give --png PATH")
    loaded = read_fam(request.fam)
    over = None
    if request.png is not None:
        over = draw_surfaces(loaded, request.png, request.over, request.fix)
    if request.explain is not None:
        ring = parse_ring(request.explain, loaded.robot_config.sonar.count)
        return Inspected(request, loaded, ring, loaded.fam.explain(ring), None, over)
    rules = select_rules(
        loaded.fam, request.trajectory, request.top, request.sort, request.untrained
    )
    return Inspected(request, loaded, None, None, rules, over)


def draw_surfaces(
    loaded: FamFile,
    png: Path,
    over: tuple[str, str] | None,
    fix: tuple[tuple[str, float], ...],
) -> tuple[str, str]:
    """`inspect --png`: the learnt velocity over two inputs, the others held; the two inputs
    (`over`, else the pair most of the FAM's tables read)."""
    from tvl_cli.render.plot import render_surfaces  # matplotlib only when a picture is wanted

    sonar = loaded.robot_config.sonar
    fixed = dict(fix)
    drawn_over = over or shared_inputs(loaded.fam.config)
    surfaces = velocity_surfaces(
        loaded.fam,
        drawn_over,
        fixed,
        sonar.min_range_m,
        sonar.max_range_m,
        sonar.count,
    )
    held = ", ".join(f"{n} {v:g} m" for n, v in fixed.items()) or "the rest open"
    render_surfaces(surfaces, png, f"{loaded.fam.config.name} FAM, {held}")
    return drawn_over
