"""The pybullet world that stands in for Gazebo: Husky, laser range finder, wandering P3-ATs."""
