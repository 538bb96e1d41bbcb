"""Render a frame range, or one frame in tiles, with Whitted on a Dask cluster.

The farm verb runs farm/render.py (its docstring says how the farm works) as __main__:
distributed sends a function of an importable module by reference, so the scheduler
and every worker would have to import whitted_tools, and one of __main__ by value, so
workers need only distributed and Blender.
"""

import runpy


def main(argv):
    return runpy.run_module("whitted_tools.farm.render", run_name="__main__")["main"](argv)
