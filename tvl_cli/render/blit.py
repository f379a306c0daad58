"""Frames of an animation by blitting: the figure's still parts drawn once, and each frame
only the artists that move drawn over a copy of them.

Drawing a whole figure costs tens of milliseconds, nearly all of it the parts that never
change (a world's walls, axes, ticks and labels); the robot, its rays and a few bars take a
millisecond or two.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.artist import Artist
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import to_rgba
from matplotlib.figure import Figure


class Blitter:
    """A figure whose `moving` artists are left out of its still background and drawn, in
    their z-order, over a copy of that background for every frame."""

    def __init__(self, figure: Figure, moving: Sequence[Artist]) -> None:
        self.figure = figure
        self.canvas = FigureCanvasAgg(figure)
        # Drawn over one another as a whole draw would order them.
        self.moving = sorted(moving, key=lambda artist: artist.get_zorder())
        for artist in self.moving:
            artist.set_animated(True)
        self.canvas.draw()
        self.background = self.canvas.copy_from_bbox(figure.bbox)

    def frame(self) -> np.ndarray:
        """(H, W, 3) uint8 RGB: the background with the moving artists as they are now; a
        view of the canvas, valid until the next frame."""
        self.canvas.restore_region(self.background)
        for artist in self.moving:
            self.figure.draw_artist(artist)
        return np.asarray(self.canvas.buffer_rgba())[..., :3]

    def still(self) -> np.ndarray:
        """(H, W, 3) uint8 RGB of the background alone."""
        self.canvas.restore_region(self.background)
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()


# The coverages a thin line's antialiased edge is drawn at over the floor, as kept in a
# palette beside its full colour: without them, a line under a pixel wide maps to whatever
# grey or dark colour of the background is nearest.
EDGE_COVERAGES = (0.25, 0.5, 0.75)


def inks(*colours: str | tuple[str, float]) -> np.ndarray:
    """(K, 3) uint8: the RGB a frame draws matplotlib colours in, each also at the coverages
    of its antialiased edges; a (colour, alpha) pair as it looks over white, the floor the
    robot drives on."""
    rgb = []
    for colour in colours:
        red, green, blue, alpha = to_rgba(*colour) if isinstance(colour, tuple) else to_rgba(colour)
        for coverage in (1.0, *EDGE_COVERAGES):
            weight = alpha * coverage
            rgb.append([round(255 * (weight * c + 1.0 - weight)) for c in (red, green, blue)])
    return np.array(rgb, dtype=np.uint8)
