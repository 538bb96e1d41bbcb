"""Exporters: pure functions from evaluated Blender data to plain data (dataclasses,
numpy arrays), one module per concept; none of them builds native objects (the sync does:
sync/native_data.py). A problem with one object becomes a warning string appended to the
caller's `warnings` list; a problem that makes the render impossible raises ExportError.
"""


class ExportError(Exception):
    """The scene cannot be rendered (for example: it has no camera)."""
