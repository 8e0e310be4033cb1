"""
Built-in scenarios: map_server maps (``*.yaml`` + ``*.pgm``) and ``index.yaml`` with their tasks.

The files are package data; ``generate`` rebuilds the synthetic maps (``back_and_forth``).

"""
