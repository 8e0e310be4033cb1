"""
The navigation core: labelled occupancy grid, A*, path follower and navigator, with no ROS.

Everything here takes and returns plain floats and numpy arrays, so the ROS nodes, the batch
benchmark and other tools can drive the same code.

"""
