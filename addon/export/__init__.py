"""Exporters: pure functions from evaluated Blender data to plain data.

Each module has one public `convert_*` function; only scene.py builds native
objects. A problem with one object becomes a warning string appended to the
caller's `warnings` list; a problem that makes the render impossible raises
ExportError.
"""


class ExportError(Exception):
    """The scene cannot be rendered (for example: it has no camera)."""
