"""Settings that Whitted stores in Blender data (scene.whitted)."""
