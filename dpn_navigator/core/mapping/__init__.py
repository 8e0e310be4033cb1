"""
The labelled grid: the per-scan label update and the parts of its rule.

Labels change only here, through ``LabelGrid`` (update, settle, forget).

"""
