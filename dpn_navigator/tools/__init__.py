"""Command-line tools: compile_kernels, the demo, the figures."""
