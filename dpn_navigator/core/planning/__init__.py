"""Planning on the labelled grid: the blocked and cost masks, A*."""
