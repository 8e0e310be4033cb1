"""
Maze and spiral maps: grid mazes, a tree of T-junctions, and square spirals.

Each function returns the `MapDesign` of one map of the benchmark set.

"""

from .design import EAST, MapDesign, MIN_PASSAGE, NORTH, outer_walls, SOUTH, task, WALL, WEST
from .families import band, maze as maze_walls, polyline_walls, spiral_points
from .shapes import Free, Rect


def double_spiral():
    """Return map 10: two interleaved square spiral walls, two corridors meeting at the centre."""
    size = (34.0, 34.0)
    pitch = 7.4   # between the turns of one wall; the other wall's turns lie halfway
    x0, y0 = 15.2, 15.2
    first = spiral_points((0.0, 0.0), pitch, 6)
    # The second wall is the first turned by half a turn about (pitch / 4, pitch / 4).
    second = [(0.5 * pitch - x, 0.5 * pitch - y) for x, y in first]
    walls = outer_walls(*size)
    for points in (first, second):
        walls += polyline_walls([(round(x0 + x, 6), round(y0 + y, 6)) for x, y in points])
    tasks = (
        task((2.0, 2.0, EAST), (17.0, 17.0), 'from outside along a spiral corridor to the centre'),
        task((17.0, 17.0, NORTH), (32.0, 32.0), 'from the centre out to a corner'),
        task((9.6, 17.0, SOUTH), (24.4, 17.0), 'from one corridor to the other'),
    )
    return MapDesign(10, 'double_spiral', 'spiral', size, tuple(walls), tasks, 3.5,
                     'two interleaved square spiral walls; 3.5 m corridors meet at the centre')


def maze():
    """Return map 15: a 10 x 10 grid maze of 2.0 m corridors with two 4.2 m rooms."""
    cells = 10
    pitch = MIN_PASSAGE + WALL
    size = (round(cells * pitch + WALL, 6),) * 2
    walls = maze_walls((0.0, 0.0), (cells, cells), MIN_PASSAGE, seed=15,
                       rooms=((0, 0, 2, 2), (8, 8, 2, 2)), loops=5)

    def centre(c, r):
        return (round(WALL + (c + 0.5) * pitch - 0.5 * WALL, 6),
                round(WALL + (r + 0.5) * pitch - 0.5 * WALL, 6))

    tasks = (
        task((*centre(0.5, 0.5), EAST), centre(8.5, 8.5), 'room to room across the maze'),
        task((*centre(9, 0), WEST), centre(0, 9), 'corner to corner'),
        task((*centre(8.5, 8.5), SOUTH), centre(5, 4), 'from a room to the middle'),
    )
    return MapDesign(15, 'maze', 'maze', size, tuple(walls), tasks, MIN_PASSAGE,
                     '10 x 10 cells of 2.0 m corridors, a few loops, a room in two corners')


def square_spiral():
    """Return map 23: a square spiral of 2.0 m corridors entered from a hall."""
    pitch = MIN_PASSAGE + WALL
    cx, cy = 11.7, 4.5
    size = (round(cx + 4 * pitch + 0.1, 6), round(cy + 4 * pitch + 0.1, 6))
    walls = [Rect(0.0, 0.0, size[0], 0.2), Rect(0.0, size[1] - 0.2, size[0], size[1]),
             Rect(0.0, 0.0, 0.2, size[1])]
    walls += polyline_walls(spiral_points((cx, cy), pitch, 11, first=2))
    tasks = (
        task((3.5, 6.7, EAST), (12.8, 6.7), 'from the hall round every turn to the centre'),
        task((12.8, 6.7, WEST), (3.5, 11.0), 'from the centre out to the hall'),
        task((19.4, 8.0, NORTH), (12.8, 6.7), 'from the outer turn, facing out, to the centre'),
    )
    return MapDesign(23, 'square_spiral', 'spiral', size, tuple(walls), tasks, MIN_PASSAGE,
                     'a square spiral of 2.0 m corridors, five turns, entered from a hall')


def t_maze():
    """Return map 24: a tree of T-junctions with 2.6 m corridors and eight dead ends."""
    size = (24.0, 24.0)
    lines = ([(12.0, 1.5), (12.0, 12.0)], [(6.0, 12.0), (18.0, 12.0)],
             [(6.0, 6.0), (6.0, 18.0)], [(18.0, 6.0), (18.0, 18.0)],
             [(3.0, 6.0), (9.0, 6.0)], [(3.0, 18.0), (9.0, 18.0)],
             [(15.0, 6.0), (21.0, 6.0)], [(15.0, 18.0), (21.0, 18.0)])
    walls = [Rect(0.0, 0.0, 24.0, 24.0)]
    walls += [Free(shape) for line in lines for shape in band(line, 2.6)]
    walls.append(Free(Rect(9.0, 0.2, 15.0, 3.0)))
    tasks = (
        task((12.0, 1.6, NORTH), (20.7, 18.0), 'from the entrance to a leaf, three junctions'),
        task((3.3, 6.0, EAST), (20.7, 18.0), 'leaf to the farthest leaf'),
        task((8.7, 18.0, WEST), (12.0, 1.6), 'leaf back to the entrance'),
    )
    return MapDesign(24, 't_maze', 'maze', size, tuple(walls), tasks, 2.6,
                     'a tree of T-junctions, 2.6 m corridors, eight dead ends')


def wide_maze():
    """Return map 31: a 11 x 11 grid maze of 3.0 m corridors with many loops."""
    cells = 11
    pitch = 3.0 + WALL
    size = (round(cells * pitch + WALL, 6),) * 2
    walls = maze_walls((0.0, 0.0), (cells, cells), 3.0, seed=31, loops=25,
                       rooms=((4, 4, 3, 3),))

    def centre(c, r):
        return (round(WALL + (c + 0.5) * pitch - 0.5 * WALL, 6),
                round(WALL + (r + 0.5) * pitch - 0.5 * WALL, 6))

    tasks = (
        task((*centre(0, 0), NORTH), centre(10, 10), 'corner to opposite corner'),
        task((*centre(5, 5), WEST), centre(0, 10), 'from the central room to a corner'),
        task((*centre(10, 0), WEST), centre(5, 5), 'from a corner to the central room'),
    )
    return MapDesign(31, 'wide_maze', 'maze', size, tuple(walls), tasks, 3.0,
                     '11 x 11 cells of 3.0 m corridors, many loops, a room at the centre')
