"""Figures of the paper, drawn from the pipeline's netCDF datasets.

registry.py lists every figure (the contract for adding one is in its docstring); style.py
holds the shared look (saving with provenance, panel labels, numbers, units); the drawing
functions are grouped by the stage they show: orbit_figures.py (1-3), theory_figures.py (4-7),
md_figures.py (8-10).
"""
