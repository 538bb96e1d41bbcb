"""The ray-tree inspector (issue 17): one pixel traced again, every ray of its Whitted
recursion recorded (native `RenderJob.inspect`), kept on the scene as JSON
(`scene.whitted.last_ray_tree`), listed in a panel, drawn over the 3D view and, on
request, turned into a curve object.

- tree.py: tracing a pixel of the final frame or of a 3D view, and the plain data
  (names, depth sums, what was cut) stored as JSON;
- operators.py: inspect (from Python, a click in the Image Editor or the 3D view),
  clear, to curve;
- draw.py: the segments in the 3D view (a gizmo, so nothing is registered by handle).
"""
