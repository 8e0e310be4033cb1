"""
The navigation core: labelled occupancy grid, A*, path follower and navigator, with no ROS.

Everything here takes and returns plain floats and numpy arrays, so the ROS nodes, the batch
benchmark and other tools can drive the same code.

"""

from .cell_label import CellLabel, OCCUPANCY_VALUE
from .control.path_follower import follow_path, FollowerConfig, VelocityCommand
from .grid_geometry import GridGeometry
from .mapping.label_grid import LabelGrid
from .navigator import Navigator, NavigatorConfig, NavigatorOutput, NavigatorStatus
from .navigator import ReplanCause
from .planning.astar_search import astar, path_cost

__all__ = [
    'astar', 'CellLabel', 'follow_path', 'FollowerConfig', 'GridGeometry', 'LabelGrid',
    'Navigator', 'NavigatorConfig', 'NavigatorOutput', 'NavigatorStatus', 'OCCUPANCY_VALUE',
    'path_cost', 'ReplanCause', 'VelocityCommand',
]
