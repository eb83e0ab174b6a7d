"""Benchmarks: time and memory of the pipeline's stages, written to files."""
