"""
Room maps: a flat, a campus of buildings, rooms joined by doors, and office floors.

Each function returns the `MapDesign` of one map of the benchmark set.

"""

from .design import EAST, hwall, MapDesign, MIN_PASSAGE, NORTH, outer_walls, SOUTH, task, \
    vwall, WEST
from .shapes import Rect


def _building(x0, y0, x1, y1, south=(), north=(), west=(), east=()):
    """Return the four walls of a building with door gaps ``(start, end)`` [m] on each side."""
    return (hwall(x0, x1, y0, south) + hwall(x0, x1, y1 - 0.2, north) +
            vwall(x0, y0, y1, west) + vwall(x1 - 0.2, y0, y1, east))


def apartment():
    """Return map 2: a small flat: a corridor, five rooms, 2.5 m doors, some furniture."""
    size = (20.0, 20.0)
    walls = outer_walls(*size)
    walls += hwall(0.2, 19.8, 8.0, [(2.5, 5.0), (9.0, 11.5), (15.5, 18.0)])
    walls += hwall(0.2, 19.8, 11.5, [(4.0, 6.5), (13.0, 15.5)])
    walls += vwall(7.0, 0.2, 8.0) + vwall(13.0, 0.2, 8.0) + vwall(10.0, 11.7, 19.8)
    walls += [Rect(0.2, 0.2, 2.4, 4.2), Rect(3.5, 14.5, 5.5, 16.5), Rect(17.8, 17.0, 19.8, 19.8),
              Rect(17.5, 0.2, 19.8, 2.0)]
    tasks = (
        task((4.5, 3.0, NORTH), (15.0, 15.5), 'bedroom to the opposite room, via the corridor'),
        task((16.5, 4.5, WEST), (2.0, 15.5), 'corner room to the living room'),
        task((10.1, 4.0, NORTH), (1.5, 9.85), 'middle room to the end of the corridor'),
    )
    return MapDesign(2, 'apartment', 'rooms', size, tuple(walls), tasks, 2.5,
                     'a flat: a 3.3 m corridor, five rooms with 2.5 m doors, furniture')


def campus():
    """Return map 5: six buildings with rooms and doors in open grounds."""
    size = (80.0, 60.0)
    walls = outer_walls(*size)
    walls += _building(5.0, 5.0, 25.0, 20.0, north=[(18.0, 21.0)])
    walls += vwall(15.0, 5.2, 19.8, [(11.0, 14.0)])
    walls += _building(35.0, 5.0, 55.0, 18.0, west=[(6.0, 9.0)], east=[(13.0, 16.0)])
    walls += hwall(35.2, 54.8, 11.5, [(43.0, 46.0)])
    walls += _building(62.0, 5.0, 76.0, 30.0, north=[(67.0, 70.0)])
    walls += hwall(62.2, 75.8, 17.5, [(68.0, 71.0)])
    walls += _building(5.0, 30.0, 22.0, 55.0, south=[(12.0, 15.0)], east=[(38.0, 41.0)])
    walls += vwall(13.5, 30.2, 54.8, [(45.0, 48.0)])
    walls += _building(30.0, 28.0, 50.0, 52.0, south=[(39.0, 42.0)], north=[(38.0, 41.0)])
    walls.append(Rect(36.0, 34.0, 44.0, 46.0))   # the inner court, closed
    walls += _building(58.0, 38.0, 76.0, 56.0, west=[(44.0, 47.0)], south=[(64.0, 67.0)])
    walls += vwall(67.0, 38.2, 55.8, [(50.0, 53.0)])
    tasks = (
        task((10.0, 12.0, EAST), (72.0, 48.0), 'from a room of one building to one across'),
        task((9.0, 42.0, SOUTH), (69.0, 10.0), 'building to building, diagonally'),
        task((3.0, 57.0, EAST), (33.0, 40.0), 'from the grounds into the ring building'),
    )
    return MapDesign(5, 'campus', 'rooms', size, tuple(walls), tasks, 3.0,
                     'six buildings with rooms and 3 m doors in 80 m x 60 m grounds')


def narrow_passages():
    """Return map 16: six rooms in a row of turns, joined by 2.0 m doors."""
    size = (30.0, 24.0)
    walls = outer_walls(*size)
    walls += vwall(10.0, 0.2, 12.0, [(3.0, 5.0)]) + vwall(20.0, 0.2, 12.0, [(8.0, 10.0)])
    walls += hwall(0.2, 29.8, 12.0, [(26.0, 28.0)])
    walls += vwall(20.0, 12.2, 23.8, [(19.0, 21.0)]) + vwall(10.0, 12.2, 23.8, [(14.0, 16.0)])
    walls += [Rect(4.0, 8.5, 6.0, 10.0), Rect(14.0, 3.0, 16.0, 5.5), Rect(24.0, 16.5, 26.0, 18.0)]
    tasks = (
        task((5.0, 5.0, NORTH), (5.0, 18.0), 'to the room next door, through the other five'),
        task((27.0, 20.0, SOUTH), (5.0, 5.0), 'back through four doors'),
        task((15.0, 8.0, EAST), (15.0, 19.0), 'middle room to middle room'),
    )
    return MapDesign(16, 'narrow_passages', 'rooms', size, tuple(walls), tasks, MIN_PASSAGE,
                     'six rooms in a ring, opened one into the next by 2.0 m doors')


def office():
    """Return map 17: an office floor: a 3 m corridor with offices on both sides."""
    size = (50.0, 30.0)
    walls = outer_walls(*size)
    below = (0.2, 8.0, 14.0, 20.0, 26.0, 32.0, 38.0, 44.0, 49.8)
    above = (0.2, 10.0, 20.0, 30.0, 40.0, 49.8)
    walls += hwall(0.2, 49.8, 13.3, [(a + 1.5, a + 4.0) for a in below[:-1]])
    walls += hwall(0.2, 49.8, 16.5, [(a + 5.0, a + 7.5) for a in above[:-1]])
    for x in below[1:-1]:
        walls += vwall(x, 0.2, 13.3)
    for x in above[1:-1]:
        walls += vwall(x, 16.7, 29.8)
    walls += [Rect(2.0, 20.0, 6.0, 26.0), Rect(33.0, 21.0, 37.0, 25.0)]   # tables
    tasks = (
        task((4.0, 4.0, NORTH), (45.0, 25.0), 'office to office at the far end, across'),
        task((47.0, 6.0, WEST), (15.0, 25.0), 'corner office to a meeting room'),
        task((25.0, 15.0, WEST), (17.0, 4.0), 'from the corridor into an office'),
    )
    return MapDesign(17, 'office', 'office', size, tuple(walls), tasks, 2.5,
                     'a 3 m corridor, eight offices and four meeting rooms, 2.5 m doors')


def rooms():
    """Return map 21: twelve 10 m rooms, each joined to one or two others by 3 m doors."""
    size = (40.0, 30.0)
    walls = outer_walls(*size)
    walls += vwall(10.0, 0.2, 10.0, [(3.5, 6.5)]) + vwall(10.0, 10.2, 20.0)
    walls += vwall(10.0, 20.2, 29.8, [(21.5, 24.5)])
    walls += vwall(20.0, 0.2, 10.0) + vwall(20.0, 10.2, 20.0, [(16.0, 19.0)])
    walls += vwall(20.0, 20.2, 29.8, [(25.0, 28.0)])
    walls += vwall(30.0, 0.2, 10.0, [(1.5, 4.5)]) + vwall(30.0, 10.2, 20.0)
    walls += vwall(30.0, 20.2, 29.8, [(24.0, 27.0)])
    walls += hwall(0.2, 39.8, 10.0, [(11.5, 14.5), (25.0, 28.0), (35.0, 38.0)])
    walls += hwall(0.2, 39.8, 20.0, [(4.0, 7.0), (13.0, 16.0), (32.0, 35.0)])
    tasks = (
        task((5.0, 5.0, NORTH), (5.0, 15.0), 'to the room above, which opens elsewhere'),
        task((35.0, 25.0, WEST), (15.0, 5.0), 'corner room to a bottom room'),
        task((25.0, 15.0, SOUTH), (35.0, 5.0), 'middle room to the bottom corner'),
    )
    return MapDesign(21, 'rooms', 'rooms', size, tuple(walls), tasks, 3.0,
                     'twelve 10 m rooms joined by 3 m doors into a winding chain')


def wings():
    """Return map 32: an office building of two wings joined by a cross corridor."""
    size = (50.0, 40.0)
    walls = outer_walls(*size)
    for x_corr in (8.0, 39.0):   # left face of each wing's 3 m corridor
        left, right = x_corr - 0.2, x_corr + 3.0
        edges = (0.2, 6.5, 13.0, 18.3, 21.7, 27.0, 33.5, 39.8)
        for k, (y0, y1) in enumerate(zip(edges[:-1], edges[1:])):
            if k == 3:
                continue   # the cross corridor
            door = [(y0 + 1.0, y0 + 3.5)] if y1 - y0 > 4.0 else []
            walls += vwall(left, y0, y1, door) + vwall(right, y0, y1, door)
        for y in edges[1:-1]:
            if y not in (18.3, 21.7):
                walls += hwall(0.2 if x_corr < 20.0 else right, left + 0.2 if x_corr < 20.0
                               else 49.8, y - 0.1)
    walls += hwall(11.2, 38.8, 18.1, [(23.0, 27.0)]) + hwall(11.2, 38.8, 21.7, [(23.0, 27.0)])
    walls += vwall(19.8, 0.2, 18.1) + vwall(19.8, 21.9, 39.8)
    walls += vwall(30.0, 0.2, 18.1) + vwall(30.0, 21.9, 39.8)
    tasks = (
        task((4.0, 3.5, NORTH), (46.0, 36.5), 'from an office of one wing to one of the other'),
        task((25.0, 10.0, NORTH), (4.0, 30.0), 'from the south hall to a west office'),
        task((46.0, 9.5, WEST), (25.0, 30.0), 'east office to the north hall'),
    )
    return MapDesign(32, 'wings', 'office', size, tuple(walls), tasks, 2.5,
                     'two office wings with 3 m corridors joined by a cross corridor and halls')
