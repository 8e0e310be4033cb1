"""From a path to velocity commands: the path follower, the turn sweep."""
