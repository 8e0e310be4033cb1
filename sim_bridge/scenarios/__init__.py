"""
Built-in scenarios: map_server maps (``*.yaml`` + ``*.pgm``) and ``index.yaml`` with their tasks.

The files are package data. All 34 maps of the benchmark set are synthetic: ``generate``
rebuilds them and the index from their designs (``catalogue``).

"""
