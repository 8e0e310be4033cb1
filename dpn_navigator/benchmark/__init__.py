"""The benchmark of the paper's test protocol, run without ROS, in-process and in lockstep."""
