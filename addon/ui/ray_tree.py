"""The ray-tree inspector's panel, in the 3D view's and the Image Editor's sidebar
(tab "Whitted"): the pick button, the one-line summary and the tree as an outline."""

import bpy

from ..ray_tree.tree import KINDS, feeler_source, loads

# Rows of the outline at most: a deep tree of a soft-shadowed scene has thousands.
MAX_ROWS = 80


def _rgb(values):
    return " ".join(f"{v:.4g}" for v in values)


def _ray_label(ray):
    what = ray["object"] or "background"
    if ray["kind"] == "shadow":
        state = {True: "blocked", False: "lit", None: ray["cut"]}[ray["blocked"]]
        if ray["blocked"] and ray["object"]:
            state = f"blocked by {ray['object']}"
        # A feeler from a scatter point of a segment in media.
        kind = "scatter" if ray.get("scatter") else "shadow"
        return f"{kind} -> {feeler_source(ray)}: {state}"
    if ray["kind"] == "volume":
        steps = f", {ray['steps']} steps" if ray["steps"] else ""
        return f"volume segment: lets {_rgb(ray['transmittance'])} through{steps}"
    if ray["cut"]:
        return f"{ray['kind']}: cut ({ray['cut']})"
    if ray["kind"] == "camera":
        # Where the sample left the lens, and when in the shutter (distributed ray tracing).
        x, y, z = ray["origin"]
        return f"camera from ({x:.3g}, {y:.3g}, {z:.3g}) at t={ray.get('time', 0.0):.2f} -> {what}"
    return f"{ray['kind']} -> {what}"


def draw_ray_tree(layout, scene):
    layout.operator("whitted.inspect_ray_tree", icon="EYEDROPPER")
    tree = loads(scene.whitted.last_ray_tree)
    if tree is None:
        layout.label(text="No ray tree: inspect a pixel")
        return
    row = layout.row(align=True)
    row.operator("whitted.ray_tree_to_curve", icon="CURVE_DATA")
    row.operator("whitted.clear_ray_tree", icon="X", text="")
    summary = tree["summary"]
    column = layout.column(align=True)
    column.label(
        text=f"Pixel ({tree['x']}, {tree['y']}) of the {tree['source']}: {_rgb(tree['pixel'])}"
    )
    column.label(text=summary["text"])
    counts = summary["counts"]
    column.label(text=", ".join(f"{counts[k]} {k}" for k in KINDS if counts[k]))
    box = layout.box().column(align=True)
    for ray in tree["rays"][:MAX_ROWS]:
        row = box.row()
        row.label(text="    " * ray["depth"] + _ray_label(ray))
        row.label(text=_rgb(ray["contribution"]))
    if len(tree["rays"]) > MAX_ROWS:
        more = len(tree["rays"]) - MAX_ROWS
        box.label(text=f"... {more} more rays (scene.whitted.last_ray_tree)")


class _RayTreePanel:
    bl_region_type = "UI"
    bl_category = "Whitted"
    bl_label = "Ray Tree"

    @classmethod
    def poll(cls, context):
        return context.engine == "WHITTED"

    def draw(self, context):
        draw_ray_tree(self.layout, context.scene)


class WHITTED_VIEW3D_PT_ray_tree(_RayTreePanel, bpy.types.Panel):
    bl_space_type = "VIEW_3D"


class WHITTED_IMAGE_PT_ray_tree(_RayTreePanel, bpy.types.Panel):
    bl_space_type = "IMAGE_EDITOR"
