"""
Notice another publisher on the node's command topic: two navigators fighting over one base.

The node polls ``check`` with the number of publishers the graph shows on its command topic
(its own included); a count above one is a conflict. Plain integers in, no ROS.

"""


class CommandTopicMonitor:
    """
    Count the other publishers on a command topic and how often a conflict began.

    Attributes
    ----------
    others : int
        Publishers on the topic besides the node's own, at the last check.
    conflicts : int
        How many times the topic went from no other publisher to some.

    """

    def __init__(self):
        self.others = 0
        self.conflicts = 0

    def check(self, publisher_count):
        """
        Update from the graph's publisher count on the topic, the node's own included.

        Parameters
        ----------
        publisher_count : int
            Publishers on the topic, as ``Node.count_publishers`` reports them.

        Returns
        -------
        bool
            True while another publisher is on the topic.

        """
        others = max(0, int(publisher_count) - 1)
        if others > 0 and self.others == 0:
            self.conflicts += 1
        self.others = others
        return others > 0
