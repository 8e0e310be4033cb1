"""
Count the Husky's collisions as distinct contact events, for judging an episode.

A contact event starts on the first tick the Husky touches something it did not touch on the
tick before, and lasts while the touching goes on. All walls together count as one obstacle,
so scraping along a wall made of several boxes, or into a corner, is one event; each wanderer
is an obstacle of its own.

"""


class ContactLog:
    """
    Contact events of the Husky with walls and with wanderers.

    Attributes
    ----------
    wall_events : int
        Distinct contact events with walls.
    wanderer_events : int
        Distinct contact events with wanderers (a touch of two wanderers at once counts two).
    first_wall_time, first_wanderer_time : float or None
        Simulated time of the first event of each kind [s], None before it.
    touching_wall : bool
        Whether the Husky touches a wall now.
    touching_wanderers : frozenset of int
        Indices of the wanderers it touches now.

    """

    def __init__(self):
        self.wall_events = 0
        self.wanderer_events = 0
        self.first_wall_time = None
        self.first_wanderer_time = None
        self.touching_wall = False
        self.touching_wanderers = frozenset()

    @property
    def events(self):
        """Return the number of contact events, walls and wanderers together."""
        return self.wall_events + self.wanderer_events

    @property
    def first_contact_time(self):
        """Return the simulated time of the first contact of any kind [s], or None."""
        times = [t for t in (self.first_wall_time, self.first_wanderer_time) if t is not None]
        return min(times) if times else None

    def update(self, stamp, touching_wall, touching_wanderers):
        """
        Record what the Husky touches on one tick.

        Parameters
        ----------
        stamp : float
            Simulated time of the tick [s].
        touching_wall : bool
            Whether it touches any wall.
        touching_wanderers : iterable of int
            Indices of the wanderers it touches.

        """
        touching_wanderers = frozenset(touching_wanderers)
        if touching_wall and not self.touching_wall:
            self.wall_events += 1
            if self.first_wall_time is None:
                self.first_wall_time = stamp
        new = touching_wanderers - self.touching_wanderers
        if new:
            self.wanderer_events += len(new)
            if self.first_wanderer_time is None:
                self.first_wanderer_time = stamp
        self.touching_wall = bool(touching_wall)
        self.touching_wanderers = touching_wanderers
