"""The stored ray tree drawn over the 3D view: a line per ray, coloured by kind,
thicker the more it weighs on the pixel, blocked feelers faint.

A gizmo draws it, so there is no draw handler to keep a handle of: the gizmo group
shows while the scene holds a tree and rebuilds its batches when the tree changes.
"""

import bpy
import gpu
from gpu_extras.batch import batch_for_shader

from .tree import loads, segments

# RGBA by ray kind; a blocked feeler is drawn in BLOCKED.
COLOURS = {
    "camera": (1.0, 0.85, 0.2, 1.0),
    "shadow": (0.35, 1.0, 0.35, 1.0),
    "reflection": (0.3, 0.6, 1.0, 1.0),
    "refraction": (1.0, 0.35, 0.9, 1.0),
    "tir": (1.0, 0.5, 0.1, 1.0),
    "transparent": (0.75, 0.75, 0.75, 1.0),
    "glossy": (0.45, 0.85, 1.0, 1.0),
    "volume": (0.65, 0.45, 1.0, 1.0),
    "ambient_occlusion": (0.55, 0.55, 0.4, 1.0),
    "bevel": (0.4, 0.55, 0.55, 1.0),
}
BLOCKED = (0.9, 0.2, 0.2, 0.45)
# Line widths in pixels by the ray's weight on the pixel (its largest channel): at
# least WIDTHS[i][0] draws WIDTHS[i][1] wide.
WIDTHS = ((0.5, 4.0), (0.1, 2.5), (0.0, 1.5))


def _line_shader():
    # Renamed in Blender 4.0 (the "3D_" prefix dropped).
    name = "POLYLINE_FLAT_COLOR" if bpy.app.version >= (4, 0, 0) else "3D_POLYLINE_FLAT_COLOR"
    return gpu.shader.from_builtin(name)


def line_groups(tree):
    """Per line width, the (positions, colours) of that width's segments."""
    groups = {width: ([], []) for _, width in WIDTHS}
    for kind, start, end, weight, blocked in segments(tree):
        width = next(w for least, w in WIDTHS if weight >= least)
        colour = BLOCKED if blocked else COLOURS[kind]
        positions, colours = groups[width]
        positions += [start, end]
        colours += [colour, colour]
    return {width: group for width, group in groups.items() if group[0]}


class WHITTED_GT_ray_tree(bpy.types.Gizmo):
    bl_idname = "WHITTED_GT_ray_tree"

    def setup(self):
        self.drawn = None  # the JSON the batches were built from
        self.batches = []
        self.hide_select = True

    def _rebuild(self, text):
        self.drawn = text
        self.batches = []
        tree = loads(text)
        if tree is None:
            return
        shader = _line_shader()
        for width, (positions, colours) in line_groups(tree).items():
            batch = batch_for_shader(shader, "LINES", {"pos": positions, "color": colours})
            self.batches.append((width, batch))

    def draw(self, context):
        text = context.scene.whitted.last_ray_tree
        if text != self.drawn:
            self._rebuild(text)
        if not self.batches:
            return
        shader = _line_shader()
        region = context.region
        gpu.state.blend_set("ALPHA")
        shader.bind()
        shader.uniform_float("viewportSize", (region.width, region.height))
        for width, batch in self.batches:
            shader.uniform_float("lineWidth", width)
            batch.draw(shader)
        gpu.state.blend_set("NONE")

    def test_select(self, context, location):
        return -1  # never picked: it only shows the tree


class WHITTED_GGT_ray_tree(bpy.types.GizmoGroup):
    bl_idname = "WHITTED_GGT_ray_tree"
    bl_label = "Whitted Ray Tree"
    bl_space_type = "VIEW_3D"
    bl_region_type = "WINDOW"
    bl_options = {"3D", "PERSISTENT", "SHOW_MODAL_ALL"}

    @classmethod
    def poll(cls, context):
        scene = context.scene
        return scene is not None and bool(scene.whitted.last_ray_tree)

    def setup(self, context):
        self.gizmos.new(WHITTED_GT_ray_tree.bl_idname)
