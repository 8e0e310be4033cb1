"""The labelled grid: the per-scan label update and the parts of its rule; labels change only here."""
