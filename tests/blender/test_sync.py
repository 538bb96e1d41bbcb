"""The sync layer (addon/sync): after any sequence of edits, the synced native scene
renders the same pixels as a full export of the edited scene, bit for bit, and each
sync re-exports only what the edit touched.

The depsgraph lists its updates only while they are delivered, so the live sync
runs in a depsgraph_update_post handler, as the viewport's view_update does.
"""

import math

import bpy
import numpy as np
import pytest
from test_objects import grid_points, scatter
from whitted.export.camera import convert_camera
from whitted.properties.presets import preset
from whitted.sync import SceneSync, SyncParams
from whitted.sync.native_data import native_camera
from whitted.sync.scene import _same_instance

WIDTH, HEIGHT = 64, 48


class LiveSync:
    """A SceneSync fed by Blender's depsgraph updates, as the viewport feeds it."""

    def __init__(self, native, scene):
        self.native = native
        self.sync = SceneSync(native)
        self.reports = []
        self.sync.sync(bpy.context.evaluated_depsgraph_get(), params(scene))
        bpy.app.handlers.depsgraph_update_post.append(self.on_update)

    def on_update(self, scene, depsgraph):
        self.reports.append(self.sync.sync(depsgraph, params(scene)))

    def close(self):
        bpy.app.handlers.depsgraph_update_post.remove(self.on_update)

    def edit(self, change):
        """Apply `change`, let the depsgraph evaluate; the reports of the syncs it ran."""
        self.reports = []
        change()
        bpy.context.view_layer.update()
        return self.reports


def params(scene):
    return SyncParams.of(scene, preset("PREVIEW"))


def render(native, scene_sync, blender_scene):
    settings = native.Settings(width=WIDTH, height=HEIGHT, aa_samples=1, threads=2)
    camera = convert_camera(blender_scene.camera, blender_scene.render, [])
    job = native.RenderJob(scene_sync.scene, settings, camera=native_camera(native, camera))
    job.start()
    while not job.wait(1.0):
        pass
    return job.image()


def full_export(native, scene):
    fresh = SceneSync(native)
    fresh.sync(bpy.context.evaluated_depsgraph_get(), params(scene))
    return fresh


@pytest.fixture
def scene(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    cube = scene.objects["Cube"]
    twin = cube.copy()  # a linked duplicate: one mesh, two instances
    twin.name = "Cube Twin"
    twin.location.x -= 5.0
    scene.collection.objects.link(twin)
    spheres = scatter(scene, grid_points(16, 1.0) + np.array([0.0, -4.0, 0.5]))
    spheres.scale = (2.0, 2.0, 2.0)
    textured = bpy.data.materials.new("Textured")
    if bpy.app.version < (5, 0, 0):  # 5.0 always shades with nodes
        textured.use_nodes = True
    image = bpy.data.images.new("Stripes", 8, 8)
    image.pixels.foreach_set(np.tile([1.0, 0.2, 0.1, 1.0], 64).astype(np.float32))
    node = textured.node_tree.nodes.new("ShaderNodeTexImage")
    node.image = image
    principled = textured.node_tree.nodes["Principled BSDF"]
    textured.node_tree.links.new(node.outputs["Color"], principled.inputs["Base Color"])
    cube.data.materials.clear()
    cube.data.materials.append(textured)
    bpy.context.view_layer.update()
    return scene


@pytest.fixture
def live(native, scene):
    live = LiveSync(native, scene)
    yield live
    live.close()


def _add_cube(scene):
    mesh = bpy.data.meshes.new("Added")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)], [], [(0, 1, 2), (0, 2, 3)])
    obj = bpy.data.objects.new("Added", mesh)
    obj.location = (-1.5, -3.0, 0.5)
    scene.collection.objects.link(obj)


def _edit_vertices(obj):
    mesh = obj.data
    mesh.vertices[0].co.z += 0.4
    mesh.update()


def _texture_pixels():
    image = bpy.data.images["Stripes"]
    image.pixels.foreach_set(np.tile([0.1, 0.9, 0.3, 1.0], 64).astype(np.float32))
    # As texture painting does: the depsgraph hears of an image only when it is tagged.
    image.update_tag()


def _swap_texture():
    other = bpy.data.images.new("Checks", 4, 4)
    other.pixels.foreach_set(np.tile([0.2, 0.3, 1.0, 1.0], 16).astype(np.float32))
    bpy.data.materials["Textured"].node_tree.nodes["Image Texture"].image = other


def _base_color(name, color):
    principled = bpy.data.materials[name].node_tree.nodes["Principled BSDF"]
    principled.inputs["Base Color"].default_value = color


def _rough_metal(name, roughness):
    principled = bpy.data.materials[name].node_tree.nodes["Principled BSDF"]
    principled.inputs["Metallic"].default_value = 1.0
    principled.inputs["Roughness"].default_value = roughness


# (name, edit(scene), what the syncs of that edit may re-export at most)
EDITS = (
    ("move", lambda s: setattr(s.objects["Cube"], "location", (2.0, -1.0, 0.9)), "transform"),
    (
        "rotate",
        lambda s: setattr(s.objects["Cylinder"], "rotation_euler", (0.3, 0.0, 0.5)),
        "transform",
    ),
    ("scale", lambda s: setattr(s.objects["Cube Twin"], "scale", (1.0, 1.5, 0.7)), "transform"),
    ("edit vertices", lambda s: _edit_vertices(s.objects["Cube"]), "geometry"),
    ("add modifier", lambda s: s.objects["Cylinder"].modifiers.new("Bevel", "BEVEL"), "geometry"),
    ("material colour", lambda s: _base_color("Checker 0", (0.1, 0.6, 0.2, 1.0)), "material"),
    # A rough metal reflects glossily in the Blender local model, as a mirror and a Phong
    # highlight in the Lecture model: switching re-exports it, and the lamps, whose shapes
    # no ray sees in the Lecture model.
    ("rough metal", lambda s: _rough_metal("Checker 0", 0.35), "material"),
    (
        "local model",
        lambda s: (setattr(s.whitted, "local_model", "LECTURE"), s.update_tag()),
        "model",
    ),
    ("texture pixels", lambda s: _texture_pixels(), "texture"),
    ("swap texture", lambda s: _swap_texture(), "texture"),
    ("add object", _add_cube, "any"),
    ("hide object", lambda s: s.objects["Mirror Sphere"].hide_set(True), "any"),
    ("hide in renders", lambda s: setattr(s.objects["Cube Twin"], "hide_render", True), "any"),
    ("unhide object", lambda s: s.objects["Mirror Sphere"].hide_set(False), "any"),
    ("delete object", lambda s: bpy.data.objects.remove(s.objects["Cylinder"]), "any"),
    # Its camera pixels then show only the shadows on it (integrator/catcher.h).
    ("shadow catcher", lambda s: setattr(s.objects["Cube"], "is_shadow_catcher", True), "any"),
    ("light power", lambda s: setattr(s.objects["Point Light"].data, "energy", 500.0), "light"),
    (
        "light move",
        lambda s: setattr(s.objects["Point Light"], "location", (2.0, 4.0, 5.0)),
        "light",
    ),
    (
        "world",
        lambda s: setattr(s.world.node_tree.nodes["Background"].inputs[1], "default_value", 0.3),
        "world",
    ),
    # Python sets an add-on property without telling the depsgraph; the UI tags the scene.
    ("ambient", lambda s: (setattr(s.whitted, "ambient_strength", 0.5), s.update_tag()), "world"),
    ("scatter count", lambda s: _scatter_more(s), "any"),
    ("scatter move", lambda s: setattr(s.objects["Scatter"], "location", (0.5, 0.0, 0.0)), "any"),
    ("camera", lambda s: setattr(s.objects["Camera"], "location", (1.0, -10.0, 4.0)), "nothing"),
    (
        "light samples",
        lambda s: setattr(s.objects["Point Light"].data, "shadow_soft_size", 0.5),
        "light",
    ),
    # Hair and points (issue 31): added, edited and moved as the viewport sees them.
    ("add hair", lambda s: _add_hair(s.objects["Cube"]), "any"),
    ("hair length", lambda s: _hair_settings(s, "hair_length", 0.9), "any"),
    ("hair children", lambda s: _hair_settings(s, "child_type", "SIMPLE"), "any"),
    ("move hairy", lambda s: setattr(s.objects["Cube"], "location", (1.5, -1.0, 0.9)), "any"),
    ("add points", lambda s: _add_points(s), "any"),
    # Volume objects (issue 48): added, their material edited, moved, clipped.
    ("add smoke", lambda s: _add_smoke(s), "any"),
    ("smoke density", lambda s: _smoke_density(0.8), "any"),
    ("move smoke", lambda s: setattr(s.objects["Smoke"], "location", (1.0, 0.5, 0.0)), "any"),
    # Its Clipping above every voxel: its mesh encloses nothing (VolumeObject.bound_mesh).
    ("clip smoke", lambda s: _clip_smoke(s.objects["Smoke"]), "any"),
)
# Light linking and shadow linking (Blender 4.0+): linked, relinked and unlinked.
if bpy.app.version >= (4, 0, 0):
    EDITS += (
        ("light linking", lambda s: _link(s, "receiver_collection", "INCLUDE"), "any"),
        ("exclude instead", lambda s: _link_state(s, "receiver_collection", "EXCLUDE"), "any"),
        ("shadow linking", lambda s: _link(s, "blocker_collection", "EXCLUDE"), "any"),
        (
            "unlink",
            lambda s: setattr(s.objects["Point Light"].light_linking, "receiver_collection", None),
            "any",
        ),
    )


def _link(scene, kind, state):
    collection = bpy.data.collections.new(f"Linked {kind}")
    collection.objects.link(scene.objects["Cube"])
    collection.collection_objects[0].light_linking.link_state = state
    setattr(scene.objects["Point Light"].light_linking, kind, collection)


def _link_state(scene, kind, state):
    collection = getattr(scene.objects["Point Light"].light_linking, kind)
    collection.collection_objects[0].light_linking.link_state = state


def _add_hair(obj):
    obj.modifiers.new("Fur", "PARTICLE_SYSTEM")
    settings = obj.particle_systems[0].settings
    settings.type = "HAIR"
    settings.count = 40
    settings.hair_length = 0.5
    settings.radius_scale = 0.05


def _hair_settings(scene, name, value):
    setattr(scene.objects["Cube"].particle_systems[0].settings, name, value)


def _add_points(scene):
    from whitted_tools.hair_scenes import point_cloud_modifier

    plane = scene.objects.get("Added") or scene.objects["Cube Twin"]
    point_cloud_modifier(plane, density=20.0, radius=0.1)


def _add_smoke(scene):
    # A Mesh to Volume filling a hidden cube, shaded by a Principled Volume reading its grid.
    from whitted_tools.scenes import add_object, cube_mesh, mesh_to_volume
    from whitted_tools.volume_scenes import principled_volume, volume_material

    source = add_object(scene, "Smoke Source", cube_mesh("Smoke Source", 1.5), location=(1, 0, 1))
    source.hide_render = True
    smoke = mesh_to_volume(scene, "Smoke", source, 0.25)
    smoke.data.materials.append(volume_material("Smoke", principled_volume(0.3)))


def _clip_smoke(smoke):
    smoke.modifiers["Fill"].density = 0.5
    smoke.data.render.clipping = 0.6


def _smoke_density(density):
    nodes = bpy.data.materials["Smoke"].node_tree.nodes
    nodes["Principled Volume"].inputs["Density"].default_value = density


def _scatter_more(scene):
    mesh = scene.objects["Scatter"].data
    mesh.vertices.add(4)
    for i, vertex in enumerate(mesh.vertices[-4:]):
        vertex.co = (1.2 + 0.2 * i, 0.0, 1.2)
    mesh.update()


# Blender 5.3's depsgraph flags an object's geometry as updated when a material or an
# image it uses changes (is_updated_geometry on the Object; 5.2 flags shading only;
# seen with bpy 5.3.0). The sync then exports the object's mesh again, as Cycles' sync
# does on that flag: the mesh is the same, so only the time differs.
SHADING_EDIT_FLAGS_GEOMETRY = bpy.app.version >= (5, 3, 0)
SHADING_MESHES = {"meshes"} if SHADING_EDIT_FLAGS_GEOMETRY else set()


def _within(kind, report):
    """Whether `report` did no more than an edit of `kind` needs."""
    exported = {
        "meshes": report.meshes,
        "materials": report.materials,
        "textures": report.textures,
        "lights": report.lights,
    }
    allowed = {
        "transform": set(),
        "geometry": {"meshes"},
        "material": {"materials", *SHADING_MESHES},
        "texture": {"textures", "materials", *SHADING_MESHES},
        "light": {"lights"},
        "model": {"materials", "lights", *SHADING_MESHES},
        "world": set(),
        "nothing": set(),
        "any": set(exported),
    }[kind]
    if kind == "transform" and report.walked:
        return False
    if kind in ("transform", "geometry") and report.meshes > (1 if kind == "geometry" else 0):
        return False
    if kind == "world" and not report.world:
        return False
    if kind == "nothing" and (report.instances or report.world or report.removed):
        return False
    return all(count == 0 for name, count in exported.items() if name not in allowed)


def test_each_edit_syncs_to_the_pixels_of_a_full_export(native, scene, live):
    assert render(native, live.sync, scene).any()
    for name, change, kind in EDITS:
        reports = live.edit(lambda change=change: change(scene))
        assert reports, f"{name}: no depsgraph update reached the sync"
        for report in reports:
            assert _within(kind, report), f"{name}: {report}"
        full = full_export(native, scene)
        synced = render(native, live.sync, scene)
        expected = render(native, full, scene)
        assert np.array_equal(synced, expected), (
            f"after '{name}': {np.count_nonzero((synced != expected).any(axis=-1))} pixels "
            f"differ, max {np.abs(synced - expected).max()}; {_differences(live.sync, full)}"
        )


def _differences(synced, full):
    """What the two syncs hold differently, for a failure message."""
    out = []
    for what in ("_instances", "_geometry", "_materials", "_textures", "_lights", "_world"):
        a, b = getattr(synced, what), getattr(full, what)
        if not isinstance(a, dict):
            if a != b:
                out.append(f"{what}: {a} != {b}")
            continue
        if a.keys() != b.keys():
            out.append(
                f"{what}: only synced {a.keys() - b.keys()}, only full {b.keys() - a.keys()}"
            )
        for key in a.keys() & b.keys():
            same = _same_instance(a[key], b[key]) if what == "_instances" else a[key] == b[key]
            if not same:
                out.append(f"{what}[{key}]: {a[key]} != {b[key]}")
    return "; ".join(out) or "the same data"


def test_transform_edit_moves_only_the_instance(native, scene, live):
    builds = live.sync.scene.top_level_builds
    (report,) = live.edit(lambda: setattr(scene.objects["Cube"], "location", (0, 0, 3)))
    assert not report.walked
    assert (report.meshes, report.instances, report.materials, report.lights) == (0, 1, 0, 0)
    render(native, live.sync, scene)
    # The move rebuilt the top level (Embree's instance transforms), nothing else.
    assert live.sync.scene.top_level_builds == builds + 1


def test_a_shadow_catcher_switch_reaches_the_live_scene(native, scene, live):
    before = render(native, live.sync, scene)
    live.edit(lambda: setattr(scene.objects["Cube"], "is_shadow_catcher", True))
    assert live.sync._instances["Cube"].shadow_catcher
    # The cube's pixels now show only the shadows cast on it (integrator/catcher.h).
    assert not np.array_equal(render(native, live.sync, scene), before)


def test_geometry_edit_exports_the_shared_mesh_once(native, scene, live):
    (report,) = live.edit(lambda: _edit_vertices(scene.objects["Cube Twin"]))
    # Cube and its twin share the mesh: one export serves both instances.
    assert report.meshes == 1


def test_camera_and_world_edits_keep_the_top_level_bvh(native, scene, live):
    render(native, live.sync, scene)
    builds = live.sync.scene.top_level_builds
    live.edit(lambda: setattr(scene.objects["Camera"], "location", (0.0, -12.0, 3.0)))
    live.edit(
        lambda: setattr(scene.world.node_tree.nodes["Background"].inputs[1], "default_value", 2.0)
    )
    if not SHADING_EDIT_FLAGS_GEOMETRY:  # there the Glass sphere's mesh is exported again
        live.edit(lambda: _base_color("Glass", (0.9, 0.9, 1.0, 1.0)))
    render(native, live.sync, scene)
    assert live.sync.scene.top_level_builds == builds


def test_keys_survive_re_evaluation(native, scene):
    # Two full exports of one scene, with a re-evaluation between them, name every
    # mesh and instance the same: nothing would be exported again by a later sync.
    first = full_export(native, scene)
    scene.frame_set(scene.frame_current)
    second = full_export(native, scene)
    assert first._geometry.keys() == second._geometry.keys()
    assert first._instances.keys() == second._instances.keys()
    assert len(first._instances) > 16  # the scatter's instances are there


def test_instancer_edit_reexports_no_geometry_it_does_not_own(native, scene, live):
    (report,) = live.edit(
        lambda: setattr(scene.objects["Scatter"], "rotation_euler", (0, 0, math.pi / 4))
    )
    assert report.walked  # an instancer moved: its instances are compared
    assert report.meshes == 0
    assert report.instances == 16


def test_two_full_exports_render_the_same_pixels(native, scene):
    # Blender 3.x sums vertex normals on several threads in no fixed order; the
    # exporter computes them itself so that a render is a pure function of the scene.
    first = render(native, full_export(native, scene), scene)
    for _ in range(4):
        assert np.array_equal(render(native, full_export(native, scene), scene), first)
