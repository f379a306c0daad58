"""`tvl world`: make, check, show and draw worlds; import and export occupancy grids."""

from __future__ import annotations

import json
from pathlib import Path

import click

from tvl_cli.cli.examples import examples
from tvl_cli.cli.groups import Subcommands
from tvl_cli.cli.options import (
    PICTURE,
    PICTURE_HELP,
    SEED,
    print_json,
    refuse_existing,
    refuse_outputs,
    robot_option,
    world_file,
    world_given,
)
from tvl_cli.cli.params import complete_world
from tvl_cli.commands.world import (
    NewWorldRequest,
    check_world,
    new_world,
    render_world,
    show_world,
)
from tvl_cli.commands.world_export import export_map, image_beside
from tvl_cli.commands.world_import import (
    Imported,
    ImportRequest,
    import_map,
    parse_box,
    parse_start,
)
from tvl_cli.core.robot_config import RobotConfig
from tvl_cli.core.robot_profiles import DEFAULT_ROBOT_NAME
from tvl_cli.core.words import counted
from tvl_cli.io.occupancy_map import SAVED_FREE_THRESH, UNKNOWN_PIXEL
from tvl_cli.sim.worldgen import KINDS, SMOOTH, Materials
from tvl_cli.sim.worldmap import describe


@click.group(cls=Subcommands, epilog=examples("world"))
def world() -> None:
    """Make, check, show and draw text-map worlds; import and export occupancy grids."""


@world.command(
    "new",
    help=f"Write a generated world of KIND: {', '.join(KINDS)}.",
    epilog=examples("world new"),
)
@click.argument("kind", metavar="KIND", type=click.Choice(list(KINDS)))
@click.option("-o", "--output", type=click.Path(path_type=Path), required=True, help="World file.")
@click.option("--size", type=(float, float), default=None, metavar="W H", help="Metres.")
@click.option(
    "--seed",
    type=SEED,
    default=1,
    show_default=True,
    help=f"Layout seed ({', '.join(name for name, kind in KINDS.items() if kind.seeded)}).",
)
@click.option(
    "--rough",
    "rough_share",
    type=float,
    default=SMOOTH.share,
    show_default=True,
    help="rooms: the share of the rooms whose walls are rough (the rest are smooth).",
)
@click.option(
    "--roughness",
    type=float,
    default=SMOOTH.roughness,
    show_default=True,
    help="rooms: how rough a rough room's walls are, from 0 to 1.",
)
@click.option("--force", is_flag=True, help="Overwrite OUTPUT.")
@click.option("--json", "as_json", is_flag=True, help="Print what was written as JSON.")
def world_new(
    kind: str,
    output: Path,
    size: tuple[float, float] | None,
    seed: int,
    rough_share: float,
    roughness: float,
    force: bool,
    as_json: bool,
) -> None:
    width_m, height_m = size if size else (None, None)
    materials = Materials(rough_share, roughness)
    refuse_existing(output, force)
    made = new_world(NewWorldRequest(kind, output, width_m, height_m, seed, materials, force))
    if as_json:
        print_json(made.document())
    else:
        click.echo(f"{output}: a {kind} world ({counts_text(made.counts)})")


@world.command("show", epilog=examples("world show"))
@click.argument("world_entry", metavar="WORLD", shell_complete=complete_world)
@click.option("--json", "as_json", is_flag=True, help="Print the geometry as JSON.")
def world_show(world_entry: str, as_json: bool) -> None:
    """Print a summary of a world (or its geometry as JSON): a world file, a generated world
    (KIND:SEED) or a bundled world's name, as for `tvl learn`."""
    loaded = show_world(world_given(world_entry))
    if as_json:
        # On one line, for a reader with no JSON tool (a shell script may grep it).
        click.echo(json.dumps(loaded.document()))
    else:
        click.echo(describe(loaded.world))


@world.command("check", epilog=examples("world check"))
@click.argument("file", type=click.Path(path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print the counts as JSON.")
def world_check(file: Path, as_json: bool) -> None:
    """Validate a world file (exit 2 naming the problem)."""
    found = check_world(file)
    if as_json:
        print_json(found.document())
    else:
        click.echo(f"{file}: ok ({counts_text(found.counts)})")


@world.command("render", epilog=examples("world render"))
@click.argument("world_entry", metavar="WORLD", shell_complete=complete_world)
@click.option("-o", "--output", type=PICTURE, required=True, help=PICTURE_HELP)
@click.option("--force", is_flag=True, help="Overwrite OUTPUT.")
@click.option("--json", "as_json", is_flag=True, help="Print what was drawn as JSON.")
def world_render(world_entry: str, output: Path, force: bool, as_json: bool) -> None:
    """Draw a world as a picture: a world file, a generated world (KIND:SEED) or a bundled
    world's name."""
    given = world_given(world_entry)
    refuse_outputs({"-o": output}, {"WORLD": world_file(given)}, force)
    drawn = render_world(given, output)
    if as_json:
        print_json(drawn.document())
    else:
        click.echo(f"{output}: {world_entry} drawn ({counts_text(drawn.counts)})")


def counts_text(counts: dict[str, int]) -> str:
    """A world's counts in words: `4 segments, 1 disc, 0 rings, 0 goals`."""
    return ", ".join(counted(n, what.removesuffix("s")) for what, n in counts.items())


@world.command("import", epilog=examples("world import"))
@click.argument("map_yaml", metavar="MAP.yaml", type=click.Path(path_type=Path))
@click.option("-o", "--output", type=click.Path(path_type=Path), required=True, help="World file.")
@click.option(
    "--start",
    default=None,
    metavar="X,Y,HEADING_DEG",
    help="Where the robot starts, in the map's frame (metres), facing any way (degrees CCW "
    "from +x). Default: the widest free place, facing +x.",
)
@click.option(
    "--cell",
    type=float,
    default=None,
    metavar="METRES",
    help="Coarser cells than the map's: a cell is free only where every map cell under it is.",
)
@click.option(
    "--crop",
    default=None,
    metavar="X0,Y0,X1,Y1",
    help="Keep only this rectangle of the map (its frame, metres).",
)
@click.option("--name", default=None, help="The world's name (default: the map's file name).")
@robot_option("The robot the start and the narrow passages are judged for.", DEFAULT_ROBOT_NAME)
@click.option("--force", is_flag=True, help="Overwrite OUTPUT.")
@click.option("--json", "as_json", is_flag=True, help="Print what was written as JSON.")
def world_import(
    map_yaml: Path,
    output: Path,
    start: str | None,
    cell: float | None,
    crop: str | None,
    name: str | None,
    robot: RobotConfig,
    force: bool,
    as_json: bool,
) -> None:
    """Make a world from a ROS map_server occupancy grid (a YAML file and its PGM or PNG).

    Cells are read by map_server's rule (free below free_thresh, occupied above
    occupied_thresh); every cell not free, unknown ones too, becomes a wall. The world keeps
    the map's frame: every coordinate of it, and of the runs in it, is the map's.
    """
    request = ImportRequest(
        map_yaml,
        output,
        None if start is None else parse_start(start),
        name,
        cell,
        None if crop is None else parse_box(crop),
        force,
        robot,
    )
    refuse_outputs({"-o": output}, {"MAP.yaml": map_yaml}, force)
    imported = import_map(request)
    for warning in _import_warnings(imported, robot):
        click.echo(f"tvl: warning: {map_yaml}: {warning}", err=True)
    if as_json:
        print_json(imported.document())
    else:
        click.echo(_import_summary(output, imported))


def _import_warnings(imported: Imported, robot: RobotConfig) -> list[str]:
    """What the user may not expect of the world made: unknown grey read as free, and floor
    the robot fits on but cannot reach."""
    warnings = []
    grey = imported.map.unknown_grey_free
    if grey:
        warnings.append(
            f"{grey:,} cells of grey {UNKNOWN_PIXEL} (map_saver's unknown) are free under "
            f"free_thresh {imported.map.meta.free_thresh:g}, as map_server reads them; "
            f"free_thresh {SAVED_FREE_THRESH:g} keeps them unknown"
        )
    if imported.passages:
        count = len(imported.passages)
        narrowest = imported.passages[0]
        warnings.append(
            f"{count} passage{'s' if count > 1 else ''} narrower than the robot "
            f"({2 * robot.radius_m:g} m across) lead{'' if count > 1 else 's'} to floor "
            f"it fits on but cannot reach; the narrowest is {narrowest.width_m:.3g} m wide "
            f"at x {narrowest.x_m:g} y {narrowest.y_m:g}, with {narrowest.beyond_m2:.3g} m² "
            "beyond it"
        )
    return warnings


def _import_summary(output: Path, imported: Imported) -> str:
    found = imported.to_dict()
    x0, y0 = imported.world.place.left_x_m, imported.world.place.bottom_y_m
    x, y, heading = imported.world.start
    how = (
        f" (the widest free place, {imported.start_clearance_m:.2f} m clear)"
        if imported.start_chosen
        else ""
    )
    return (
        f"{output}: {found['columns']} x {found['rows']} cells of {found['cell_m']:g} m, "
        f"{found['free_cells']:,} free, origin x {x0:g} y {y0:g} (the map's frame); "
        f"start x {x:g} y {y:g} heading {heading:g}°{how}"
    )


@world.command("export", epilog=examples("world export"))
@click.argument("world_entry", metavar="WORLD", shell_complete=complete_world)
@click.option(
    "-o", "--output", type=click.Path(path_type=Path), required=True, help="MAP.yaml file."
)
@click.option("--force", is_flag=True, help="Overwrite OUTPUT and its PGM.")
@click.option("--json", "as_json", is_flag=True, help="Print what was written as JSON.")
def world_export(world_entry: str, output: Path, force: bool, as_json: bool) -> None:
    """Write a world (a file, KIND:SEED or a bundled name) as a ROS map_server occupancy
    grid: MAP.yaml and MAP.pgm beside it.

    The world's walls, pillars, discs and rings are drawn at its cell size, as map_saver
    writes a map (254 free, 0 occupied, 205 outside the world), origin at the world's
    bottom-left corner.
    """
    image = image_beside(output)
    given = world_given(world_entry)
    refuse_outputs({"-o": output, "its PGM": image}, {"WORLD": world_file(given)}, force)
    exported = export_map(given, output)
    if as_json:
        print_json(exported.document())
    else:
        click.echo(
            f"{output}, {image.name}: {exported.columns} x {exported.rows} cells of "
            f"{exported.cell_m:g} m, {exported.free_cells:,} free"
        )
