"""
The integer codes the kernels compare cells with: the four cell labels and the scan inputs.

The core's `CellLabel` and `ScanInput` take their values from here, so the kernels (which
freeze these into their machine code) and the core cannot disagree. The kernels' cache is keyed
on this file too (``jit.sources_digest``).

"""

#: Cell labels (``CellLabel``), stored as uint8.
NON_EXPLORED = 0
EXPLORED = 1
STEADY_OBSTACLE = 2
MOBILE_OBSTACLE = 3

#: A cell's FSM input for one scan (``ScanInput``), ``2 * f1 + f2``: no input, inside the scan
#: polygon with no hit near (f2), within the safety radius of a hit (f1).
SCAN_NONE = 0
SCAN_INSIDE = 1
SCAN_HIT = 2
