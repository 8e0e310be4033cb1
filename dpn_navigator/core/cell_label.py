"""
The four cell labels, their finite state machine, and the values they publish as.

The FSM is the paper's Fig. 4 as this project adopts it (the figure is not in our copy of the
paper). Inputs per cell and scan are ``(f1, f2)``; ``(1, 1)`` cannot occur because f2 is forced
to 0 wherever f1 is 1.

===================  ==================  ==================  ============
state                (f1, f2) = (1, 0)   (f1, f2) = (0, 1)   (0, 0)
===================  ==================  ==================  ============
non-explored         steady obstacle     explored            non-explored
explored             mobile obstacle     explored            explored
steady obstacle      steady obstacle     explored            steady
mobile obstacle      mobile obstacle     explored            mobile
===================  ==================  ==================  ============

"""

import enum

import numpy as np

from ._kernels import codes

#: dtype of every label array.
LABEL_DTYPE = np.uint8


class CellLabel(enum.IntEnum):
    """Label of one occupancy-grid cell; stored as ``LABEL_DTYPE``."""

    NON_EXPLORED = codes.NON_EXPLORED
    EXPLORED = codes.EXPLORED
    STEADY_OBSTACLE = codes.STEADY_OBSTACLE
    MOBILE_OBSTACLE = codes.MOBILE_OBSTACLE


class ScanInput(enum.IntEnum):
    """The FSM input of one cell for one scan, ``2 * f1 + f2``."""

    NONE = codes.SCAN_NONE          # (f1, f2) = (0, 0)
    INSIDE = codes.SCAN_INSIDE      # (0, 1): inside the scan polygon, no hit near
    HIT = codes.SCAN_HIT            # (1, 0): within the safety radius of a laser hit point


def _transition_table():
    table = np.empty((len(CellLabel), len(ScanInput)), dtype=LABEL_DTYPE)
    for label in CellLabel:
        table[label, ScanInput.NONE] = label
        table[label, ScanInput.INSIDE] = CellLabel.EXPLORED
    table[CellLabel.NON_EXPLORED, ScanInput.HIT] = CellLabel.STEADY_OBSTACLE
    table[CellLabel.EXPLORED, ScanInput.HIT] = CellLabel.MOBILE_OBSTACLE
    table[CellLabel.STEADY_OBSTACLE, ScanInput.HIT] = CellLabel.STEADY_OBSTACLE
    table[CellLabel.MOBILE_OBSTACLE, ScanInput.HIT] = CellLabel.MOBILE_OBSTACLE
    table.setflags(write=False)
    return table


#: ``TRANSITION[label, scan_input]`` is the next label, shape (4, 3), dtype ``LABEL_DTYPE``.
TRANSITION = _transition_table()


def _transition_by_code():
    table = np.zeros(4 * len(CellLabel), dtype=LABEL_DTYPE)
    for label in CellLabel:
        for scan_input in ScanInput:
            table[(label << 2) | scan_input] = TRANSITION[label, scan_input]
    table.setflags(write=False)
    return table


#: `TRANSITION` flattened for one lookup, ``TRANSITION_BY_CODE[(label << 2) | scan_input]``,
#: shape (16,), dtype ``LABEL_DTYPE``: the table the label kernels take as an argument (so that
#: no kernel freezes the FSM into its machine code).
TRANSITION_BY_CODE = _transition_by_code()

#: Labels that planning treats as blocked (non-explored counts as free, the paper's rule).
BLOCKED_LABELS = (CellLabel.STEADY_OBSTACLE, CellLabel.MOBILE_OBSTACLE)

# nav_msgs/OccupancyGrid values, named once (like Nav2's cost_values.hpp).
OCCUPANCY_UNKNOWN = -1
OCCUPANCY_FREE = 0
OCCUPANCY_STEADY_OBSTACLE = 100
#: In 65..99: above map_server's usual 0.65 occupied threshold, drawn grey by RViz.
OCCUPANCY_MOBILE_OBSTACLE = 70

#: ``OCCUPANCY_VALUE[label]`` is the OccupancyGrid value a label publishes as, dtype int8.
OCCUPANCY_VALUE = np.array(
    [OCCUPANCY_UNKNOWN, OCCUPANCY_FREE, OCCUPANCY_STEADY_OBSTACLE, OCCUPANCY_MOBILE_OBSTACLE],
    dtype=np.int8)
OCCUPANCY_VALUE.setflags(write=False)


def blocked_mask(labels):
    """
    Cells that planning must avoid.

    Parameters
    ----------
    labels : (H, W) ndarray of uint8
        Cell labels.

    Returns
    -------
    blocked : (H, W) ndarray of bool
        True for steady and mobile obstacle cells.

    """
    return np.asarray(labels) >= CellLabel.STEADY_OBSTACLE
