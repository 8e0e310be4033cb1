"""
The compiled label update: one scan folded into a window of the grid, in place.

`scan_update` does, for the window the scan can reach, everything ``LabelGrid.update`` does
per cell: f2 by even-odd crossings along each row, f1 as the cells within the safety radius of
each hit, the FSM, and the dpn ``LabelRule`` (conservative free space, object-level
relabelling, the hit clock of the ghost expiry). `expire_listed` is the ghost expiry itself,
visiting only the cells listed as mobile, not the whole grid.

Every test is the floating-point expression of the literal twin in the tests
(``test/reference/literal_reference.py``), evaluated in the same order, so the result equals it
cell for cell:

- f1 and every disc: ``dx * dx + dy * dy <= bound`` with ``bound`` from
  ``grid_geometry.squared_radius_bound`` (the same answers as ``sqrt(...) <= r``);
- f2: edge ``(a, b)`` crosses the ray from centre ``(x, y)`` along +x when
  ``(y_a > y) != (y_b > y)`` and ``x < x_a + (x_b - x_a) * (y - y_a) / (y_b - y_a)``;
- an edge band as in ``free_evidence``: ``0 <= dot <= length2`` and
  ``abs(cross) / sqrt(length2) <= radius``.

The work grows with the beams and the window's cells, never with the grid.

"""

import math

import numpy as np

from .._kernels import free_space, motion_evidence, scan_window
from .._kernels import scan_labels as label_kernels
from ..cell_label import CellLabel, ScanInput, TRANSITION, TRANSITION_BY_CODE
from ..grid_geometry import squared_bound

# The update writes f2 cells as explored and leaves cells without input alone, under every
# rule, without looking the table up: the paper's FSM says so for every label.
if not ((TRANSITION[:, ScanInput.INSIDE] == CellLabel.EXPLORED).all()
        and (TRANSITION[:, ScanInput.NONE] == np.arange(len(CellLabel))).all()):
    raise ImportError('label_update expects f2 cells to become explored and cells without '
                      'input to keep their label (cell_label.TRANSITION)')

#: `scan_update` without extra moving hits.
_NO_HITS = np.zeros(0, dtype=bool)
#: `surely_free_update` without the burn-in.
_NO_STAMPS = np.zeros((1, 1), dtype=np.float64)


def surely_free_update(seen_free, geometry, pose, ranges, angle_min, angle_increment,
                       range_min, range_max, radius, hit_stamp=None, fresh_after=0.0):
    """
    Fold one checked scan into ``seen_free`` alone: the conservative free space of a grid.

    The same cells ``scan_update`` marks in ``seen_free`` under a ``LabelRule`` with only
    ``free_evidence_radius = radius`` on and a safety radius of ``radius``, without the labels;
    with ``hit_stamp``, only those a hit has not come within ``radius`` of since
    ``fresh_after`` (the burn-in, ``FineEvidence``).

    Parameters
    ----------
    seen_free : (rows, cols) ndarray of bool
        Cells once surely seen free, updated in place.
    geometry : GridGeometry
        The grid's placement.
    pose, ranges, angle_min, angle_increment, range_min, range_max
        As in `scan_update`, checked.
    radius : float
        A cell is surely free when its disc of this radius lies inside the polygon [m], > 0.
    hit_stamp : (rows, cols) ndarray of float64, optional
        Per cell, the latest time a hit lay within ``radius`` of its centre [s]
        (``_kernels.free_space.stamp_hits``); None: no burn-in.
    fresh_after : float
        With ``hit_stamp``: cells stamped later than this [s] are not marked.

    """
    x0, y0 = geometry.origin
    free_space.surely_free_update(
        seen_free, np.ascontiguousarray(ranges), pose[0], pose[1], pose[2], float(angle_min),
        float(angle_increment), float(range_min), float(range_max), x0, y0, geometry.resolution,
        float(radius), squared_bound(float(radius)),
        _NO_STAMPS if hit_stamp is None else hit_stamp, float(fresh_after))


def scan_update(labels, seen_free, last_hit, listed, geometry, pose, ranges, angle_min,
                angle_increment, range_min, range_max, safety_radius, rule_arguments, stamp,
                path, extra_moving=None, points=None, defer_free=False,
                free_fresh_after=-math.inf):
    """
    Fold one validated scan into the grid's state arrays in place.

    Parameters
    ----------
    labels : (rows, cols) ndarray of uint8
        The grid's labels.
    seen_free, listed : (rows, cols) ndarray of bool
        ``(1, 1)`` stand-ins when the rule keeps no such state.
    last_hit : (rows, cols) ndarray of float64
        Likewise.
    geometry : GridGeometry
        The grid's placement.
    pose : (float, float, float)
        The laser's ``(x, y, yaw)`` [m, m, rad], checked.
    ranges : (L,) ndarray of float64
        Checked ranges [m].
    angle_min, angle_increment, range_min, range_max : float
        The scan's fields, checked.
    safety_radius : float
        f1's ``r`` [m].
    rule_arguments : tuple
        ``LabelRule.kernel_arguments()``: ``(free_on, free_radius, free_bound, objects_on,
        evidence_radius, evidence_bound, segment_gap, object_size, min_hits, bridge_beams,
        expiry_on)``.
    stamp : float
        The scan's time [s] (any float when the expiry is off).
    path : (N, 2) ndarray of int64
        The planned path's cells, on the grid.
    extra_moving : (K,) ndarray of bool, optional
        Hits (in the order of `scan_hits`) to count as hits on moving objects besides those
        the object rule finds, such as the followed objects of ``motion_tracks``; read only
        with the object rule on.
    points : tuple, optional
        ``(vertices_x, vertices_y, hits_x, hits_y, hit_beams, moving)`` of this scan from
        `scan_hits` on the same state, so that they are not found again; ``extra_moving`` is
        then added to ``moving``.
    defer_free : bool
        With the conservative free space on, leave ``seen_free`` as it is and return what
        `mark_free_window` needs to mark this scan's surely-free cells later. The labels, the
        replan flag and the window are the same either way: no label of this scan depends on
        the cells it shows surely free (they are f2 cells; the rule reads ``seen_free`` only
        at f1 cells and at the hits, before the update).
    free_fresh_after : float
        The burn-in (``LabelRule.free_burn_in``): cells whose ``last_hit`` is later than this
        [s] are not marked surely free; ``-inf`` (the default) turns it off.

    Returns
    -------
    replan : bool
    window : (slice, slice, (n_rows, n_cols) ndarray of uint8)
        The window the scan reached and its FSM input (``ScanInput``).
    new_mobile : (M,) ndarray of int64
        Flat indices of the cells this scan made mobile and listed (with the expiry on).
    deferred : tuple or None
        For `mark_free_window`, with ``defer_free`` and the free space on; else None.

    """
    x0, y0 = geometry.origin
    free_on, free_radius, free_bound = rule_arguments[:3]
    reach = max(safety_radius, free_radius)
    defer_free = bool(defer_free and free_on)
    if points is None and not defer_free:
        replan, row0, row_end, col0, col_end, cell_input, new_mobile = label_kernels.scan_update(
            labels, seen_free, last_hit, listed, TRANSITION_BY_CODE,
            np.ascontiguousarray(ranges), pose[0], pose[1], pose[2], float(angle_min),
            float(angle_increment), float(range_min), float(range_max), x0, y0,
            geometry.resolution, reach, safety_radius, squared_bound(safety_radius),
            *rule_arguments, float(stamp), np.ascontiguousarray(path),
            _NO_HITS if extra_moving is None else np.ascontiguousarray(extra_moving, dtype=bool),
            float(free_fresh_after))
        return (bool(replan), (slice(row0, row_end), slice(col0, col_end), cell_input),
                new_mobile, None)
    if points is None:
        # The kernel's object rule finds the moving hits itself (moving_known False).
        vertices_x, vertices_y, hits_x, hits_y, hit_beams = scan_window.scan_points(
            np.ascontiguousarray(ranges), pose[0], pose[1], pose[2], float(angle_min),
            float(angle_increment), float(range_min), float(range_max))
        moving = (_NO_HITS if extra_moving is None
                  else np.ascontiguousarray(extra_moving, dtype=bool))
        moving_known = False
    else:
        vertices_x, vertices_y, hits_x, hits_y, hit_beams, moving = points
        if extra_moving is not None:
            moving = moving | extra_moving
        moving_known = True
    (replan, row0, row_end, col0, col_end, cell_input, new_mobile,
     extent) = label_kernels.points_update(
        labels, seen_free, last_hit, listed, TRANSITION_BY_CODE, vertices_x, vertices_y, hits_x,
        hits_y, hit_beams, x0, y0, geometry.resolution, reach, safety_radius,
        squared_bound(safety_radius), *rule_arguments, float(stamp),
        np.ascontiguousarray(path), moving, moving_known, defer_free, float(free_fresh_after))
    deferred = None
    if defer_free:
        deferred = (row0, col0, cell_input, extent, vertices_x, vertices_y, hit_beams,
                    float(safety_radius), float(free_radius), float(free_bound),
                    float(free_fresh_after))
    return (bool(replan), (slice(row0, row_end), slice(col0, col_end), cell_input),
            new_mobile, deferred)


def mark_free_window(seen_free, geometry, deferred, last_hit=None):
    """
    Mark the surely-free cells that a `scan_update` with ``defer_free`` left unmarked.

    Parameters
    ----------
    seen_free : (rows, cols) ndarray of bool
        The grid's cells once surely seen free, updated in place.
    geometry : GridGeometry
        The grid's placement.
    deferred : tuple
        What that `scan_update` returned last.
    last_hit : (rows, cols) ndarray of float64, optional
        The grid's hit clock, read with the burn-in (that call's ``free_fresh_after``).

    """
    x0, y0 = geometry.origin
    (row0, col0, cell_input, extent, vertices_x, vertices_y, hit_beams, safety_radius,
     free_radius, free_bound, free_fresh_after) = deferred
    free_space.mark_free_window(seen_free, row0, col0, cell_input, extent, x0, y0,
                                geometry.resolution, vertices_x, vertices_y, hit_beams,
                                safety_radius, free_radius, free_bound,
                                _NO_STAMPS if last_hit is None else last_hit, free_fresh_after)


def scan_hits(seen_free, geometry, pose, ranges, angle_min, angle_increment, range_min,
              range_max, rule_arguments, find_moving=True):
    """
    Return the scan's polygon and hits, and the hits the object rule finds moving.

    The same points and the same evidence as `scan_update` finds in its kernel, from the
    grid's state before the update.

    Parameters
    ----------
    seen_free : (rows, cols) ndarray of bool
        Cells once surely seen free (a stand-in without the object rule).
    geometry, pose, ranges, angle_min, angle_increment, range_min, range_max, rule_arguments
        As in `scan_update`.
    find_moving : bool
        False leaves ``moving`` all False (for a caller that finds it itself).

    Returns
    -------
    vertices_x, vertices_y : (L + 2,) ndarray of float64
        The closed scan polygon [m].
    hits_x, hits_y : (K,) ndarray of float64
        Hit points [m].
    hit_beams : (K,) ndarray of int64
        Their beams.
    moving : (K,) ndarray of bool
        Hits on objects seen to move (all False without the object rule).

    """
    vertices_x, vertices_y, hits_x, hits_y, hit_beams = scan_window.scan_points(
        np.ascontiguousarray(ranges), pose[0], pose[1], pose[2], float(angle_min),
        float(angle_increment), float(range_min), float(range_max))
    (_, _, _, objects_on, evidence_radius, evidence_bound, segment_gap, object_size,
     min_hits, bridge_beams, _) = rule_arguments
    moving = np.zeros(hits_x.shape[0], dtype=bool)
    if objects_on and find_moving:
        x0, y0 = geometry.origin
        evidence = motion_evidence.hit_evidence(seen_free, hits_x, hits_y, x0, y0,
                                                geometry.resolution, evidence_radius,
                                                evidence_bound)
        moving = motion_evidence.moving_hits(hits_x, hits_y, hit_beams, evidence, segment_gap,
                                             object_size, min_hits, vertices_x[0], vertices_y[0],
                                             ranges.shape[0], bridge_beams)
    return vertices_x, vertices_y, hits_x, hits_y, hit_beams, moving


def expire_listed(labels, last_hit, listed, cells, count, stamp, mobile_expiry, window):
    """
    Run the ``expire_listed`` kernel over ``cells[:count]`` after the scan of ``window``.

    Returns
    -------
    kept : int
    earliest : float
        The earliest last hit of the cells kept [s], ``inf`` when none.
    expired : (slice, slice)
        Rows and columns of a box around the cells expired (empty when none).

    """
    rows, cols, cell_input = window
    kept, earliest, row_lo, row_hi, col_lo, col_hi = label_kernels.expire_listed(
        labels, last_hit, listed, cells, count, float(stamp), float(mobile_expiry), rows.start,
        cols.start, cell_input)
    return (int(kept), float(earliest),
            (slice(row_lo, max(row_lo, row_hi)), slice(col_lo, max(col_lo, col_hi))))
