"""
Corridor maps: lanes, alleys, bends, slaloms, zig-zags, streets and tunnels.

Each function returns the `MapDesign` of one map of the benchmark set.

"""

from .design import EAST, MapDesign, MIN_PASSAGE, NORTH, outer_walls, RESOLUTION, SOUTH, task, \
    WEST
from .families import band, rock
from .shapes import Blocky, Free, Rect, Segment


def alleys():
    """Return map 1: a town of solid blocks between 2.0 m alleys, some of them closed."""
    size = (30.0, 30.0)
    bands = ((0.2, 2.2), (8.2, 10.2), (15.2, 17.2), (21.8, 23.8), (27.8, 29.8))
    blocks = [(a[1], b[0]) for a, b in zip(bands[:-1], bands[1:])]
    walls = outer_walls(*size)
    walls += [Rect(x0, y0, x1, y1) for x0, x1 in blocks for y0, y1 in blocks]
    # Alleys closed between two blocks: (i, j) to (i + 1, j) across an alley along y, and
    # (i, j) to (i, j + 1) across one along x; i counts blocks along x, j along y.
    for i, j in ((0, 1), (2, 2), (1, 3), (2, 0)):
        walls.append(Rect(blocks[i][1], blocks[j][0], blocks[i + 1][0], blocks[j][1]))
    for i, j in ((1, 0), (3, 1), (0, 2), (2, 1)):
        walls.append(Rect(blocks[i][0], blocks[j][1], blocks[i][1], blocks[j + 1][0]))
    tasks = (
        task((1.3, 1.3, EAST), (28.6, 28.6), 'corner to opposite corner, round the closed alleys'),
        task((28.8, 5.0, NORTH), (1.2, 20.0), 'east side to west side'),
        task((16.2, 16.2, NORTH), (9.2, 1.2), 'from the middle to the south side'),
    )
    return MapDesign(1, 'alleys', 'corridors', size, tuple(walls), tasks, MIN_PASSAGE,
                     'blocks of houses between 2.0 m alleys, some alleys closed')


def back_and_forth():
    """Return map 3, the paper's Fig. 9: five lanes joined by gaps at alternating ends."""
    size = (25.0, 20.0)
    walls = (
        Rect(0.0, 0.0, 25.0, 0.2),     # outer walls: bottom, top, left, right
        Rect(0.0, 19.8, 25.0, 20.0),
        Rect(0.0, 0.0, 0.2, 20.0),
        Rect(24.8, 0.0, 25.0, 20.0),
        Rect(0.2, 3.9, 19.0, 4.1),     # inner walls, gap on the right
        Rect(6.0, 7.9, 24.8, 8.1),     # gap on the left
        Rect(0.2, 11.9, 19.0, 12.1),   # gap on the right
        Rect(6.0, 15.9, 24.8, 16.1),   # gap on the left
    )
    tasks = (
        task((2.0, 2.0, 0.0), (2.0, 18.0),
             'bottom lane to top lane through all five lanes: about 74 m of path'),
        task((23.0, 2.0, 3.1416), (12.5, 10.0),
             'bottom-right corner to the middle lane, facing away from the first gap: about '
             '29 m'),
        task((12.5, 18.0, 0.0), (22.0, 6.0), 'top lane back down to the second lane: about 61 m'),
    )
    return MapDesign(3, 'back_and_forth', 'corridors', size, walls, tasks, 3.7,
                     "the paper's Fig. 9: five 3.7-3.8 m lanes joined at alternating ends")


def crossroads():
    """Return map 8: a roundabout round a square island, four roads to four halls."""
    size = (40.0, 40.0)
    walls = [Rect(0.0, 0.0, 40.0, 40.0)]
    walls += [Free(Rect(12.0, 12.0, 28.0, 28.0)), Rect(16.0, 16.0, 24.0, 24.0)]   # ring road
    walls += [Free(Rect(18.5, 0.2, 21.5, 12.0)), Free(Rect(18.5, 28.0, 21.5, 39.8)),
              Free(Rect(0.2, 18.5, 12.0, 21.5)), Free(Rect(28.0, 18.5, 39.8, 21.5))]
    walls += [Free(Rect(0.2, 0.2, 10.0, 10.0)), Free(Rect(30.0, 0.2, 39.8, 10.0)),
              Free(Rect(0.2, 30.0, 10.0, 39.8)), Free(Rect(30.0, 30.0, 39.8, 39.8))]
    # Each hall opens onto the road clockwise from it.
    walls += [Free(Rect(10.0, 3.5, 18.5, 6.5)), Free(Rect(33.5, 10.0, 36.5, 18.5)),
              Free(Rect(21.5, 33.5, 30.0, 36.5)), Free(Rect(3.5, 21.5, 6.5, 30.0))]
    tasks = (
        task((5.0, 5.0, NORTH), (35.0, 35.0), 'south-west hall to north-east hall'),
        task((2.0, 20.0, EAST), (38.0, 20.0), 'west road end to east road end, round the island'),
        task((35.0, 5.0, WEST), (20.0, 38.0), 'south-east hall to the north road'),
    )
    return MapDesign(8, 'crossroads', 'corridors', size, tuple(walls), tasks, 3.0,
                     'a 4 m ring road round a square island, 3 m roads to four corner halls')


def l_corridor():
    """Return map 14: a 3 m corridor with one right-angle bend between two rooms."""
    size = (30.0, 30.0)
    walls = [Rect(0.0, 0.0, 30.0, 30.0), Free(Rect(0.2, 0.2, 8.0, 8.0)),
             Free(Rect(22.0, 22.0, 29.8, 29.8)), Free(Rect(8.0, 2.5, 26.0, 5.5)),
             Free(Rect(23.0, 5.5, 26.0, 22.0))]
    tasks = (
        task((3.0, 4.0, EAST), (26.0, 27.0), 'room to room round the bend'),
        task((27.0, 25.0, SOUTH), (12.0, 4.0), 'far room back to the near end of the corridor'),
        task((24.5, 10.0, NORTH), (4.0, 6.0), 'from inside the corridor, facing away'),
    )
    return MapDesign(14, 'l_corridor', 'corridors', size, tuple(walls), tasks, 3.0,
                     'an L-shaped 3 m corridor between two rooms')


def slalom():
    """Return map 22: a long hall with baffles from alternate sides, 3 m gaps."""
    size = (40.0, 12.0)
    walls = outer_walls(*size)
    for k, x in enumerate(range(5, 36, 5)):
        walls.append(Rect(x, 0.2, x + 0.2, 8.8) if k % 2 == 0 else Rect(x, 3.2, x + 0.2, 11.8))
    tasks = (
        task((2.5, 6.0, EAST), (37.5, 6.0), 'end to end through all seven baffles'),
        task((37.5, 2.0, WEST), (12.5, 10.0), 'back half the way'),
        task((17.5, 6.0, NORTH), (32.5, 2.0), 'middle to the fourth bay on'),
    )
    return MapDesign(22, 'slalom', 'corridors', size, tuple(walls), tasks, 3.0,
                     'a 40 m hall with seven baffles leaving 3 m gaps at alternate sides')


def town():
    """Return map 25: city blocks and streets 4 to 6 m wide, with a park."""
    size = (70.0, 50.0)
    walls = outer_walls(*size)
    # Streets along x and along y, as (start, end); the blocks fill the rest.
    xs = ((0.2, 4.2), (16.0, 21.0), (33.0, 37.0), (50.0, 55.0), (65.8, 69.8))
    ys = ((0.2, 4.2), (14.0, 19.0), (30.0, 34.0), (45.8, 49.8))
    for (_, x0), (x1, _) in zip(xs[:-1], xs[1:]):
        for (_, y0), (y1, _) in zip(ys[:-1], ys[1:]):
            if (x0, y0) != (37.0, 19.0):   # the park
                walls.append(Rect(x0, y0, x1, y1))
    walls += [Free(Rect(8.0, 4.2, 12.0, 14.0)), Free(Rect(55.0, 37.0, 61.0, 41.0)),
              Rect(33.0, 4.2, 37.0, 14.0), Rect(4.2, 30.0, 16.0, 34.0),
              Rect(50.0, 19.0, 55.0, 25.0)]
    walls += [Rect(41.0, 22.0, 42.0, 23.0), Rect(46.0, 26.0, 47.0, 27.0)]   # park posts
    tasks = (
        task((2.2, 2.2, EAST), (67.8, 47.8), 'corner to opposite corner through the streets'),
        task((43.5, 24.5, WEST), (10.0, 47.8), 'from the park to the north street'),
        task((60.0, 2.2, WEST), (27.0, 16.5), 'round the closed street to a middle street'),
    )
    return MapDesign(25, 'town', 'corridors', size, tuple(walls), tasks, 4.0,
                     'city blocks, 4-6 m streets and a park')


def tunnel_twisted():
    """Return map 26: a tunnel that twists at slanted angles between two halls."""
    size = (50.0, 30.0)
    line = [(8.0, 15.0), (13.0, 15.0), (19.0, 24.0), (26.0, 24.0), (32.0, 8.0),
            (37.0, 8.0), (42.0, 15.0)]
    widths = [MIN_PASSAGE, 2.2, MIN_PASSAGE, 2.2, MIN_PASSAGE, 2.2]
    # Solid rock in 1 m blocks, but for the halls and every block the tunnel touches: the
    # slanted pieces are staircases, 2.2 m wide at least; the straight ones exactly 2.0 m.
    # (Finer steps make a pybullet box of every row of blocks, and slow the laser down.)
    passage = [shape for a, b, width in zip(line[:-1], line[1:], widths)
               for shape in band([a, b], width)]
    halls = [Rect(0.2, 0.2, 8.0, 29.8), Rect(42.0, 0.2, 49.8, 29.8)]
    walls = outer_walls(*size) + rock(size, halls + passage, step=1.0)
    tasks = (
        task((4.0, 15.0, EAST), (46.0, 15.0), 'hall to hall through the whole tunnel'),
        task((46.0, 26.0, SOUTH), (4.0, 4.0), 'back, from corner to corner'),
        task((22.5, 24.0, WEST), (46.0, 4.0), 'from the middle of the tunnel, facing back'),
    )
    return MapDesign(26, 'tunnel_twisted', 'tunnel', size, tuple(walls), tasks, MIN_PASSAGE,
                     'a tunnel twisting between two halls: 2.0 m straight, 2.2-3 m slanted pieces')


def tunnel():
    """Return map 27: a 2.0 m tunnel with right-angle bends between two halls."""
    size = (60.0, 20.0)
    line = [(12.0, 10.0), (24.0, 10.0), (24.0, 5.0), (36.0, 5.0), (36.0, 14.0), (48.0, 14.0)]
    walls = outer_walls(*size) + [Rect(12.0, 0.2, 48.0, 19.8)]
    walls += [Free(shape) for shape in band(line, MIN_PASSAGE)]
    tasks = (
        task((5.0, 10.0, EAST), (55.0, 10.0), 'hall to hall through the tunnel'),
        task((55.0, 3.0, WEST), (6.0, 17.0), 'back, from corner to corner'),
        task((30.0, 5.0, WEST), (54.0, 17.0), 'from the middle of the tunnel, facing back'),
    )
    return MapDesign(27, 'tunnel', 'tunnel', size, tuple(walls), tasks, MIN_PASSAGE,
                     'a 2.0 m tunnel with four right-angle bends between two halls')


def u_turn():
    """Return map 28: a 3 m corridor that turns back on itself round a long wall."""
    size = (30.0, 20.0)
    walls = [Rect(0.0, 0.0, 30.0, 20.0), Free(Rect(0.2, 2.0, 27.0, 5.0)),
             Free(Rect(24.0, 5.0, 27.0, 15.0)), Free(Rect(0.2, 15.0, 27.0, 18.0)),
             Free(Rect(0.2, 5.0, 5.0, 9.0))]
    tasks = (
        task((2.0, 3.5, EAST), (2.0, 16.5), 'one end of the U to the other'),
        task((2.5, 7.0, SOUTH), (15.0, 16.5), 'from the side room to the upper leg'),
        task((20.0, 16.5, WEST), (25.5, 3.5), 'upper leg, facing away, to the lower bend'),
    )
    return MapDesign(28, 'u_turn', 'corridors', size, tuple(walls), tasks, 3.0,
                     'a 3 m U-shaped corridor with a side room')


def zigzag():
    """Return map 33: a hall crossed by slanted baffles that force a zig-zag route."""
    size = (40.0, 24.0)
    walls = outer_walls(*size)
    for k, x in enumerate((10.0, 20.0, 30.0)):
        if k % 2 == 0:
            baffle = Segment(x - 3.0, 0.2, x + 3.0, 18.0, 0.3)
        else:
            baffle = Segment(x - 3.0, 23.8, x + 3.0, 6.0, 0.3)
        # A staircase of 1 m blocks: drawn pixel by pixel it would make a box of every row.
        walls.append(Blocky(baffle, 1.0, RESOLUTION))
    tasks = (
        task((2.0, 12.0, EAST), (38.0, 12.0), 'across every baffle'),
        task((38.0, 21.0, WEST), (3.0, 12.0), 'back all the way'),
        task((14.0, 12.0, NORTH), (35.0, 12.0), 'from the first bay past two baffles'),
    )
    return MapDesign(33, 'zigzag', 'corridors', size, tuple(walls), tasks, 3.1,
                     'three slanted baffles, staircases of 1 m blocks, from alternate sides')


def zigzag_narrow():
    """Return map 34: a 2.0 m staircase corridor climbing across the map."""
    size = (40.0, 24.0)
    line = [(3.0, 2.0), (10.0, 2.0), (10.0, 8.0), (18.0, 8.0), (18.0, 14.0), (26.0, 14.0),
            (26.0, 20.0), (37.0, 20.0)]
    walls = [Rect(0.0, 0.0, 40.0, 24.0), Free(Rect(0.2, 0.2, 6.0, 7.0)),
             Free(Rect(33.0, 17.0, 39.8, 23.8))]
    walls += [Free(shape) for shape in band(line, MIN_PASSAGE)]
    tasks = (
        task((3.0, 4.5, EAST), (36.5, 21.0), 'bottom room to top room up every step'),
        task((36.0, 18.5, WEST), (14.0, 8.0), 'top room to the second step'),
        task((18.0, 11.0, SOUTH), (30.0, 20.0), 'from a riser, facing down, to the top room'),
    )
    return MapDesign(34, 'zigzag_narrow', 'corridors', size, tuple(walls), tasks, MIN_PASSAGE,
                     'a 2.0 m corridor climbing in steps between two rooms')
