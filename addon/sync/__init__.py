"""The one sync layer: F12, the viewport and the material preview all keep a
native scene up to date from the depsgraph through `SceneSync` (scene.py);
an F12 render is a sync from empty."""

from .scene import SceneSync, SyncParams, SyncReport

__all__ = ["SceneSync", "SyncParams", "SyncReport"]
