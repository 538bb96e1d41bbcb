"""Operators of the ray-tree inspector: inspect a pixel, clear the tree, turn it into
a curve object."""

import math

import bpy
from bpy.props import IntProperty

from ..export import ExportError
from ..native import load_native
from ..viewport.session import region_camera
from .draw import BLOCKED, COLOURS
from .tree import PixelView, dumps, inspect_pixel, loads, segments

PICK_HINT = "Click a pixel of a Whitted render (Image Editor) or of a 3D view; Esc cancels"


def _redraw(context):
    for window in context.window_manager.windows:
        for area in window.screen.areas:
            if area.type in {"VIEW_3D", "IMAGE_EDITOR"}:
                area.tag_redraw()


def _frame_size(scene):
    # The final frame's size in pixels, as export/camera.py computes it.
    scale = scene.render.resolution_percentage / 100.0
    return (
        max(1, int(scene.render.resolution_x * scale)),
        max(1, int(scene.render.resolution_y * scale)),
    )


def _under_mouse(window, x, y):
    """The area and main region under window coordinates (x, y), or (None, None)."""
    for area in window.screen.areas:
        if area.type not in {"VIEW_3D", "IMAGE_EDITOR"}:
            continue
        for region in area.regions:
            inside = region.x <= x < region.x + region.width and (
                region.y <= y < region.y + region.height
            )
            if region.type == "WINDOW" and inside:
                return area, region
    return None, None


class WHITTED_OT_inspect_ray_tree(bpy.types.Operator):
    bl_idname = "whitted.inspect_ray_tree"
    bl_label = "Inspect Ray Tree"
    bl_description = (
        "Trace one pixel again and record its Whitted ray tree: every camera, shadow, "
        "reflection and refraction ray, what each adds to the pixel and what was cut. "
        "Click a pixel of a render in the Image Editor or of a 3D view"
    )

    x: IntProperty(name="X", description="Pixel column, from the left", default=-1, min=-1)
    y: IntProperty(name="Y", description="Pixel row, from the bottom", default=-1, min=-1)
    sample: IntProperty(
        name="Sample",
        description="One anti-aliasing grid sample alone, or -1 for the whole pixel",
        default=-1,
        min=-1,
    )

    def execute(self, context):
        if self.x < 0 or self.y < 0:
            self.report({"ERROR"}, "Whitted: give the pixel (x, y), or click one")
            return {"CANCELLED"}
        return self._inspect(context, view=None)

    def invoke(self, context, event):
        if self.properties.is_property_set("x") and self.properties.is_property_set("y"):
            return self.execute(context)
        context.window.cursor_modal_set("EYEDROPPER")
        context.workspace.status_text_set(PICK_HINT)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type in {"ESC", "RIGHTMOUSE"}:
            self._end_pick(context)
            return {"CANCELLED"}
        if event.type != "LEFTMOUSE" or event.value != "PRESS":
            return {"RUNNING_MODAL"}
        self._end_pick(context)
        area, region = _under_mouse(context.window, event.mouse_x, event.mouse_y)
        if area is None:
            self.report({"WARNING"}, "Whitted: no Image Editor or 3D view under the mouse")
            return {"CANCELLED"}
        mx = event.mouse_x - region.x
        my = event.mouse_y - region.y
        if area.type == "VIEW_3D":
            space = area.spaces.active
            self.x, self.y = mx, my
            view = PixelView(
                width=region.width,
                height=region.height,
                camera=region_camera(
                    context.scene, space, space.region_3d, region.width, region.height
                ),
            )
            return self._inspect(context, view)
        # The Image Editor shows the frame over [0, 1]^2 of its view.
        u, v = region.view2d.region_to_view(mx, my)
        width, height = _frame_size(context.scene)
        self.x, self.y = math.floor(u * width), math.floor(v * height)
        if not (0 <= self.x < width and 0 <= self.y < height):
            self.report({"WARNING"}, "Whitted: the click is outside the image")
            return {"CANCELLED"}
        return self._inspect(context, view=None)

    def _end_pick(self, context):
        context.window.cursor_modal_restore()
        context.workspace.status_text_set(None)

    def _inspect(self, context, view):
        try:
            tree = inspect_pixel(
                context.evaluated_depsgraph_get(),
                load_native(),
                self.x,
                self.y,
                self.sample,
                view,
            )
        except (ImportError, ExportError) as error:
            self.report({"ERROR"}, str(error))
            return {"CANCELLED"}
        except (IndexError, ValueError) as error:
            self.report({"ERROR"}, f"Whitted: cannot inspect that pixel: {error}")
            return {"CANCELLED"}
        context.scene.whitted.last_ray_tree = dumps(tree)
        self.report(
            {"INFO"}, f"Whitted ray tree of ({self.x}, {self.y}): {tree['summary']['text']}"
        )
        _redraw(context)
        return {"FINISHED"}


class WHITTED_OT_clear_ray_tree(bpy.types.Operator):
    bl_idname = "whitted.clear_ray_tree"
    bl_label = "Clear Ray Tree"
    bl_description = "Forget the inspected ray tree and stop drawing it"

    def execute(self, context):
        context.scene.whitted.last_ray_tree = ""
        _redraw(context)
        return {"FINISHED"}


# The curve's thickness: this fraction of the tree's extent, times the ray's weight
# (at least a fifth of it, so faint rays stay visible).
CURVE_RADIUS = 0.004


class WHITTED_OT_ray_tree_to_curve(bpy.types.Operator):
    bl_idname = "whitted.ray_tree_to_curve"
    bl_label = "Ray Tree to Curve"
    bl_description = (
        "Make a curve object of the inspected ray tree, one spline per ray and a material "
        "per kind, for a final render or a slide"
    )
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        tree = loads(context.scene.whitted.last_ray_tree)
        if tree is None:
            self.report({"ERROR"}, "Whitted: no ray tree to convert; inspect a pixel first")
            return {"CANCELLED"}
        lines = segments(tree)
        extent = max((math.dist(start, end) for _, start, end, _, _ in lines), default=1.0)
        curve = bpy.data.curves.new("Whitted Ray Tree", "CURVE")
        curve.dimensions = "3D"
        curve.bevel_depth = CURVE_RADIUS * extent
        slots = {}
        for kind, start, end, weight, blocked in lines:
            look = "blocked" if blocked else kind
            if look not in slots:
                slots[look] = len(curve.materials)
                curve.materials.append(
                    _emission_material(look, BLOCKED if blocked else COLOURS[kind])
                )
            spline = curve.splines.new("POLY")
            spline.points.add(1)
            radius = max(0.2, min(1.0, weight))
            for point, at in zip(spline.points, (start, end), strict=True):
                point.co = (*at, 1.0)
                point.radius = radius
            spline.material_index = slots[look]
        obj = bpy.data.objects.new("Whitted Ray Tree", curve)
        context.scene.collection.objects.link(obj)
        self.report({"INFO"}, f"Whitted: curve object '{obj.name}' with {len(lines)} rays")
        return {"FINISHED"}


def _emission_material(look, colour):
    name = f"Whitted Ray Tree {look}"
    material = bpy.data.materials.get(name)
    if material is not None:
        return material
    material = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):  # 5.0 always shades with the node tree
        material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = colour
    emission.inputs["Strength"].default_value = 1.0
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    material.diffuse_color = colour
    return material
