"""
Trails: mobile cells that a followed object left behind go back to explored.

Every scan marks, in the grid's ``cell_track``, the cells within the safety radius of a hit of a
followed object (``motion_tracks``) with that object's track, and lists them. A listed cell that
is still mobile and still marked goes back to explored, unmarked, once the scan does not see it
(f1 = f2 = 0) and sees its object at least ``trail_distance`` from it: the object has moved on.

`update_trails` is one compiled kernel per scan over the scan's window and the listed cells;
the numpy implementation it replaced is the oracle of the tests
(``test/numpy_label_grid.NumpyExtrasLabelGrid``).

"""

from .._kernels import trails as trail_kernels
from ..cell_label import CellLabel, ScanInput
from ..grid_geometry import squared_bound

_EXPLORED = int(CellLabel.EXPLORED)
_MOBILE = int(CellLabel.MOBILE_OBSTACLE)
_HIT = int(ScanInput.HIT)
_NONE = int(ScanInput.NONE)


def update_trails(cell_track, labels, marked, geometry, window, hits_x, hits_y, hit_ids,
                  track_ids, positions, last_seen, stamp, safety_radius, trail_distance):
    """
    Mark the cells of the followed objects' hits, then clear the trails they left.

    Parameters
    ----------
    cell_track : (rows, cols) ndarray of int64
        Track of each cell's last marking hit, -1 for none; updated in place.
    labels : (rows, cols) ndarray of uint8
        The grid's labels after the scan's update; trail cells are set to explored.
    marked : (M,) ndarray of int64
        Flat indices of the cells that may hold a mark (repeats allowed): every cell of
        ``cell_track`` that holds one is among them.
    geometry : GridGeometry
        The grid's geometry.
    window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
        The scan's window and FSM input (``LabelGrid.last_window``), not empty.
    hits_x, hits_y : (K,) ndarray of float64
        The scan's hits [m].
    hit_ids : (K,) ndarray of int64
        The track each hit's segment continued, -1 for none (``MotionTracks.hit_ids``).
    track_ids : (T,) ndarray of int64
        The tracks (``MotionTracks.ids``).
    positions : (T, 2) ndarray of float64
        Their positions [m].
    last_seen : (T,) ndarray of float64
        When a segment last continued each [s].
    stamp : float
        The scan's time [s].
    safety_radius, trail_distance : float
        f1's ``r`` and ``LabelRule.trail_distance`` [m].

    Returns
    -------
    marked : (M',) ndarray of int64
        The cells that may hold a mark now.
    cleared : (slice, slice)
        A box around the cells set to explored (empty slices when none).

    """
    rows, cols, cell_input = window
    x0, y0 = geometry.origin
    marked, row_lo, row_hi, col_lo, col_hi = trail_kernels.update_trails(
        cell_track, labels, marked, rows.start, cols.start, cell_input, x0, y0,
        geometry.resolution, hits_x, hits_y, hit_ids, track_ids, positions, last_seen,
        float(stamp), float(safety_radius), squared_bound(float(safety_radius)),
        float(trail_distance))
    return marked, (slice(row_lo, max(row_lo, row_hi)), slice(col_lo, max(col_lo, col_hi)))
