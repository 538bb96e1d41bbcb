"""500 seeded random edits while the Whitted viewport renders progressively.

--edits N (500), --seed S (1), --interval SECONDS between edits (0.12). The edit
kinds: move, rotate, scale, vertex edit, material colour, light, add cube, delete,
hide/unhide, resize the main region (sidebar and toolbar on/off), shading
SOLID <-> RENDERED. The edits do not wait for convergence: most land while a
render is in flight. Resident memory (VmRSS) is sampled every 10 edits.
"""

import random
import time

import bmesh
import bpy
from whitted_tools import viewport_driver as driver

# Cubes the run may add at most at a time (a delete removes one first).
MAX_ADDED = 8


def add_arguments(parser):
    parser.add_argument("--edits", type=int, default=500)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--interval", type=float, default=0.05)
    # Another engine proves the scenario itself (no viewport log: fixed waits instead).
    parser.add_argument("--engine", default="WHITTED")


class Editor:
    def __init__(self, h, rng):
        self.h = h
        self.rng = rng
        self.added = 0
        self.counts = {}

    def meshes(self):
        return [o for o in bpy.context.scene.objects if o.type == "MESH"]

    def pick(self):
        candidates = [o for o in self.meshes() if o.name != "Floor"]
        return self.rng.choice(candidates) if candidates else None

    def uniform(self, low, high):
        return self.rng.uniform(low, high)

    # --- the edit kinds ----------------------------------------------------------
    def move(self):
        obj = self.pick()
        if obj:
            obj.location.x = self.uniform(-4, 4)
            obj.location.y = self.uniform(-3, 4)
            obj.location.z = self.uniform(0.3, 2.5)

    def rotate(self):
        obj = self.pick()
        if obj:
            obj.rotation_euler = [self.uniform(-3.1, 3.1) for _ in range(3)]

    def scale(self):
        obj = self.pick()
        if obj:
            obj.scale = [self.uniform(0.5, 1.5)] * 3

    def vertices(self):
        obj = self.pick()
        if obj:
            mesh = obj.data
            for _ in range(8):
                vertex = mesh.vertices[self.rng.randrange(len(mesh.vertices))]
                vertex.co.z += self.uniform(-0.1, 0.1)
            mesh.update()

    def colour(self):
        material = self.rng.choice([m for m in bpy.data.materials if m.node_tree])
        colour = (self.uniform(0, 1), self.uniform(0, 1), self.uniform(0, 1), 1.0)
        principled = material.node_tree.nodes.get("Principled BSDF")
        if principled:
            principled.inputs["Base Color"].default_value = colour
        material.diffuse_color = colour

    def light(self):
        lights = [o for o in bpy.context.scene.objects if o.type == "LIGHT"]
        light = self.rng.choice(lights).data
        light.energy = light.energy * self.uniform(0.7, 1.4)
        light.color = (self.uniform(0.6, 1), self.uniform(0.6, 1), self.uniform(0.6, 1))

    def add_cube(self):
        if self.added >= MAX_ADDED:
            self.delete()
            return
        mesh = bpy.data.meshes.new("Stress Cube")
        bm = bmesh.new()
        try:
            bmesh.ops.create_cube(bm, size=0.6)
            bm.to_mesh(mesh)
        finally:
            bm.free()
        obj = bpy.data.objects.new("Stress Cube", mesh)
        obj.location = (self.uniform(-4, 4), self.uniform(-3, 4), 0.3)
        mesh.materials.append(self.rng.choice(bpy.data.materials))
        bpy.context.scene.collection.objects.link(obj)
        self.added += 1

    def delete(self):
        added = [o for o in self.meshes() if o.name.startswith("Stress Cube")]
        # Keep the demo's own objects in play until cubes were added to delete.
        obj = self.rng.choice(added) if added else self.pick()
        if obj is None or (not added and len(self.meshes()) <= 3):
            return
        mesh = obj.data
        bpy.data.objects.remove(obj)
        # The orphaned mesh too, or deleted cubes would count as memory growth.
        if mesh.users == 0:
            bpy.data.meshes.remove(mesh)
        if added:
            self.added -= 1

    def hide(self):
        obj = self.pick()
        if obj:
            obj.hide_set(not obj.hide_get())

    def resize(self):
        # Changes the main region's size: view_draw must follow (a new texture size).
        space = self.h.space
        if self.rng.random() < 0.5:
            space.show_region_ui = not space.show_region_ui
        else:
            space.show_region_toolbar = not space.show_region_toolbar

    def shading(self):
        space = self.h.space
        space.shading.type = "SOLID" if space.shading.type == "RENDERED" else "RENDERED"

    KINDS = (
        ("move", 3),
        ("rotate", 2),
        ("scale", 2),
        ("vertices", 2),
        ("colour", 2),
        ("light", 2),
        ("add_cube", 1),
        ("delete", 1),
        ("hide", 1),
        ("resize", 1),
        ("shading", 1),
    )

    def random_edit(self):
        names = [name for name, _ in self.KINDS]
        weights = [weight for _, weight in self.KINDS]
        name = self.rng.choices(names, weights)[0]
        getattr(self, name)()
        self.counts[name] = self.counts.get(name, 0) + 1
        self.h.region.tag_redraw()


def scenario(h):
    scene = bpy.context.scene
    scene.render.engine = h.args.engine
    whitted = h.args.engine == "WHITTED"
    yield h.maximise()
    h.setup_view("SOLID")
    mark = h.log.mark()
    h.set_shading("RENDERED")
    yield h.until_converged(mark) if whitted else 2.0
    editor = Editor(h, random.Random(h.args.seed))
    rss = []
    started = time.perf_counter()
    h.step(f"{h.args.edits} edits")
    for index in range(h.args.edits):
        if index % 10 == 0:
            rss.append([index, driver.rss_mb()])
        editor.random_edit()
        yield h.args.interval
    rss.append([h.args.edits, driver.rss_mb()])
    h.record("edit_seconds", time.perf_counter() - started)
    h.record("t_edits", [started, time.perf_counter()])
    h.record("rss_mb", rss)
    h.record("counts", editor.counts)
    h.record("edits", h.args.edits)
    # End in Rendered mode with one last edit, and wait for convergence on it: after
    # all that, the viewport still renders to the end.
    if h.space.shading.type != "RENDERED":
        h.set_shading("RENDERED")
        yield 0.5
    mark = h.log.mark()
    h.step("final edit and convergence")
    editor.move()
    yield h.until_converged(mark) if whitted else 2.0
    yield from h.screenshot("final")
    h.set_shading("SOLID")
    yield 1.0


driver.main(scenario, add_arguments)
