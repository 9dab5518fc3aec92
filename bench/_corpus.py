"""The classes of inputs bench/reliability.py tries, in the order of its table.

Hand-written inputs are in bench/_hostile.py, hostile files (and their seeded mutations)
in bench/_hostile_files.py, generated sweeps and random inputs in
bench/_hostile_generated.py.
"""

from __future__ import annotations

import _hostile as hostile
import _hostile_files as files
import _hostile_generated as generated

CLASSES = {
    "alpha values": hostile.alpha_cases,
    "alpha sweep": generated.alpha_sweep_cases,
    "sample budgets": hostile.budget_cases,
    "region geometries": hostile.geometry_cases,
    "degenerate polygons": generated.degenerate_polygon_cases,
    "random regions": generated.random_region_cases,
    "far and tiny coordinates": hostile.coordinate_cases,
    "coordinate grid": generated.coordinate_grid_cases,
    "point sets": hostile.point_set_cases,
    "random point sets": generated.random_point_set_cases,
    "SVG files": hostile.svg_cases,
    "SVG structures": files.svg_structure_cases,
    "SVG mutations": files.svg_mutation_cases,
    "DXF files": files.dxf_cases,
    "DXF mutations": files.dxf_mutation_cases,
    "mesh files and solids": hostile.mesh_file_cases,
    "mesh file mutations": files.mesh_mutation_cases,
    "automatic alpha": hostile.auto_alpha_cases,
    "command line": hostile.cli_cases,
    "command line fuzz": generated.cli_fuzz_cases,
    "interrupted writes": hostile.interrupted_write_cases,
    "signals": hostile.signal_cases,
    "failed runs": hostile.failed_run_cases,
}
"""Class name -> function returning its list of :class:`_hostile.Case`."""

TIME_LIMITS = {"command line": 120.0, "command line fuzz": 120.0, "interrupted writes": 120.0,
               "signals": 180.0, "failed runs": 120.0}
"""Seconds per input for the classes that run pds-mesh itself (a fresh Python, workers),
when more than the harness's limit."""
