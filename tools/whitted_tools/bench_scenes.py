"""The benchmark scenes, built with bpy (Blender 3.4 and 5.0): the performance suite's
(whitted_tools perf-scenes, bench_performance.py, bench_memory.py, bench_viewport.py),
and the cost report's (whitted_tools cost-scenes, accuracy_cost.py).

    demo       the demo scene (whitted_tools.demo_scene)
    million    the demo's layout with about `triangles` (default 1,000,000) triangles:
               high-resolution glass and mirror spheres, a glass torus and a gold torus
    instances  `instances` (default 10,000) ico spheres of 20,480 triangles (fewer with
               `ico_subdivisions`) scattered by geometry nodes over a mirror floor
    glass8     overlapping glass spheres and slabs, max depth 8
    triangles  one torus of about `triangles` triangles (1k..10M) beside a mirror quad
               on a one-quad floor: the triangle-count scaling curve
    fur        a furry character on the demo's stage: a ball with `parents` (default
               5,000) particle hairs of 20 children each, 100,000 strands of 9 keys
    glass      (cost report) a 3 x 3 grid of glass spheres and a glass slab over the
               demo's checkerboard, lit by a sphere light (soft shadows): deep refraction
    diffuse    (cost report) matte spheres on an image-textured floor under an area
               light and a sun with an angle: soft shadows, textures, no mirrors

configure() gives every performance scene the same explicit settings: Whitted REGULAR
2x2 anti-aliasing, max depth 5 (glass8: 8), the default cutoff; Cycles on the CPU with
64 samples, no adaptive sampling and no denoising (default bounces); render threads at
Blender's default; the Standard view transform.
"""

import math

import bpy

# isort: split
# Blender as a Python module makes bmesh importable only after bpy.
import bmesh
import numpy as np

from whitted_tools import demo_scene
from whitted_tools.camera_scenes import linear_keys
from whitted_tools.hair_scenes import grow_fur
from whitted_tools.scenes import (
    SPECULAR,
    TRANSMISSION,
    add_object,
    bmesh_mesh,
    cube_mesh,
    facing,
    ico_sphere_on_points,
    mesh_from_faces,
    principled_material,
)

DEFAULT_MAX_DEPTH = 5
GLASS8_MAX_DEPTH = 8
CYCLES_SAMPLES = 64
MILLION_TRIANGLES = 1_000_000
INSTANCES = 10_000
ICO_SUBDIVISIONS = 6  # 20 * 4^(6 - 1) = 20,480 triangles (subdivision 1 is the icosahedron)
# The demo objects a derived scene replaces.
DEMO_OBJECTS = ("Glass Sphere", "Mirror Sphere", "Cube", "Cylinder")
GLASS_IORS = (1.2, 1.33, 1.5, 1.33, 1.5, 1.8, 1.5, 1.8, 2.4)
TEXTURE_SIZE = 64  # pixels per side of the cost report's floor image
FUR_PARENTS = 5_000
FUR_CHILDREN = 20


# --- the performance suite ---------------------------------------------------------


def _grid_quads(rows, columns, wrap_columns):
    """int[K,4] quads over a rows x columns vertex grid (index r * columns + c), with
    the last column joined to the first when wrap_columns."""
    spans = columns if wrap_columns else columns - 1
    r, c = np.meshgrid(np.arange(rows - 1), np.arange(spans), indexing="ij")
    c1 = (c + 1) % columns
    return np.stack(
        [r * columns + c, (r + 1) * columns + c, (r + 1) * columns + c1, r * columns + c1],
        axis=-1,
    ).reshape(-1, 4)


def torus_mesh(name, major, minor, triangles):
    """A smooth torus about Z of about `triangles` triangles (quads, two each)."""
    quads = max(triangles // 2, 12)
    around_tube = max(round(math.sqrt(quads / 4.0)), 3)
    around_axis = max(quads // around_tube, 3)
    theta = np.linspace(0.0, 2.0 * math.pi, around_axis, endpoint=False)[:, None]
    phi = np.linspace(0.0, 2.0 * math.pi, around_tube, endpoint=False)[None, :]
    ring = major + minor * np.cos(phi)
    positions = np.stack(
        np.broadcast_arrays(ring * np.cos(theta), ring * np.sin(theta), minor * np.sin(phi)),
        axis=-1,
    ).reshape(-1, 3)
    # Rows go around the axis (wrapped by hand: the last row joins the first).
    faces = _grid_quads(around_axis + 1, around_tube, wrap_columns=True)
    faces %= around_axis * around_tube
    return mesh_from_faces(name, positions, [faces])


def dense_sphere_mesh(name, radius, triangles):
    """A smooth UV sphere of about `triangles` triangles: quads between the rings,
    triangle fans at the poles."""
    segments = max(round(math.sqrt(triangles)), 3)
    rings = max(triangles // (2 * segments) + 1, 3)
    polar = np.linspace(0.0, math.pi, rings + 1)[1:-1, None]  # without the poles
    azimuth = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)[None, :]
    body = np.stack(
        np.broadcast_arrays(
            np.sin(polar) * np.cos(azimuth), np.sin(polar) * np.sin(azimuth), np.cos(polar)
        ),
        axis=-1,
    ).reshape(-1, 3)
    positions = radius * np.concatenate([body, [(0.0, 0.0, 1.0), (0.0, 0.0, -1.0)]])
    north, south = len(body), len(body) + 1
    # Rows run from the north pole down, columns east: (row, col), (row+1, col), ...
    # turns counter-clockwise seen from outside.
    quads = _grid_quads(rings - 1, segments, wrap_columns=True)
    column = np.arange(segments)
    top = np.stack([np.full(segments, north), column, (column + 1) % segments], axis=-1)
    last = (rings - 2) * segments
    bottom = np.stack(
        [np.full(segments, south), last + (column + 1) % segments, last + column], axis=-1
    )
    return mesh_from_faces(name, positions, [quads, top, bottom])


def quad_mesh(name, corners):
    """One flat quad from four corners, counter-clockwise seen from its front."""
    return mesh_from_faces(name, np.asarray(corners), [np.arange(4)[None, :]], smooth=False)


def floor_mesh(name, half):
    """A square in the XY plane, 2 * half on a side, facing +Z."""
    return quad_mesh(name, [(-half, -half, 0), (half, -half, 0), (half, half, 0), (-half, half, 0)])


def wall_mesh(name, half, height):
    """An upright rectangle in the XZ plane, 2 * half wide, facing -Y (the cameras)."""
    return quad_mesh(name, [(-half, 0, 0), (half, 0, 0), (half, 0, height), (-half, 0, height)])


def _add(scene, name, mesh, location, material, rotation=(0.0, 0.0, 0.0)):
    obj = add_object(scene, name, mesh, location)
    obj.rotation_euler = rotation
    mesh.materials.append(material)
    return obj


def _demo_without_objects(scene, extra=()):
    """The demo's floor, lights, camera and world, without its objects."""
    demo_scene.build_demo_scene(scene)
    for name in (*DEMO_OBJECTS, *extra):
        bpy.data.objects.remove(bpy.data.objects[name])
    return scene


def build_demo(scene, args):
    """The demo scene as scripts/demo.sh renders it."""
    del args
    return demo_scene.build_demo_scene(scene)


def build_fur(scene, args):
    """The demo's stage with a furry ball: args.parents hairs (FUR_PARENTS) of
    FUR_CHILDREN children each."""
    _demo_without_objects(scene)
    ball = _add(
        scene,
        "Furry Ball",
        dense_sphere_mesh("Furry Ball", 1.0, 20_000),
        (0.0, 0.0, 1.0),
        principled_material("Skin", (0.5, 0.3, 0.2), {}),
    )
    ball.data.materials.append(principled_material("Fur", (0.8, 0.6, 0.3), {}))
    grow_fur(ball, args.parents or FUR_PARENTS, FUR_CHILDREN, length=0.3, radius_scale=0.01)
    return scene


def build_million(scene, args):
    """The demo's layout with about args.triangles triangles of glass and mirrors."""
    total = args.triangles or MILLION_TRIANGLES
    demo_scene.build_demo_scene(scene)
    for name in ("Glass Sphere", "Mirror Sphere"):
        bpy.data.objects.remove(bpy.data.objects[name])
    share = total // 4
    _add(
        scene,
        "Glass Sphere",
        dense_sphere_mesh("Glass Sphere", demo_scene.GLASS_RADIUS, share),
        demo_scene.GLASS_CENTER,
        glass_material("Glass", 1.5),
    )
    _add(
        scene,
        "Mirror Sphere",
        dense_sphere_mesh("Mirror Sphere", demo_scene.MIRROR_RADIUS, share),
        demo_scene.MIRROR_CENTER,
        demo_scene.mirror_material("Mirror"),
    )
    _add(
        scene,
        "Glass Torus",
        torus_mesh("Glass Torus", 0.8, 0.3, share),
        (-3.0, -2.6, 1.1),
        glass_material("Torus Glass", 1.45),
        rotation=(math.radians(75.0), 0.0, math.radians(-20.0)),
    )
    _add(
        scene,
        "Gold Torus",
        torus_mesh("Gold Torus", 0.9, 0.3, share),
        (3.4, 2.4, 1.2),
        demo_scene.mirror_material("Gold", (1.0, 0.75, 0.3)),
        rotation=(math.radians(90.0), 0.0, math.radians(10.0)),
    )
    return scene


def build_instances(scene, args):
    """args.instances ico spheres scattered by geometry nodes, over a mirror floor,
    seen in perspective."""
    count = args.instances or INSTANCES
    build_instance_grid(scene, count, max(args.resolution))
    if args.ico_subdivisions:
        scatter = bpy.data.objects["Scatter"].modifiers["Scatter"].node_group
        ico = next(n for n in scatter.nodes if n.bl_idname == "GeometryNodeMeshIcoSphere")
        ico.inputs["Subdivisions"].default_value = args.ico_subdivisions
    side = math.ceil(math.sqrt(count))
    half = side / 2.0 + 1.0
    floor = floor_mesh("Floor", half)
    _add(
        scene,
        "Mirror Floor",
        floor,
        (0.0, 0.0, -0.45),
        demo_scene.mirror_material("Mirror Floor", (0.35, 0.35, 0.4)),
    )
    camera = scene.camera
    camera.data.type = "PERSP"
    camera.data.lens = 30.0
    # Low over one edge of the grid: the near spheres large, the far ones receding.
    camera.location = (0.0, -0.6 * side, 0.25 * side)
    camera.rotation_euler = facing((0.0, 0.6 * side, -0.3 * side))
    bpy.data.lights["Sun"].angle = 0.0  # hard shadows, as in the other scenes
    scene.world = demo_scene.sky_world()
    return scene


def build_glass8(scene, args):
    """A grid of overlapping glass spheres crossed by glass slabs, before a mirror."""
    del args
    _demo_without_objects(scene)
    iors = GLASS_IORS
    index = 0
    for row in range(3):
        for column in range(4):
            ior = iors[index % len(iors)]
            _add(
                scene,
                f"Glass {index}",
                demo_scene.demo_sphere_mesh(0.75),
                (-1.8 + 1.2 * column, -1.2 + 1.2 * row, 0.75 + 0.1 * (index % 3)),
                glass_material(f"Glass {index} ({ior})", ior),
            )
            index += 1
    for slab_index, (location, scale, angle) in enumerate(
        (
            ((0.0, -2.4, 1.0), (4.2, 0.25, 2.0), 10.0),
            ((-0.6, 0.0, 1.6), (0.25, 3.6, 1.2), -15.0),
        )
    ):
        slab = _add(
            scene,
            f"Slab {slab_index}",
            cube_mesh("Cube", 1.0),
            location,
            glass_material(f"Slab Glass {slab_index}", 1.5),
            rotation=(0.0, 0.0, math.radians(angle)),
        )
        slab.scale = scale
    _add(
        scene,
        "Mirror",
        wall_mesh("Mirror", 4.0, 4.0),
        (0.0, 2.8, 0.0),
        demo_scene.mirror_material("Mirror"),
    )
    return scene


def build_triangles(scene, args):
    """A torus of about args.triangles triangles, a mirror quad and a one-quad floor:
    four triangles besides the torus, so the count is the torus's."""
    total = args.triangles or MILLION_TRIANGLES
    _demo_without_objects(scene, extra=("Floor",))
    half = demo_scene.FLOOR_CELLS / 2
    _add(
        scene,
        "Floor",
        floor_mesh("Floor", half),
        (0.0, 0.0, 0.0),
        principled_material("Floor", (0.6, 0.6, 0.6), {SPECULAR: 0.0}),
    )
    _add(
        scene,
        "Mirror",
        wall_mesh("Mirror", 3.0, 4.0),
        (0.0, 2.5, 0.0),
        demo_scene.mirror_material("Mirror"),
        rotation=(0.0, 0.0, math.radians(-15.0)),
    )
    _add(
        scene,
        "Torus",
        torus_mesh("Torus", 1.6, 0.6, max(total - 4, 12)),
        (0.0, 0.0, 1.9),
        principled_material("Torus", (0.1, 0.25, 0.8), {("Roughness",): 0.3}),
        rotation=(math.radians(70.0), 0.0, 0.0),
    )
    return scene


def configure(scene, resolution, depth):
    """The settings every scene of the suite shares (module docstring)."""
    render = scene.render
    render.engine = "WHITTED"
    render.resolution_x, render.resolution_y = resolution
    render.resolution_percentage = 100
    render.threads_mode = "AUTO"
    render.image_settings.file_format = "PNG"
    scene.view_settings.view_transform = "Standard"
    whitted = scene.whitted
    whitted.aa_mode = "REGULAR"
    whitted.aa_samples = 2
    whitted.max_depth = depth
    whitted.property_unset("cutoff")
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = CYCLES_SAMPLES
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False


def mesh_triangles(scene):
    """Triangles of the distinct evaluated meshes (each shared mesh once), as
    Whitted's exporter sees them."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    counts = {}
    for instance in depsgraph.object_instances:
        obj = instance.object
        if obj.type == "MESH" and instance.show_self and not obj.original.hide_render:
            mesh = obj.data
            # An n-gon is n - 2 triangles.
            counts[mesh.as_pointer()] = len(mesh.loops) - 2 * len(mesh.polygons)
    return sum(counts.values())


# --- the cost report -----------------------------------------------------------------


def build_glass_scene(scene):
    collection = scene.collection
    demo_scene.build_demo_scene(scene)
    for name in ("Glass Sphere", "Mirror Sphere", "Cube", "Cylinder", "Point Light"):
        bpy.data.objects.remove(bpy.data.objects[name])
    for index, ior in enumerate(GLASS_IORS):
        row, column = divmod(index, 3)
        sphere = add_object(
            collection,
            f"Glass {index}",
            demo_scene.demo_sphere_mesh(0.6),
            (-2.0 + 2.0 * column, -1.5 + 2.0 * row, 0.6),
        )
        sphere.data.materials.append(glass_material(f"Glass {ior}", ior))
    slab = add_object(collection, "Slab", cube_mesh("Cube", 1.0), (0.0, -3.6, 0.9))
    slab.scale = (4.0, 0.3, 1.8)
    slab.data.materials.append(glass_material("Slab Glass", 1.5))
    light = bpy.data.lights.new("Sphere Light", "POINT")
    light.energy = 2500.0
    light.shadow_soft_size = 0.5
    add_object(collection, "Sphere Light", light, (-2.5, 3.5, 6.0))
    return scene


def build_diffuse_scene(scene):
    collection = scene.collection
    demo_scene.build_demo_scene(scene)
    for name in ("Glass Sphere", "Mirror Sphere", "Point Light", "Floor"):
        bpy.data.objects.remove(bpy.data.objects[name])
    floor = add_object(collection, "Floor", _uv_floor())
    floor.data.materials.append(_textured("Floor", _floor_image()))
    for index, (x, y, color) in enumerate(
        ((-1.0, -1.0, (0.8, 0.3, 0.1)), (1.2, 0.8, (0.2, 0.7, 0.3)), (-1.6, 1.6, (0.7, 0.7, 0.7)))
    ):
        sphere = add_object(
            collection, f"Ball {index}", demo_scene.demo_sphere_mesh(0.8), (x, y, 0.8)
        )
        sphere.data.materials.append(principled_material(f"Matte {index}", color, {SPECULAR: 0.0}))
    area = bpy.data.lights.new("Area Light", "AREA")
    area.energy = 1500.0
    area.size = 2.5
    area_object = add_object(collection, "Area Light", area, (-2.0, 1.0, 5.0))
    area_object.rotation_euler = facing((0.3, -0.1, -1.0))
    sun = bpy.data.lights["Sun"]
    sun.angle = math.radians(8.0)
    return scene


def build_distributed_scene(scene):
    """The diffuse scene's floor and sun, its area light replaced by an emissive panel,
    its matte balls by a rough gold metal, a rough plastic and a frosted glass ball:
    glossy rays, rough refraction and emitter feelers (MIS) where a scene calls for
    them (issue 29)."""
    from whitted_tools.material_scenes import emission_material, emissive_panel

    build_diffuse_scene(scene)
    bpy.data.objects.remove(bpy.data.objects["Area Light"])
    looks = (
        ("Rough Gold", (1.0, 0.78, 0.34), {("Metallic",): 1.0, ("Roughness",): 0.35}),
        ("Rough Plastic", (0.1, 0.1, 0.5), {("Roughness",): 0.3}),
        ("Frosted", (1.0, 1.0, 1.0), {TRANSMISSION: 1.0, ("IOR",): 1.5, ("Roughness",): 0.2}),
    )
    for index, (name, colour, inputs) in enumerate(looks):
        ball = bpy.data.objects[f"Ball {index}"]
        ball.data.materials[0] = principled_material(name, colour, inputs)
    panel = emissive_panel("Panel", (-1.0, 0.5, 3.5), 2.0, emission_material("Panel Glow", 8.0))
    # Out of the camera's sight, as a light panel often is: seen edge-on its radiance of
    # 8 would make a few pixels' sampling the whole error against the reference.
    panel.visible_camera = False
    return scene


def build_camera_scene(scene):
    """The diffuse scene through a lens focused on its green ball at f/1.4, its orange
    ball moving 0.6 m along X within Render > Motion Blur's shutter (half a frame
    around frame 1): depth of field and motion blur, the camera's samples spread over
    the lens and the shutter (issue 30)."""
    build_diffuse_scene(scene)
    camera = scene.camera.data
    camera.dof.use_dof = True
    camera.dof.aperture_fstop = 1.4
    camera.dof.focus_object = bpy.data.objects["Ball 1"]
    ball = bpy.data.objects["Ball 0"]
    start = ball.location.copy()
    for frame, shift in ((0, 0.0), (2, 2.4)):
        ball.location = (start.x + shift, start.y, start.z)
        ball.keyframe_insert("location", frame=frame)
    linear_keys(ball)
    scene.frame_set(1)
    scene.render.use_motion_blur = True
    return scene


def glass_material(name, ior):
    return principled_material(
        name,
        (1.0, 1.0, 1.0),
        {TRANSMISSION: 1.0, ("IOR",): ior, ("Roughness",): 0.0},
    )


def _uv_floor():
    half = demo_scene.FLOOR_CELLS / 2

    def build(bm):
        bm.loops.layers.uv.new("UVMap")  # calc_uvs fills an existing UV layer
        bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=half, calc_uvs=True)

    return bmesh_mesh("Floor", build, smooth=False)


def _floor_image():
    # Tiles with a thin grout, so closest and linear sampling differ visibly.
    image = bpy.data.images.new("Floor Tiles", TEXTURE_SIZE, TEXTURE_SIZE)
    pixels = []
    for y in range(TEXTURE_SIZE):
        for x in range(TEXTURE_SIZE):
            grout = x % 16 == 0 or y % 16 == 0
            tile = (x // 16 + y // 16) % 2
            value = 0.1 if grout else (0.75 if tile else 0.45)
            pixels += [value, value * 0.9, value * 0.8, 1.0]
    image.pixels.foreach_set(pixels)
    image.pack()
    return image


def _textured(name, image):
    material = principled_material(name, (0.8, 0.8, 0.8), {SPECULAR: 0.0})
    nodes = material.node_tree.nodes
    principled = next(n for n in nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    texture = nodes.new("ShaderNodeTexImage")
    texture.image = image
    texture.interpolation = "Linear"
    material.node_tree.links.new(texture.outputs["Color"], principled.inputs["Base Color"])
    return material


# --- many instances of one mesh ------------------------------------------------------


def build_instance_grid(scene, count, resolution):
    """`count` ico spheres on a square grid of points by geometry nodes, an orthographic
    camera above, a sun: every instance shares the one mesh (build_instances' start)."""
    side = math.ceil(math.sqrt(count))
    spacing = 1.0
    u = (np.arange(side) - (side - 1) / 2.0) * spacing
    x, y = np.meshgrid(u, u)
    points = np.stack([x.ravel(), y.ravel(), np.zeros(side * side)], axis=-1)[:count]

    mesh = bpy.data.meshes.new("Points")
    mesh.vertices.add(count)
    mesh.vertices.foreach_set("co", points.astype(np.float32).reshape(-1))
    scatter = bpy.data.objects.new("Scatter", mesh)
    scene.collection.objects.link(scatter)
    tree = ico_sphere_on_points("Scatter", radius=0.4, subdivisions=ICO_SUBDIVISIONS)
    scatter.modifiers.new("Scatter", "NODES").node_group = tree

    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = side * spacing + 1.0
    camera.location = (0.0, 0.0, 10.0)
    scene.collection.objects.link(camera)
    scene.camera = camera
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
    sun.rotation_euler = (0.5, 0.3, 0.0)
    scene.collection.objects.link(sun)

    scene.render.engine = "WHITTED"
    scene.render.resolution_x = scene.render.resolution_y = resolution
    scene.render.resolution_percentage = 100
    scene.whitted.aa_samples = 1
