"""The ROS 2 side: the dpn node, its parameters, message conversions, QoS, names, spin, watchdog, markers, diagnostics, TF messages."""
