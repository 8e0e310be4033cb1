"""
Fine free evidence: where space was surely seen empty, on a grid finer than the labels'.

The label grid's conservative free space (``LabelRule.free_evidence_radius``) is kept per
label cell: a cell is surely free when its disc of radius ``r`` lay inside one scan's polygon,
and a hit shows motion when such a cell's centre is within ``r - evidence_margin`` of it. On
0.5 m cells that leaves every point less than about 0.5 m inside the polygons seen so far
without evidence: a wanderer walking along the edge of its own shadow, or one first seen far
away, shows motion late or never.

Here a second grid of ``resolution`` cells keeps the same evidence with its own ``radius``
(``FineEvidence.seen_free``): a fine cell is surely free when its disc of ``radius`` lay inside
one scan's polygon. A hit whose fine cell is surely free lies at least ``radius`` minus half
the fine cell's diagonal inside space one scan saw empty, and shows motion. The evidence is
exactly the ``seen_free`` of a ``LabelGrid`` of the fine cells with only the conservative free
space on, computed without its labels (``label_update.surely_free_update``) and tested against
the literal twin and the numpy twin.

Only space within ``max_range`` of the laser is marked: the scan goes into the fine grid with
that as its ``range_max``, so a beam reaching farther saw empty space up to it. Between two
beams the polygon takes space for empty that no beam crossed; 640 beams over 180 degrees are
7 cm apart at 15 m, less than a fine cell, but 15 cm apart at 30 m, where a speck of a wall
of a SLAM map hides between them and its next hit looks like motion.

With ``renewal`` > 0 the evidence is kept in two generations: marks go into the current one,
lookups read both, and each time the laser has travelled ``renewal / 2`` since the current one
began, the older is dropped and a new one begins. What is looked up was thus seen free within
the last ``renewal / 2`` to ``renewal`` metres of travel. A pose with a fixed heading error
(a localiser's) places a wall seen from two poses ``d`` apart that error times ``d`` apart; with
the evidence's own margin (``radius`` less half a fine cell's diagonal, 0.13 m by default) a
renewal of 6 m keeps a 1-degree error (0.10 m over 6 m) from showing walls moving.

With ``burn_in`` > 0 a fine cell is marked only when no hit of an earlier scan has come within
``radius`` of its centre in the last ``burn_in`` seconds (each cell keeps the time of the
latest, ``hit_stamp``): the burn-in of Dynablox's ever-free space (Schmid et al., RA-L 2023,
``burn_in_period``). A surface that returns an echo in some scans and none in others (weak
echoes, read as no return) is seen empty between its hits; without the burn-in its next hit
lands in space seen empty and looks like motion.

With ``first_sight`` > 0 a fine cell counts as surely free only from a scan that shows it empty
at least ``first_sight`` after the first scan that did (each cell keeps that first time,
``first_free``): free evidence needs a second look. At the start of a recording, or where
space is first seen, the first scan's polygon takes for empty the place of a surface that
returned no echo in that one scan (a dark surface, an echo lost), and its echo in the next
scans looks like motion; the burn-in cannot hold it back, as no hit has come near it yet.

"""

import math

import numpy as np

from .label_update import surely_free_update
from .map_growth import embed_at, subgrid_offset
from .second_look import hold_back, scan_window
from .travel_generations import TravelGenerations
from .._kernels import fine_evidence as fine_kernels
from .._kernels.free_space import stamp_hits
from .._kernels.motion_evidence import moving_hits
from ..grid_geometry import GridGeometry, squared_bound


class FineEvidence:
    """
    Surely-free space on a fine grid over the label grid's extent, and the hits it shows moving.

    Parameters
    ----------
    geometry : GridGeometry
        The label grid's placement; the fine grid covers the same rectangle.
    resolution : float
        Side of the fine cells [m], > 0.
    radius : float
        A fine cell is surely free when its disc of this radius lay inside one scan's polygon
        [m], > 0.
    max_range : float
        Only space within this distance of the laser is marked [m], > 0.
    renewal : float
        Evidence is dropped after this much travel of the laser [m], in two generations; 0:
        never.
    burn_in : float
        A fine cell is marked only when no hit has been within ``radius`` of it for this long
        [s]; 0: off.
    first_sight : float
        A fine cell is marked only by a scan at least this long after the first scan that
        showed it empty [s]; 0: off.

    """

    def __init__(self, geometry, resolution, radius, max_range, renewal=0.0, burn_in=0.0,
                 first_sight=0.0):
        self.radius = float(radius)
        self.max_range = float(max_range)
        self.renewal = float(renewal)
        self.burn_in = float(burn_in)
        self.first_sight = float(first_sight)
        if not (math.isfinite(self.renewal) and self.renewal >= 0.0):
            raise ValueError(f'renewal must be finite and >= 0, got {renewal!r} m')
        if not (math.isfinite(self.burn_in) and self.burn_in >= 0.0):
            raise ValueError(f'burn_in must be finite and >= 0, got {burn_in!r} s')
        if not (math.isfinite(self.first_sight) and self.first_sight >= 0.0):
            raise ValueError(f'first_sight must be finite and >= 0, got {first_sight!r} s')
        if not self.radius > 0.0:
            raise ValueError(f'radius must be > 0, got {radius!r} m')
        if not self.max_range > 0.0:
            raise ValueError(f'max_range must be > 0, got {max_range!r} m')
        self.geometry = GridGeometry(geometry.width, geometry.height, resolution,
                                     origin=tuple(geometry.origin))
        self._seen_free = np.zeros(self.geometry.shape, dtype=bool)
        # With renewal: the older generation, and the travel that ends the current one.
        self._older = (np.zeros(self.geometry.shape, dtype=bool) if self.renewal > 0.0
                       else None)
        self._generations = (TravelGenerations(0.5 * self.renewal) if self.renewal > 0.0
                             else None)
        # With the burn-in: per fine cell, the latest time a hit lay within `radius` [s].
        self.hit_stamp = (np.full(self.geometry.shape, -math.inf) if self.burn_in > 0.0
                          else None)
        # With first_sight: per fine cell, the time of the first scan that showed it empty
        # [s]; +inf: none yet.
        self.first_free = (np.full(self.geometry.shape, math.inf) if self.first_sight > 0.0
                           else None)
        self._last_stamp = -math.inf

    def grow(self, geometry):
        """
        Cover the grown label grid's ``geometry``; fine cells keep their places.

        When the label grid's origin moved by a fraction of a fine cell (its resolution not a
        whole multiple of the fine one), the fine evidence starts again empty.
        """
        new = GridGeometry(geometry.width, geometry.height, self.geometry.resolution,
                           origin=tuple(geometry.origin))
        offset = subgrid_offset(self.geometry, new)
        self._seen_free = (np.zeros(new.shape, dtype=bool) if offset is None
                           else embed_at(self._seen_free, new.shape, *offset, False))
        if self._older is not None:
            self._older = (np.zeros(new.shape, dtype=bool) if offset is None
                           else embed_at(self._older, new.shape, *offset, False))
        if self.hit_stamp is not None:
            # Without a whole offset the evidence starts again: so does its clock.
            self.hit_stamp = (np.full(new.shape, -math.inf) if offset is None
                              else embed_at(self.hit_stamp, new.shape, *offset, -math.inf))
        if self.first_free is not None:
            self.first_free = (np.full(new.shape, math.inf) if offset is None
                               else embed_at(self.first_free, new.shape, *offset, math.inf))
        self.geometry = new

    @property
    def nbytes(self):
        """Bytes held by the fine grid (both generations with renewal, the two clocks)."""
        return (self._seen_free.nbytes + (0 if self._older is None else self._older.nbytes)
                + (0 if self.hit_stamp is None else self.hit_stamp.nbytes)
                + (0 if self.first_free is None else self.first_free.nbytes))

    @property
    def seen_free(self):
        """
        Return the fine cells surely seen free, (rows, cols) ndarray of bool.

        Without renewal the grid itself (ever seen free); with it a new array, the cells seen
        free in either generation.
        """
        if self._older is None:
            return self._seen_free
        return self._seen_free | self._older

    def evidence(self, hits_x, hits_y):
        """
        Tell for each hit whether its fine cell was once surely seen free.

        Parameters
        ----------
        hits_x, hits_y : (K,) ndarray of float64
            Hit points [m].

        Returns
        -------
        (K,) ndarray of bool
            False for hits off the grid.

        """
        evidence, _ = self._lookup(np.ascontiguousarray(hits_x, dtype=np.float64),
                                   np.ascontiguousarray(hits_y, dtype=np.float64))
        return evidence

    def _lookup(self, hits_x, hits_y):
        """Return ``fine_hit_evidence``'s ``(evidence, found)`` over both generations."""
        x0, y0 = self.geometry.origin
        evidence, found = fine_kernels.fine_hit_evidence(
            self._seen_free, x0, y0, self.geometry.resolution, hits_x, hits_y)
        if self._older is not None:
            older, found_older = fine_kernels.fine_hit_evidence(
                self._older, x0, y0, self.geometry.resolution, hits_x, hits_y)
            evidence |= older
            found = found or found_older
        return evidence, found

    def moving_hits(self, points, rule):
        """
        Return the hits of objects this evidence shows moving (``moving_object_hits``).

        `evidence` and the object rule's ``_kernels.motion_evidence.moving_hits`` in one compiled
        call.

        Parameters
        ----------
        points : tuple
            ``(vertices_x, vertices_y, hits_x, hits_y, hit_beams, ...)`` of the scan, as
            ``label_update.scan_hits`` returns them; read before `update` with that scan.
        rule : LabelRule
            Its ``segment_gap``, ``segment_bridge_beams``, ``moving_object_size`` and
            ``object_min_hits``.

        Returns
        -------
        (K,) ndarray of bool

        """
        vertices_x, vertices_y, hits_x, hits_y, hit_beams = points[:5]
        x0, y0 = self.geometry.origin
        if self._older is not None:
            hits_x = np.ascontiguousarray(hits_x, dtype=np.float64)
            hits_y = np.ascontiguousarray(hits_y, dtype=np.float64)
            evidence, found = self._lookup(hits_x, hits_y)
            if not found:
                return evidence
            return moving_hits(hits_x, hits_y, np.ascontiguousarray(hit_beams, dtype=np.int64),
                               evidence, float(rule.segment_gap),
                               float(rule.moving_object_size), int(rule.object_min_hits),
                               float(vertices_x[0]), float(vertices_y[0]),
                               vertices_x.shape[0] - 2, int(rule.segment_bridge_beams))
        return fine_kernels.fine_moving_hits(self.seen_free, x0, y0, self.geometry.resolution,
                                             np.ascontiguousarray(hits_x, dtype=np.float64),
                                             np.ascontiguousarray(hits_y, dtype=np.float64),
                                             np.ascontiguousarray(hit_beams, dtype=np.int64),
                                             float(rule.segment_gap), float(
                                                 rule.moving_object_size),
                                             int(rule.object_min_hits), float(vertices_x[0]),
                                             float(vertices_y[0]), vertices_x.shape[0] - 2,
                                             int(rule.segment_bridge_beams))

    def update(self, pose, ranges, angle_min, angle_increment, range_min, range_max,
               stamp=0.0, hits=None):
        """
        Fold one checked scan into the fine evidence, up to ``max_range`` from the laser.

        The laser's pose and the scan as ``LabelGrid.update`` takes them, checked. Exactly the
        ``seen_free`` of a ``LabelGrid`` of the fine cells with only
        ``free_evidence_radius = radius`` on, updated with safety radius ``radius`` and
        ``range_max`` capped at ``max_range`` (``label_update.surely_free_update``). With
        renewal, the laser's travel since the latest update (``pose``'s x and y) counts toward
        the next generation, which begins before this scan is marked.

        With the burn-in, ``stamp`` is the scan's time [s] and ``hits`` its hit points
        ``(hits_x, hits_y)`` [m] (the scan's returns, not the vertices of beams with none):
        cells stamped after ``stamp - burn_in`` are not marked, then the hits stamp theirs.
        With ``first_sight``, the cells this scan marks for the first time, or less than
        ``first_sight`` after their first time, are taken back (``second_look.hold_back``).
        """
        if self._generations is not None and self._generations.step(pose):
            self._older, self._seen_free = self._seen_free, self._older
            self._seen_free[...] = False
        stamp = float(stamp)
        if stamp < self._last_stamp:
            # Time went back (a restarted simulation, a bag played again): no clock is
            # later than now.
            for clock in (self.hit_stamp, self.first_free):
                if clock is not None:
                    np.minimum(clock, stamp, out=clock)
        self._last_stamp = stamp
        capped = self.capped_range_max(range_min, range_max)
        window = before = None
        if self.first_free is not None:
            window = scan_window(self.geometry, pose, capped + self.radius)
            before = self._seen_free[window].copy()
        surely_free_update(self._seen_free, self.geometry, pose, ranges, angle_min,
                           angle_increment, range_min, capped,
                           self.radius, self.hit_stamp, stamp - self.burn_in)
        if window is not None:
            hold_back(self._seen_free, self.first_free, window, before, stamp, self.first_sight)
        if self.hit_stamp is not None and hits is not None:
            x0, y0 = self.geometry.origin
            stamp_hits(self.hit_stamp, np.ascontiguousarray(hits[0], dtype=np.float64),
                       np.ascontiguousarray(hits[1], dtype=np.float64), x0, y0,
                       self.geometry.resolution, squared_bound(self.radius), stamp)

    def set_burn_in(self, burn_in):
        """
        Take a new burn-in [s] from the next scan on (0: off); the hit clock starts empty.

        Cells no hit has stamped yet count as long free of hits, as at the start.
        """
        burn_in = float(burn_in)
        if not (math.isfinite(burn_in) and burn_in >= 0.0):
            raise ValueError(f'burn_in must be finite and >= 0, got {burn_in!r} s')
        self.burn_in = burn_in
        if burn_in == 0.0:
            self.hit_stamp = None
        elif self.hit_stamp is None:
            self.hit_stamp = np.full(self.geometry.shape, -math.inf)

    def drop_free(self):
        """Forget which fine cells were seen free (both generations); keep the hit clock."""
        self._seen_free[...] = False
        if self._older is not None:
            self._older[...] = False

    def capped_range_max(self, range_min, range_max):
        """Return the scan's ``range_max`` [m] as the fine evidence takes it: at most max_range."""
        return min(range_max, max(self.max_range, range_min))

    def reset(self):
        """Forget all evidence (and the travel, and the two clocks)."""
        self._seen_free[...] = False
        if self.hit_stamp is not None:
            self.hit_stamp.fill(-math.inf)
        if self.first_free is not None:
            self.first_free.fill(math.inf)
        self._last_stamp = -math.inf
        if self._older is not None:
            self._older[...] = False
            self._generations.reset()
