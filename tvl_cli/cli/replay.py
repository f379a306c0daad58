"""`tvl replay`: a learning log or a run trace summarised, drawn and animated.

The command imports the modules that do its work when it runs, so that `--help` reads only
the options (and loads neither HDF5 nor the physics).
"""

from __future__ import annotations

from pathlib import Path

import click

from tvl_cli.cli import views
from tvl_cli.cli.examples import examples
from tvl_cli.cli.options import (
    GIF,
    MP4,
    PICTURE,
    given_on_command_line,
    print_json,
    refuse_outputs,
)

# replay's options that shape an animation, and nothing else.
ANIMATION_OPTIONS = ("--from", "--to", "--every", "--fps")


@click.command(epilog=examples("replay"))
@click.argument("file", type=click.Path(path_type=Path))
@click.option("--png", type=PICTURE, default=None, help="Draw the paths.")
@click.option(
    "--curves",
    type=PICTURE,
    default=None,
    help="Draw the learning curves (learning logs).",
)
@click.option(
    "--session",
    default=None,
    help="A learning log's session to draw (e.g. 0001); by default every session in the "
    "last one's world, and the last one's curves.",
)
@click.option(
    "--gif",
    type=GIF,
    default=None,
    help="Animate a run: robot, sonar rays and perceived velocities.",
)
@click.option(
    "--mp4",
    type=MP4,
    default=None,
    help="As --gif, as an MP4 video (needs ffmpeg).",
)
@click.option("--from", "from_s", type=float, default=None, help="--gif from this second.")
@click.option("--to", "to_s", type=float, default=None, help="--gif to this second.")
@click.option(
    "--every",
    type=click.IntRange(min=1),
    default=None,
    help="--gif: a frame every N steps (default: at most 200 frames).",
)
@click.option(
    "--fps",
    type=click.IntRange(1, 50),
    default=10,
    show_default=True,
    help="--gif, --mp4 frames/s.",
)
@click.option("--force", is_flag=True, help="Overwrite the PNG and GIF files.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
def replay(
    file: Path,
    png: Path | None,
    curves: Path | None,
    session: str | None,
    gif: Path | None,
    mp4: Path | None,
    from_s: float | None,
    to_s: float | None,
    every: int | None,
    fps: int,
    force: bool,
    as_json: bool,
) -> None:
    """Summarise a learning log or a run trace, and draw it."""
    from tvl_cli.cli import replay_views
    from tvl_cli.commands.replay import Animation, Replayed
    from tvl_cli.commands.replay import replay as replay_file

    if gif is not None and mp4 is not None:
        raise click.UsageError("give --gif or --mp4, not both")
    moving = gif or mp4
    if moving is None:
        # Options of the animation alone: silently ignoring one would hide a mistyped command.
        for option in given_on_command_line(*ANIMATION_OPTIONS):
            raise click.UsageError(f"{option} applies only with --gif or --mp4")
    outputs = {"--png": png, "--curves": curves, "--gif": gif, "--mp4": mp4}
    refuse_outputs(outputs, {"FILE": file}, force)
    animation = (
        Animation(moving, from_s, to_s, every, fps, video=mp4 is not None)
        if moving is not None
        else None
    )
    with views.progress("drawing frames", quiet=animation is None) as on_frame:
        summary = replay_file(file, png, curves, session, animation, on_frame)
    if as_json:
        pictures = {"png": png, "curves": curves, "animation": moving}
        print_json(Replayed(file, session, pictures, summary).document())
    else:
        replay_views.replay(summary)
