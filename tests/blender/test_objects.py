"""Objects as artists set them up: ray visibility, holdout, transparent film,
negative and non-uniform scale, custom normals, many instances, animation
frames, and the render border.

The scenes are tiny: an orthographic camera at -Y looking along +Y (image
right is +X, image up is +Z), no world (so no ambient light), and meshes of a diffuse
albedo 0.8: without a material up to Blender 4.5 (what it renders with there), with a
Diffuse BSDF material from 5.0 (where no material is a Principled BSDF with a highlight).
Pixels are linear radiance, rows bottom to top.
"""

import functools
import math
import os
import subprocess

import bpy

# isort: split
# Blender as a Python module makes bmesh importable only after bpy.
import numpy as np
import pytest
from exported import exported_meshes
from whitted.export.film import FilmData, PixelFilter, convert_film
from whitted.export.instance import RayVisibility
from whitted_tools import scenes
from whitted_tools.material_scenes import lambert_material
from whitted_tools.scenes import add_object, cube_mesh, ico_sphere_on_points

SIZE = 32  # image width and height, pixels
VIEW = 4.0  # the camera's orthographic scale: the image spans x and z in [-2, 2]
SUN_STRENGTH = 3.0  # W/m^2


def pixel(x, z):
    """(row, column) of the pixel that shows world point (x, *, z)."""
    return int((z / VIEW + 0.5) * SIZE), int((x / VIEW + 0.5) * SIZE)


def link(scene, name, data, location=(0.0, 0.0, 0.0), collection=None):
    # Blender 3.4 and 4.x: no material, the native default. (A Diffuse BSDF material
    # instead gives the quad whose custom normal faces away from the sun 0.005 of LIT in
    # 3.4, not 0: not yet explained.)
    if bpy.app.version >= (5, 0, 0) and isinstance(data, bpy.types.Mesh) and not data.materials:
        data.materials.append(
            bpy.data.materials.get("Lambert 0.8") or lambert_material("Lambert 0.8", 0.8)
        )
    return add_object(collection or scene, name, data, location)


# Coarser than the package's default sphere: the images are 32 pixels across.
sphere_mesh = functools.partial(scenes.sphere_mesh, segments=12, rings=6)


def quad_mesh(name, half_size):
    """A square in the XZ plane facing the camera (-Y)."""
    mesh = bpy.data.meshes.new(name)
    h = half_size
    mesh.from_pydata([(-h, 0, -h), (h, 0, -h), (h, 0, h), (-h, 0, h)], [], [(0, 1, 2, 3)])
    return mesh


def add_sun(scene, rotation, name="Sun"):
    sun = bpy.data.lights.new(name, "SUN")
    sun.energy = SUN_STRENGTH
    obj = link(scene, name, sun)
    obj.rotation_euler = rotation
    return obj


# A sun whose light travels along +Y, from the camera into the scene.
FROM_CAMERA = (math.pi / 2, 0.0, 0.0)


@pytest.fixture
def scene(empty_scene):
    """Camera, size and settings; no world, no lights, no objects."""
    camera_data = bpy.data.cameras.new("Camera")
    camera_data.type = "ORTHO"
    camera_data.ortho_scale = VIEW
    camera = link(empty_scene, "Camera", camera_data, location=(0.0, -10.0, 0.0))
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)
    empty_scene.camera = camera
    render = empty_scene.render
    render.resolution_x = render.resolution_y = SIZE
    render.resolution_percentage = 100
    empty_scene.world = None
    empty_scene.whitted.aa_samples = 1
    return empty_scene


@pytest.fixture
def stage(scene):
    """A backdrop (half size 1.5) behind a cube (size 1) at the origin, lit from
    the camera: the cube's shadow on the backdrop lies right behind the cube."""
    link(scene, "Backdrop", quad_mesh("Backdrop", 1.5), location=(0.0, 2.0, 0.0))
    link(scene, "Cube", cube_mesh())
    add_sun(scene, FROM_CAMERA)
    return scene


CENTER = pixel(0.0, 0.0)  # the cube, or its shadow on the backdrop
BACKDROP = pixel(1.0, 1.0)  # the lit backdrop, beside the cube
SKY = (0, 0)  # nothing: outside the backdrop
LIT = 0.8 * SUN_STRENGTH / math.pi  # radiance of the diffuse material facing the sun


# --- Ray visibility and holdout ---------------------------------------------------


def test_ray_visibility_is_read_from_the_object_and_its_instancer(scene, warnings):
    source = bpy.data.collections.new("Source")
    scene.collection.children.link(source)
    ball = link(scene, "Ball", sphere_mesh(), collection=source)
    ball.visible_glossy = False
    bpy.context.view_layer.layer_collection.children["Source"].exclude = True
    instancer = link(scene, "Instancer", None)
    instancer.instance_type = "COLLECTION"
    instancer.instance_collection = source
    instancer.visible_shadow = False
    plain = link(scene, "Plain", cube_mesh())
    plain.visible_camera = False
    plain.visible_transmission = False

    exported = exported_meshes(bpy.context.evaluated_depsgraph_get(), warnings)
    visibility = {i.name.split("/")[0]: i.visibility for i in exported.instances}
    # As in Cycles, an instance is seen only by rays that both it and its instancer allow.
    assert visibility["Instancer"] == RayVisibility(shadow=False, reflection=False)
    assert visibility["Plain"] == RayVisibility(camera=False, refraction=False)
    assert not any(i.holdout for i in exported.instances)


def test_object_and_collection_holdout_are_exported(scene, warnings):
    link(scene, "Object Holdout", cube_mesh("A")).is_holdout = True
    masks = bpy.data.collections.new("Masks")
    scene.collection.children.link(masks)
    link(scene, "In Holdout Collection", cube_mesh("B"), collection=masks)
    bpy.context.view_layer.layer_collection.children["Masks"].holdout = True
    link(scene, "Plain", cube_mesh("C"))
    exported = exported_meshes(bpy.context.evaluated_depsgraph_get(), warnings)
    assert {i.name: i.holdout for i in exported.instances} == {
        "Object Holdout": True,
        "In Holdout Collection": True,
        "Plain": False,
    }


def test_an_object_hidden_from_the_camera_still_casts_its_shadow(stage, render_pixels):
    shown = render_pixels(stage)
    stage.objects["Cube"].visible_camera = False
    hidden = render_pixels(stage)
    # The camera sees the cube's face (lit, facing the sun) ...
    assert shown[CENTER][0] == pytest.approx(LIT, rel=0.02)
    # ... and, without it, the backdrop in the cube's shadow.
    assert hidden[CENTER][:3] == pytest.approx((0.0, 0.0, 0.0), abs=1e-6)
    assert hidden[CENTER][3] == pytest.approx(1.0)
    assert hidden[BACKDROP][0] == pytest.approx(LIT, rel=0.02)


def test_an_object_with_shadows_off_casts_none(stage, render_pixels):
    cube = stage.objects["Cube"]
    cube.visible_camera = False
    cube.visible_shadow = False
    pixels = render_pixels(stage)
    assert pixels[CENTER][0] == pytest.approx(LIT, rel=0.02)


def test_holdout_gives_colour_and_alpha_zero(stage, render_pixels):
    stage.objects["Cube"].is_holdout = True
    pixels = render_pixels(stage)
    np.testing.assert_array_equal(pixels[CENTER], (0.0, 0.0, 0.0, 0.0))
    assert pixels[BACKDROP][3] == pytest.approx(1.0)
    assert pixels[BACKDROP][0] == pytest.approx(LIT, rel=0.02)


def test_transparent_film_makes_the_sky_alpha_zero(stage, render_pixels):
    assert render_pixels(stage)[SKY][3] == pytest.approx(1.0)
    stage.render.film_transparent = True
    pixels = render_pixels(stage)
    np.testing.assert_array_equal(pixels[SKY], (0.0, 0.0, 0.0, 0.0))
    assert pixels[BACKDROP][3] == pytest.approx(1.0)


# --- Scale and normals ---------------------------------------------------------


@pytest.mark.parametrize("smooth", [True, False], ids=["smooth", "flat"])
def test_a_mirrored_scene_renders_mirrored(scene, render_pixels, smooth):
    # A sphere turned about Z (so the mesh is not symmetric in X) lit from the
    # right, then the whole scene mirrored in X: the sphere by scale -1, the turn
    # and the light by their mirror images. The image must be the mirror image,
    # so normals and winding survive the negative scale.
    sphere = link(scene, "Sphere", sphere_mesh(smooth=smooth))
    sphere.rotation_euler = (0.0, 0.0, math.radians(20.0))
    sun = add_sun(scene, (math.radians(-30.0), math.radians(60.0), 0.0))
    original = render_pixels(scene)
    sphere.rotation_euler.z = math.radians(-20.0)
    sphere.scale = (-1.0, 1.0, 1.0)
    sun.rotation_euler = (math.radians(-30.0), math.radians(-60.0), 0.0)
    mirrored = render_pixels(scene)
    assert original[..., 0].max() > 0.5 * LIT  # the lit side shows
    np.testing.assert_allclose(mirrored, original[:, ::-1], atol=1e-4)


def test_non_uniform_scale_shades_like_the_scaled_mesh(scene, render_pixels):
    # Normals under a non-uniform scale transform by the inverse transpose: the
    # scaled object must shade like a mesh whose vertices were scaled instead.
    scale = (1.6, 1.0, 0.6)
    sphere = link(scene, "Sphere", sphere_mesh(segments=48, rings=24))
    sphere.scale = scale
    add_sun(scene, (math.radians(-40.0), math.radians(50.0), 0.0))
    by_object = render_pixels(scene)
    sphere.scale = (1.0, 1.0, 1.0)
    sphere.data = sphere_mesh("Scaled", segments=48, rings=24, scale=scale)
    if bpy.app.version >= (5, 0, 0):
        sphere.data.materials.append(bpy.data.materials["Lambert 0.8"])
    by_mesh = render_pixels(scene)
    covered = by_mesh[..., 0] > 0.0
    assert np.abs(by_object - by_mesh)[covered][:, :3].mean() < 0.01 * LIT
    assert by_object[..., 0].max() > 0.5 * LIT


def tilted_normals_quad(tilt_x):
    """A smooth quad facing the camera whose custom normals lean towards +X by
    `tilt_x` (a unit normal (tilt_x, -sqrt(1 - tilt_x^2), 0))."""
    mesh = quad_mesh("Quad", 1.5)
    mesh.polygons[0].use_smooth = True
    if hasattr(mesh, "use_auto_smooth"):  # Blender < 4.1: custom normals need it
        mesh.use_auto_smooth = True
    normal = (tilt_x, -math.sqrt(1.0 - tilt_x * tilt_x), 0.0)
    mesh.normals_split_custom_set([normal] * len(mesh.loops))
    return mesh


@pytest.mark.parametrize("tilt_x", [0.7071068, -0.7071068, 0.0])
def test_shading_follows_custom_split_normals(scene, render_pixels, tilt_x):
    # Sunlight arrives from the front right, along (-1, 1, 0)/sqrt(2): a normal
    # facing it gets n.l = 1, the geometric normal (0, -1, 0) gets 0.71, and a
    # normal leaning the other way gets 0. The quad's geometry is the same in
    # every case, so only the custom normals change the shading.
    link(scene, "Quad", tilted_normals_quad(tilt_x))
    add_sun(scene, (math.pi / 2, 0.0, math.radians(45.0)))
    pixels = render_pixels(scene)
    light = np.array((-1.0, 1.0, 0.0)) / math.sqrt(2.0)  # the way the light travels
    normal = np.array((tilt_x, -math.sqrt(1.0 - tilt_x * tilt_x), 0.0))
    expected = LIT * max(0.0, float(-light @ normal))
    # Blender stores custom normals to about 1e-3 (16-bit angles).
    assert pixels[CENTER][0] == pytest.approx(expected, rel=0.02, abs=0.005 * LIT)


def corner_normals(scene, warnings):
    (mesh,) = exported_meshes(bpy.context.evaluated_depsgraph_get(), warnings).meshes
    return mesh


def test_auto_smooth_keeps_sharp_edges_flat(scene, warnings):
    cube = link(scene, "Cube", cube_mesh(smooth=True))
    smoothed = corner_normals(scene, warnings).corner_normals()
    # Smooth all round: corners of a face lean out diagonally.
    assert np.abs(smoothed).max() < 0.6
    # Auto smooth at 30 degrees (3.x) or sharp edges by angle (4.1+): the cube's
    # 90-degree edges are sharp, so every corner keeps its face's normal.
    mesh = cube.data
    if hasattr(mesh, "use_auto_smooth"):
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = math.radians(30.0)
    else:
        mesh.set_sharp_from_angle(angle=math.radians(30.0))
    data = corner_normals(scene, warnings)
    face = np.cross(
        data.positions[data.triangles[:, 1]] - data.positions[data.triangles[:, 0]],
        data.positions[data.triangles[:, 2]] - data.positions[data.triangles[:, 0]],
    )
    face /= np.linalg.norm(face, axis=-1, keepdims=True)
    if bpy.app.version >= (4, 1, 0):
        assert data.corner_normals() is None  # every edge sharp: Blender calls it flat
    else:
        np.testing.assert_allclose(data.normals, np.repeat(face[:, None], 3, axis=1), atol=1e-5)


# --- Instancing ----------------------------------------------------------------


def scatter(scene, points, name="Scatter"):
    """An object whose geometry nodes put an ico sphere on each of `points`."""
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(points))
    mesh.vertices.foreach_set("co", np.asarray(points, dtype=np.float32).reshape(-1))
    obj = link(scene, name, mesh)
    tree = ico_sphere_on_points(name, radius=0.015)
    obj.modifiers.new(name, "NODES").node_group = tree
    return obj


def grid_points(count, extent):
    side = math.ceil(math.sqrt(count))
    u = np.linspace(-extent, extent, side)
    x, z = np.meshgrid(u, u)
    return np.stack([x.ravel(), np.zeros(side * side), z.ravel()], axis=-1)[:count]


def test_ten_thousand_instances_share_one_mesh(scene, render_pixels, warnings):
    count = 10_000
    scatter(scene, grid_points(count, 1.8))
    exported = exported_meshes(bpy.context.evaluated_depsgraph_get(), warnings)
    assert len(exported.meshes) == 1
    assert len(exported.instances) == count
    assert len({i.name for i in exported.instances}) == count
    assert {i.mesh for i in exported.instances} == {exported.meshes[0].name}
    add_sun(scene, FROM_CAMERA)
    scene.render.resolution_x = scene.render.resolution_y = 100
    pixels = render_pixels(scene)
    # Spheres of radius 0.015 every 0.036 (a pixel is 0.04 wide): about half the
    # pixels inside the grid catch one.
    assert (pixels[..., 0] > 0.0).sum() > 1000


# --- Animation -----------------------------------------------------------------


def keyframed_cube(scene):
    cube = link(scene, "Cube", cube_mesh(size=0.5))
    for frame, x in ((1, -1.0), (10, 1.0)):
        cube.location = (x, 0.0, 0.0)
        cube.keyframe_insert("location", index=0, frame=frame)
    add_sun(scene, FROM_CAMERA)
    return cube


def center_column(pixels):
    columns = np.nonzero(pixels[..., 0].max(axis=0) > 0.0)[0]  # the lit cube
    return columns.mean()


def test_each_frame_renders_its_own_state(scene, render_pixels):
    keyframed_cube(scene)
    scene.frame_set(1)
    first = center_column(render_pixels(scene))
    scene.frame_set(10)
    last = center_column(render_pixels(scene))
    assert first == pytest.approx(pixel(-1.0, 0.0)[1], abs=1.0)
    assert last == pytest.approx(pixel(1.0, 0.0)[1], abs=1.0)


def animation_files(directory):
    return sorted(name for name in os.listdir(directory) if name.startswith("frame_"))


def set_up_animation(scene, directory):
    keyframed_cube(scene)
    scene.render.engine = "WHITTED"
    scene.render.resolution_x = scene.render.resolution_y = 8
    scene.frame_start, scene.frame_end = 1, 2
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = str(directory / "frame_####")


def test_animation_render_writes_every_frame(scene, tmp_path):
    set_up_animation(scene, tmp_path)
    bpy.ops.render.render(animation=True)
    assert animation_files(tmp_path) == ["frame_0001.png", "frame_0002.png"]


def test_command_line_animation_writes_every_frame(scene, tmp_path):
    # `blender -b scene.blend -E WHITTED -a`, as on a render farm. Only the Blender
    # program can run it; as a Python module, Blender has no command line.
    if not bpy.app.binary_path or not os.path.basename(bpy.app.binary_path).startswith("blender"):
        pytest.skip("Blender as a Python module has no command line; the 3.4 target runs this")
    output = tmp_path / "out"
    output.mkdir()
    set_up_animation(scene, output)
    blend = tmp_path / "animation.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    command = [
        bpy.app.binary_path,
        *("-b", "--factory-startup", "--addons", "whitted", str(blend)),
        *("-E", "WHITTED", "-a"),
    ]
    subprocess.run(command, check=True, capture_output=True, timeout=120)
    assert animation_files(output) == ["frame_0001.png", "frame_0002.png"]


# --- Render border ---------------------------------------------------------------

# (min_x, max_x, min_y, max_y) as fractions; 32 pixels: columns 8..24, rows 11..30.
BORDER = (0.25, 0.75, 0.35, 0.95)
BORDER_PIXELS = (slice(11, 30), slice(8, 24))  # rows, columns


def set_border(scene, crop):
    render = scene.render
    render.use_border = True
    render.border_min_x, render.border_max_x, render.border_min_y, render.border_max_y = BORDER
    render.use_crop_to_border = crop


def test_film_region_is_the_border_in_pixels_as_blender_rounds_it(scene):
    render = scene.render
    scene.whitted.pixel_filter_type = "GAUSSIAN"
    scene.whitted.filter_width = 2.0
    gaussian = PixelFilter("GAUSSIAN", 2.0)
    assert convert_film(scene, 100, 50) == FilmData(
        region=(0, 0, 100, 50), transparent_background=False, pixel_filter=gaussian
    )
    render.use_border = True
    # 0.7 in single precision is 0.69999999; times 100 in single precision is
    # 70.0, where double precision would give 69.999999 and truncate to 69.
    render.border_min_x, render.border_max_x = 0.2, 0.7
    render.border_min_y, render.border_max_y = 0.1, 0.9
    render.film_transparent = True
    assert convert_film(scene, 100, 50) == FilmData(
        region=(20, 5, 70, 45), transparent_background=True, pixel_filter=gaussian
    )


def test_border_renders_only_its_region(stage, render_pixels):
    set_border(stage, crop=False)
    pixels = render_pixels(stage)
    assert pixels.shape == (SIZE, SIZE, 4)
    inside = np.zeros((SIZE, SIZE), dtype=bool)
    inside[BORDER_PIXELS] = True
    assert np.all(pixels[~inside] == 0.0)
    assert np.all(pixels[inside][:, 3] == 1.0)  # every traced pixel is opaque
    assert pixels[inside][:, 0].max() > 0.5 * LIT


def test_cropped_border_is_the_region_of_the_full_render(stage, render_pixels):
    full = render_pixels(stage)
    set_border(stage, crop=True)
    cropped = render_pixels(stage)
    rows, columns = BORDER_PIXELS
    assert cropped.shape == (rows.stop - rows.start, columns.stop - columns.start, 4)
    np.testing.assert_array_equal(cropped, full[BORDER_PIXELS])
