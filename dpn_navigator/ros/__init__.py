"""
The ROS 2 side: the dpn node and the parts it wires.

Its parameters, message conversions, QoS, names, spin, watchdog, markers, diagnostics and TF
messages; ``sim_bridge`` reuses them.

"""
