"""The reference navigators' maps: a Nav2-style costmap and the oracle."""
