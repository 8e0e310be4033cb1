"""
The benchmark set: 34 map designs, numbered 1 to 34.

The Czech Technical University's motion-planning map set that the paper benchmarks on is not
available to us; these designs recreate its families (traps, narrow corridors, dense
obstacles, mazes, rooms, offices, open fields, spirals, tunnels, ...) and keep the paper's
named maps at the paper's numbers: 3 back_and_forth, 15 maze, 23 square_spiral,
26 tunnel_twisted and 27 tunnel. The others are numbered alphabetically around them.

"""

from . import maps_corridors, maps_mazes, maps_obstacles, maps_rooms, maps_traps

_MAKERS = (
    maps_corridors.alleys, maps_rooms.apartment, maps_corridors.back_and_forth,
    maps_traps.bug_trap, maps_rooms.campus, maps_obstacles.clutter, maps_traps.comb,
    maps_corridors.crossroads, maps_obstacles.dense, maps_mazes.double_spiral,
    maps_traps.double_trap, maps_obstacles.forest, maps_traps.gear, maps_corridors.l_corridor,
    maps_mazes.maze, maps_rooms.narrow_passages, maps_rooms.office, maps_obstacles.open_field,
    maps_obstacles.parking, maps_obstacles.potholes, maps_rooms.rooms, maps_corridors.slalom,
    maps_mazes.square_spiral, maps_mazes.t_maze, maps_corridors.town,
    maps_corridors.tunnel_twisted, maps_corridors.tunnel, maps_corridors.u_turn,
    maps_obstacles.village, maps_obstacles.warehouse, maps_mazes.wide_maze, maps_rooms.wings,
    maps_corridors.zigzag, maps_corridors.zigzag_narrow,
)

#: Every design, in number order.
DESIGNS = tuple(sorted((make() for make in _MAKERS), key=lambda design: design.number))
