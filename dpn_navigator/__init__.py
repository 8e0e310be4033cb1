"""dpn, the dynamic planner navigator: a ROS 2 navigator for unknown, dynamic environments."""
