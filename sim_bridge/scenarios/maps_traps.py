"""
Trap maps: cups facing the start (bug traps), a comb of dead ends, and the gear.

A robot that assumes unknown space is free, as the navigator does, drives straight into a cup
that faces it and only learns at its back wall that it must turn round. Each function returns
the `MapDesign` of one map of the benchmark set.

"""

import math

from .design import EAST, MapDesign, NORTH, outer_walls, RESOLUTION, SOUTH, task, WEST
from .families import polyline_walls, rock
from .shapes import Blocky, Disc, Rect


def bug_trap():
    """Return map 4: a cup with inward lips whose mouth faces the start."""
    size = (30.0, 30.0)
    walls = outer_walls(*size) + [
        Rect(20.0, 8.0, 20.2, 22.2),                                   # back
        Rect(12.0, 8.0, 20.2, 8.2), Rect(12.0, 22.0, 20.2, 22.2),      # arms
        Rect(12.0, 8.0, 12.2, 11.0), Rect(12.0, 19.2, 12.2, 22.2),     # lips
    ]
    tasks = (
        task((4.0, 15.0, EAST), (26.0, 15.0),
             "the cup's mouth faces the start; the goal lies behind its back"),
        task((16.0, 15.0, EAST), (4.0, 26.0), 'from inside the cup, facing its back, out'),
        task((26.0, 4.0, NORTH), (16.0, 15.0), 'from behind the trap into it'),
    )
    return MapDesign(4, 'bug_trap', 'trap', size, tuple(walls), tasks, 7.8,
                     'a 8 m x 14 m cup with inward lips, its mouth facing the start')


def comb():
    """Return map 7: six dead-end pockets side by side, all open towards the start."""
    size = (40.0, 30.0)
    walls = outer_walls(*size) + [Rect(30.0, 3.0, 30.2, 27.2)]   # the comb's back
    walls += [Rect(14.0, y, 30.0, y + 0.2) for y in (3.0, 7.0, 11.0, 15.0, 19.0, 23.0, 27.0)]
    tasks = (
        task((3.0, 13.1, EAST), (36.0, 15.0), 'a pocket faces the start; the goal is behind'),
        task((22.0, 17.1, EAST), (36.0, 26.0), 'from inside a pocket, facing its end'),
        task((36.0, 5.0, WEST), (3.0, 25.0), 'from behind the comb to the far corner'),
    )
    return MapDesign(7, 'comb', 'trap', size, tuple(walls), tasks, 2.8,
                     'six 3.8 m x 16 m dead-end pockets open towards the start')


def double_trap():
    """Return map 11: two cups in a row, both facing the start, the second one larger."""
    size = (40.0, 30.0)
    walls = outer_walls(*size) + [
        Rect(16.0, 10.0, 16.2, 20.2), Rect(10.0, 10.0, 16.2, 10.2), Rect(10.0, 20.0, 16.2, 20.2),
        Rect(32.0, 5.0, 32.2, 25.2), Rect(24.0, 5.0, 32.2, 5.2), Rect(24.0, 25.0, 32.2, 25.2),
        Rect(24.0, 5.0, 24.2, 9.0), Rect(24.0, 21.2, 24.2, 25.2),
    ]
    tasks = (
        task((4.0, 15.0, EAST), (37.0, 15.0), 'straight at both cups; the goal is behind both'),
        task((13.0, 15.0, EAST), (37.0, 27.0), 'from inside the first cup'),
        task((28.0, 15.0, EAST), (4.0, 4.0), 'from inside the second cup, facing its back'),
    )
    return MapDesign(11, 'double_trap', 'trap', size, tuple(walls), tasks, 4.8,
                     'two cups in a row facing the start, 6 m x 10 m and 8 m x 20 m')


def gear():
    """Return map 13: a round arena with eight radial teeth, like a gear turned inside out."""
    size = (40.0, 40.0)
    cx, cy, radius = 20.0, 20.0, 19.8
    # The arena's rim is the edge of solid rock, in 1 m steps, and the slanted teeth are
    # staircases of 0.5 m blocks: a round or slanted wall drawn pixel by pixel would make a
    # pybullet box of every pixel row, and slow the laser down threefold.
    walls = outer_walls(*size) + rock(size, [Disc(cx, cy, radius)], step=1.0)
    for k in range(8):
        c, s = math.cos(0.25 * math.pi * k), math.sin(0.25 * math.pi * k)
        tooth = polyline_walls([(round(cx + 11.0 * c, 1), round(cy + 11.0 * s, 1)),
                                (round(cx + radius * c, 1), round(cy + radius * s, 1))], 0.3)
        walls += tooth if k % 2 == 0 else [Blocky(tooth[0], 0.5, RESOLUTION)]
    tasks = (
        task((33.9, 25.7, WEST), (6.1, 14.3), 'from one bay to the opposite one, across'),
        task((25.7, 6.1, NORTH), (33.9, 25.7), 'to the next bay but one, round two teeth'),
        task((20.0, 20.0, SOUTH), (25.7, 33.9), 'from the hub to a bay'),
    )
    return MapDesign(13, 'gear', 'gear', size, tuple(walls), tasks, 7.7,
                     'a round arena, 39.6 m across, with eight radial teeth 8.8 m long')
