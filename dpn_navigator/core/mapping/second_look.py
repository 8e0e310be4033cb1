"""
Free evidence needs a second look (``LabelRule.free_first_sight``).

dpn's motion evidence is a hit in space once surely seen empty (the coarse ``seen_free`` of
the label grid and the fine one of ``FineEvidence``). The first scan that shows a place, at
the start of a recording or where space is first seen, takes for empty the place of a surface
that returned no echo in that one scan (a dark surface, an echo lost); its echo in the next
scans then looks like motion. The burn-in (``free_burn_in``) cannot hold it back: no hit has
come near the place before.

With a second look a cell counts as surely free only from a scan at least ``first_sight``
after the first scan that showed it empty. Each cell keeps that first time (``first_free``,
+inf before). The marks a scan adds are taken back after the scan, within the window the scan
can mark: no compiled kernel changes, and nothing to do for cells already marked.
"""

import math

import numpy as np


def scan_window(geometry, pose, reach):
    """
    Return the ``(rows, cols)`` slices of ``geometry``'s cells within ``reach`` of a laser.

    Parameters
    ----------
    geometry : GridGeometry
        The grid's placement.
    pose : sequence of float
        The laser's ``(x, y, ...)`` in the grid's frame [m].
    reach : float
        How far from the laser a scan can mark a cell [m] (its ``range_max`` plus the disc's
        radius), >= 0; one cell is added on each side.

    """
    x0, y0 = geometry.origin
    resolution = geometry.resolution
    reach = float(reach) + resolution
    col0 = min(max(int(math.floor((pose[0] - reach - x0) / resolution)), 0), geometry.cols)
    col1 = min(max(int(math.ceil((pose[0] + reach - x0) / resolution)) + 1, col0),
               geometry.cols)
    row0 = min(max(int(math.floor((pose[1] - reach - y0) / resolution)), 0), geometry.rows)
    row1 = min(max(int(math.ceil((pose[1] + reach - y0) / resolution)) + 1, row0),
               geometry.rows)
    return slice(row0, row1), slice(col0, col1)


def hold_back(seen_free, first_free, window, before, stamp, first_sight):
    """
    Take back a scan's marks on cells first shown empty less than ``first_sight`` ago.

    Parameters
    ----------
    seen_free : (rows, cols) ndarray of bool
        The surely-free cells after the scan marked them, changed in place.
    first_free : (rows, cols) ndarray of float64
        Per cell the time of the first scan that showed it empty [s] (+inf: none yet);
        cells this scan marks for the first time get ``stamp``, in place.
    window : tuple of slice
        The cells the scan can have marked (`scan_window`).
    before : ndarray of bool
        ``seen_free[window]`` before the scan.
    stamp : float
        The scan's time [s].
    first_sight : float
        The wait [s], > 0.

    Returns
    -------
    int
        How many marks were taken back.

    """
    marked = seen_free[window]
    new = marked & ~before
    if not new.any():
        return 0
    first = first_free[window]
    first[new & np.isinf(first)] = stamp
    young = new & (stamp - first < first_sight)
    marked[young] = False
    return int(young.sum())
