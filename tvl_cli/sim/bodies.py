"""Robot bodies in a pymunk space: placing one, and the contacts each makes with the world.

A lone Simulator and a RobotBatch both keep their bodies' contacts here, so that every body's
contacts come in the same order however many bodies share its space: the slide rule
(sim.motion.slide) takes them in turn, and a different order would move the body differently.
"""

from __future__ import annotations

from collections.abc import Sequence

import pymunk

from tvl_cli.sim.motion import Contacts


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

    Recorded by collision handlers as the space steps, so that a sub-step costs nothing for
    the bodies that touch nothing. Each body's shapes get a collision type of their own
    (obstacles keep type 0), whose handler is told the body's number.
    """

    def __init__(self, space: pymunk.Space, bodies: Sequence[pymunk.Body]) -> None:
        self.normals: list[Contacts] = [[] for _ in bodies]
        self.touching: list[int] = []  # the bodies with contacts, each once
        for i, body in enumerate(bodies):
            self.adopt(i, body)
            space.on_collision(i + 1, None, post_solve=self._record, data=i)

    def adopt(self, i: int, body: pymunk.Body) -> None:
        """Record body's contacts as body i's (a new body in place of the old)."""
        for shape in body.shapes:
            shape.collision_type = i + 1

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

    def _record(self, arbiter: pymunk.Arbiter, space: pymunk.Space, robot: int) -> None:
        # The handler's own type comes first in its arbiters: the normal points to the
        # obstacle, as Body.each_arbiter gives it.
        normals = self.normals[robot]
        if not normals:
            self.touching.append(robot)
        normal = arbiter.normal
        # pymunk solves a body's contacts in the reverse of the order each_arbiter lists them
        # in (it threads each solved contact onto the head of the body's list), and the slide
        # rule has always taken them in each_arbiter's order.
        normals.insert(0, (normal.x, normal.y))
