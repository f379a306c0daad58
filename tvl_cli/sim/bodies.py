"""Robot bodies in a pymunk space: placing one, and the contacts each makes with the world.

A lone Simulator and a RobotBatch both keep their bodies' contacts here, so that every body's
contacts come in the same order however many bodies share its space: the slide rule
(sim.motion.slide) takes them in turn, and a different order would move the body differently.
"""

from __future__ import annotations

from collections.abc import Sequence

import pymunk

from tvl_cli.sim.motion import Contacts
from tvl_cli.sim.world import ROBOT_COLLISION_TYPE


def place_body(
    space: pymunk.Space, body: pymunk.Body, x: float, y: float, theta: float
) -> Contacts:
    """Put a robot's body at rest at a pose; the normals of what it touches there."""
    body.position = (x, y)
    body.angle = theta
    body.velocity = (0.0, 0.0)
    body.angular_velocity = 0.0
    space.reindex_shapes_for_body(body)
    (disc,) = body.shapes
    # The disc's own filter keeps other robots out of the query, as out of the physics.
    return [
        (info.contact_point_set.normal.x, info.contact_point_set.normal.y)
        for info in space.shape_query(disc)
    ]


class ContactRecorder:
    """The unit normals (body -> obstacle) of the contacts each robot body in a space made
    in the last physics sub-step, in the order pymunk's Body.each_arbiter lists them.

    Recorded by one collision handler as the space steps, so that a sub-step costs nothing
    for the bodies that touch nothing.
    """

    def __init__(self, space: pymunk.Space, bodies: Sequence[pymunk.Body]) -> None:
        self._index = {shape: i for i, body in enumerate(bodies) for shape in body.shapes}
        self.normals: list[Contacts] = [[] for _ in bodies]
        self.touching: list[int] = []  # the bodies with contacts, each once
        space.on_collision(ROBOT_COLLISION_TYPE, None, post_solve=self._record)

    def clear(self) -> None:
        """Forget the contacts, before the next sub-step records its own."""
        for i in self.touching:
            self.normals[i] = []
        self.touching = []

    def set(self, i: int, normals: Contacts) -> None:
        """Body i's contacts as a shape query found them (after placing it)."""
        if normals and i not in self.touching:
            self.touching.append(i)
        elif not normals and i in self.touching:
            self.touching.remove(i)
        self.normals[i] = normals

    def _record(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: object) -> None:
        # The handler's own type comes first in its arbiters: the normal points to the
        # obstacle, as Body.each_arbiter gives it.
        robot = self._index[arbiter.shapes[0]]
        normals = self.normals[robot]
        if not normals:
            self.touching.append(robot)
        normal = arbiter.normal
        # pymunk solves a body's contacts in the reverse of the order each_arbiter lists them
        # in (it threads each solved contact onto the head of the body's list), and the slide
        # rule has always taken them in each_arbiter's order.
        normals.insert(0, (normal.x, normal.y))
