"""
Obstacle maps: posts, trees, holes, houses, parked cars and racks.

Clutter, dense posts, a forest, potholes, an open field, a car park, a village and a warehouse.

Scattered obstacles come from `families.scatter` with a fixed seed and keep 2.6 m gaps (more
where said); the tasks' positions are kept free of them. Each function returns the `MapDesign`
of one map of the benchmark set.

"""

from .design import EAST, MapDesign, NORTH, outer_walls, random_stream, SOUTH, task, WEST
from .families import runs_of, scatter
from .shapes import Disc, Rect


def _keep_out(tasks, radius=2.0):
    """Return discs of ``radius`` [m] round every start and goal of the tasks."""
    return [(x, y, radius) for spec in tasks for x, y in (spec.start[:2], spec.goal)]


def clutter():
    """Return map 6: boxes of many sizes strewn over a square room."""
    size = (30.0, 30.0)
    tasks = (
        task((2.5, 2.5, EAST), (27.5, 27.5), 'corner to opposite corner through the clutter'),
        task((27.5, 2.5, NORTH), (2.5, 27.5), 'the other diagonal'),
        task((15.0, 2.5, NORTH), (15.0, 27.5), 'bottom to top'),
    )
    walls = outer_walls(*size) + scatter((0.2, 0.2, 29.8, 29.8), 40, (0.6, 2.6), seed=6,
                                         keep_out=_keep_out(tasks))
    return MapDesign(6, 'clutter', 'dense', size, tuple(walls), tasks, 3.4,
                     'boxes of 0.6 to 2.6 m strewn at random, 2.6 m apart at least')


def dense():
    """Return map 9: many small square and round posts, close together."""
    size = (25.0, 25.0)
    tasks = (
        task((2.0, 2.0, EAST), (23.0, 23.0), 'corner to opposite corner'),
        task((2.0, 12.5, EAST), (23.0, 12.5), 'side to side'),
        task((12.5, 23.0, SOUTH), (12.5, 2.0), 'top to bottom'),
    )
    walls = outer_walls(*size) + scatter((0.2, 0.2, 24.8, 24.8), 60, (0.3, 0.6), seed=9,
                                         gap=2.5, round_share=0.3,
                                         keep_out=_keep_out(tasks, 1.5))
    return MapDesign(9, 'dense', 'dense', size, tuple(walls), tasks, 3.0,
                     'small square and round posts, 2.5 m apart')


def forest():
    """Return map 12: round trunks of many sizes, and a clearing."""
    size = (50.0, 50.0)
    tasks = (
        task((3.0, 3.0, EAST), (47.0, 47.0), 'through the forest, corner to corner'),
        task((3.0, 47.0, SOUTH), (25.0, 25.0), 'from a corner to the clearing'),
        task((47.0, 25.0, WEST), (3.0, 25.0), 'side to side'),
    )
    keep = _keep_out(tasks, 2.0) + [(25.0, 25.0, 5.0)]
    walls = outer_walls(*size) + scatter((0.2, 0.2, 49.8, 49.8), 50, (0.4, 1.2), seed=12,
                                         gap=3.0, round_share=1.0, round_step=0.2,
                                         keep_out=keep)
    return MapDesign(12, 'forest', 'dense', size, tuple(walls), tasks, 5.0,
                     '50 round trunks 0.4 to 1.2 m thick, 3 m apart at least, a clearing')


def open_field():
    """Return map 18: a large, nearly empty field with a few obstacles."""
    size = (60.0, 60.0)
    walls = outer_walls(*size) + [
        Rect(14.0, 38.0, 24.0, 41.0), Rect(38.0, 14.0, 41.0, 26.0), Disc(30.0, 30.0, 2.0),
        Rect(44.0, 44.0, 46.0, 52.0), Rect(10.0, 12.0, 13.0, 15.0), Disc(20.0, 50.0, 1.0),
    ]
    tasks = (
        task((3.0, 3.0, EAST), (57.0, 57.0), 'corner to opposite corner'),
        task((57.0, 3.0, WEST), (3.0, 57.0), 'the other diagonal'),
        task((30.0, 10.0, NORTH), (30.0, 50.0), 'past the central disc'),
    )
    return MapDesign(18, 'open_field', 'open', size, tuple(walls), tasks, 11.8,
                     'a nearly empty 60 m field with six obstacles')


def parking():
    """Return map 19: a car park: rows of parked cars, columns, 6 m aisles."""
    size = (60.0, 40.0)
    walls = outer_walls(*size)
    # Rows of 2.5 m bays along x, as (y_min, y_max); the double rows have columns in the middle.
    rows = ((0.2, 4.7), (10.7, 15.2), (15.2, 19.7), (25.7, 30.2), (30.2, 34.7))
    blocks = ((5.0, 27.5), (32.5, 55.0))   # bays, either side of a 5 m cross aisle
    rand = random_stream(19)
    for y0, y1 in rows:
        for x0, x1 in blocks:
            taken = [next(rand) > 0.2 for _ in range(int(round((x1 - x0) / 2.5)))]
            walls += [Rect(x0 + 2.5 * a + 0.25, y0, x0 + 2.5 * b - 0.25, y1)
                      for a, b in runs_of(taken)]
    walls += [Rect(x - 0.3, y - 0.3, x + 0.3, y + 0.3)
              for x in (5.0, 15.0, 25.0, 35.0, 45.0, 55.0) for y in (15.2, 30.2)]
    tasks = (
        task((2.5, 22.7, EAST), (58.0, 22.7), 'along the middle aisle to the far end'),
        task((2.5, 2.5, NORTH), (57.5, 37.5), 'corner to opposite corner'),
        task((30.0, 7.7, NORTH), (12.0, 37.2), 'across the cross aisle to the top aisle'),
    )
    return MapDesign(19, 'parking', 'dense', size, tuple(walls), tasks, 5.1,
                     'a car park: rows of parked cars, columns, 6 m aisles and a 5 m cross aisle')


def potholes():
    """Return map 20: large square and round holes fenced off in an open yard."""
    size = (40.0, 30.0)
    tasks = (
        task((2.5, 15.0, EAST), (37.5, 15.0), 'across the yard'),
        task((2.5, 2.5, NORTH), (37.5, 27.5), 'corner to opposite corner'),
        task((20.0, 27.5, SOUTH), (20.0, 2.5), 'top to bottom'),
    )
    walls = outer_walls(*size) + scatter((0.2, 0.2, 39.8, 29.8), 20, (1.0, 3.0), seed=20,
                                         gap=2.8, round_share=0.5, round_step=0.5,
                                         keep_out=_keep_out(tasks))
    return MapDesign(20, 'potholes', 'dense', size, tuple(walls), tasks, 4.0,
                     'square and round holes 1 to 3 m across, 2.8 m apart at least')


def village():
    """Return map 29: houses of many sizes scattered over a large area, and some trees."""
    size = (70.0, 50.0)
    tasks = (
        task((3.0, 3.0, EAST), (67.0, 47.0), 'corner to opposite corner'),
        task((67.0, 3.0, NORTH), (3.0, 47.0), 'the other diagonal'),
        task((35.0, 25.0, WEST), (3.0, 25.0), 'from the village square to the west side'),
    )
    keep = _keep_out(tasks, 2.5) + [(35.0, 25.0, 5.0)]
    walls = outer_walls(*size)
    walls += scatter((0.2, 0.2, 69.8, 49.8), 28, (3.0, 7.0), seed=29, gap=4.0, keep_out=keep)
    walls += scatter((0.2, 0.2, 69.8, 49.8), 12, (0.6, 1.0), seed=290, gap=8.0,
                     round_share=1.0, keep_out=keep)
    return MapDesign(29, 'village', 'open', size, tuple(walls), tasks, 5.9,
                     'houses 3 to 7 m across scattered over 70 m x 50 m, with trees')


def warehouse():
    """Return map 30: rows of racks with 3 m aisles, cross aisles and a loading area."""
    size = (60.0, 40.0)
    walls = outer_walls(*size)
    for x0, x1 in ((4.0, 18.0), (22.0, 36.0), (40.0, 52.0)):
        walls += [Rect(x0, y - 0.6, x1, y + 0.6) for y in range(4, 33, 4)]
    tasks = (
        task((57.0, 20.0, WEST), (11.0, 30.0), 'from the loading area into a far aisle'),
        task((11.0, 6.0, EAST), (44.0, 34.0), 'aisle to aisle, across two rack blocks'),
        task((29.0, 18.0, NORTH), (56.0, 3.0), 'from an aisle to the loading area'),
    )
    return MapDesign(30, 'warehouse', 'warehouse', size, tuple(walls), tasks, 2.8,
                     'three blocks of 1.2 m deep racks with 2.8 m aisles, and a loading area')
