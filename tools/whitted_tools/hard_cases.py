"""Scenes of the classic hard cases of ray tracing (issue 4), built with bpy.

Shared by tests/blender/test_robustness.py (small images with assertions) and
whitted_tools robustness-images (the pictures of docs/ROBUSTNESS.md). Every builder
takes an empty scene (bpy.ops.wm.read_factory_settings(use_empty=True)), fills
it, and returns it; the image size is the caller's. Materials use the Whitted
material override, so each surface has exactly the parameters named here.
"""

import math

import bpy

# isort: split
# Blender as a Python module makes bmesh importable only after bpy.
import bmesh
import numpy as np
from mathutils import Vector

from whitted_tools.scenes import add_object, bmesh_mesh, cube_mesh, sphere_mesh

FLOOR_COLOR = (0.1, 0.6, 0.1)  # green: the floor is told apart by its hue
SKY = (0.02, 0.03, 0.05)  # background radiance, and the ambient light Ia
SUN_STRENGTH = 3.0  # W/m^2
POINT_POWER = 1000.0  # W at scene scale 1
GLASS_IOR = 1.5
WATER_IOR = 1.33


# --- building blocks --------------------------------------------------------------


def cylinder_mesh(name, segments, radius, depth, smooth=False):
    def build(bm):
        bmesh.ops.create_cone(
            bm,
            cap_ends=True,
            segments=segments,
            radius1=radius,
            radius2=radius,
            depth=depth,
        )

    return bmesh_mesh(name, build, smooth)


def quad_mesh(name, half_size, z=0.0, facing_up=True):
    """A square in the plane z, facing +Z (or -Z when not `facing_up`)."""
    h = half_size
    corners = [(-h, -h, z), (h, -h, z), (h, h, z), (-h, h, z)]
    face = (0, 1, 2, 3) if facing_up else (3, 2, 1, 0)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(corners, [], [face])
    return mesh


def material(
    name,
    diffuse=(0.0, 0.0, 0.0),
    specular=0.0,
    shininess=50.0,
    reflectivity=(0.0, 0.0, 0.0),
    transmissivity=(0.0, 0.0, 0.0),
    ior=GLASS_IOR,
):
    """A material with the Whitted override on: exactly these parameters."""
    mat = bpy.data.materials.new(name)
    settings = mat.whitted
    settings.use_override = True
    weight = max(diffuse)
    settings.diffuse_weight = weight
    settings.diffuse_color = [c / weight for c in diffuse] if weight > 0.0 else (1.0, 1.0, 1.0)
    settings.specular_weight = specular
    settings.specular_color = (1.0, 1.0, 1.0)
    settings.shininess = shininess
    settings.ambient = 1.0
    settings.reflectivity = reflectivity
    settings.transmissivity = transmissivity
    settings.ior = ior
    return mat


def glass(name="Glass", ior=GLASS_IOR):
    return material(name, transmissivity=(1.0, 1.0, 1.0), ior=ior)


def assign(obj, mat):
    obj.data.materials.clear()
    obj.data.materials.append(mat)
    return obj


def camera(scene, location, target, lens=35.0, clip=(0.1, 100.0)):
    data = bpy.data.cameras.new("Camera")
    data.lens = lens
    data.clip_start, data.clip_end = clip
    obj = add_object(scene, "Camera", data, location=location)
    direction = Vector(target) - Vector(location)
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.camera = obj
    return obj


def sun(scene, elevation_degrees, azimuth_degrees=30.0, strength=SUN_STRENGTH):
    """A sun shining down at `elevation_degrees` above the horizon."""
    data = bpy.data.lights.new("Sun", "SUN")
    data.energy = strength
    data.angle = 0.0
    obj = add_object(scene, "Sun", data)
    # A sun shines along its local -Z: tilt it from straight down towards the horizon.
    obj.rotation_euler = (
        math.radians(90.0 - elevation_degrees),
        0.0,
        math.radians(azimuth_degrees),
    )
    return obj


def point_light(scene, location, power):
    data = bpy.data.lights.new("Point", "POINT")
    data.energy = power
    data.shadow_soft_size = 0.0
    return add_object(scene, "Point", data, location=location)


def world(scene, color=SKY):
    """A uniform sky of radiance `color` (Blender 5.0 gives new worlds nodes)."""
    scene.world = bpy.data.worlds.new("World")
    scene.world.color = color
    if scene.world.node_tree is not None:
        scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (*color, 1.0)


def settings(scene, max_depth=8, aa_samples=1, fresnel="EXACT", tile_size=32):
    scene.whitted.max_depth = max_depth
    scene.whitted.aa_samples = aa_samples
    scene.whitted.fresnel = fresnel
    scene.whitted.tile_size = tile_size
    return scene


def floor(scene, half_size, scale=1.0):
    obj = add_object(scene, "Floor", quad_mesh("Floor", half_size), scale=scale)
    return assign(obj, material("FloorMaterial", diffuse=FLOOR_COLOR))


# --- the hard cases ---------------------------------------------------------------


def acne(scene, scale=1.0):
    """A lit floor with a smooth low-poly sphere, a flat sphere and a cube, all at
    `scale`: positions, sizes and the camera's clip range times `scale`, the point
    light's power times scale^2 (so its irradiance is the same), the sun unchanged.
    Rendered at any scale the image should be the same."""
    world(scene)
    floor(scene, 8.0, scale)
    red = material("Red", diffuse=(0.7, 0.1, 0.1), specular=0.3)
    blue = material("Blue", diffuse=(0.1, 0.1, 0.7), specular=0.3)

    def at(x, y, z):
        return (x * scale, y * scale, z * scale)

    ball = add_object(scene, "Ball", sphere_mesh("Ball", 12, 6), at(0.0, 0.0, 1.0), scale)
    assign(ball, red)
    faceted = add_object(
        scene, "Faceted", sphere_mesh("Faceted", smooth=False), at(-2.5, 1, 1), scale
    )
    assign(faceted, blue)
    cube = add_object(scene, "Cube", cube_mesh("Cube", 1.5), at(2.5, 1.0, 0.75), scale)
    cube.rotation_euler = (0.0, 0.0, 0.5)
    assign(cube, blue)
    sun(scene, 50.0)
    point_light(scene, at(4.0, -4.0, 6.0), POINT_POWER * scale * scale)
    camera(scene, at(0.0, -11.0, 5.0), at(0.0, 0.0, 0.5), clip=(0.1 * scale, 100.0 * scale))
    return settings(scene, max_depth=2)


def grazing(scene):
    """Camera and sun both 3 degrees above a large floor: every floor point is
    seen and lit at a grazing angle. A sun gives a flat floor the same radiance
    everywhere, so any dark speck is self-shadowing (acne). The sun shines from
    behind the camera: the block's long shadow falls out of sight behind it."""
    world(scene)
    floor(scene, 500.0)
    block = add_object(scene, "Block", cube_mesh("Block", 2.0), (0.0, 60.0, 1.0))
    assign(block, material("Red", diffuse=(0.7, 0.1, 0.1)))
    sun(scene, 3.0, azimuth_degrees=10.0, strength=20.0)
    elevation = math.radians(3.0)
    camera(scene, (0.0, -5.0, 1.0), (0.0, 1.0 / math.tan(elevation) - 5.0, 0.0), clip=(0.1, 2000))
    return settings(scene, max_depth=1)


def _checker_wall(scene, y):
    """A wall of coloured stripes behind the glass, so refraction shows."""
    for i in range(6):
        stripe = bpy.data.meshes.new(f"Stripe{i}")
        x0 = -3.0 + i
        stripe.from_pydata(
            [(x0, y, -1.0), (x0 + 1.0, y, -1.0), (x0 + 1.0, y, 4.0), (x0, y, 4.0)],
            [],
            [(3, 2, 1, 0)],
        )
        color = ((0.8, 0.2, 0.1), (0.9, 0.9, 0.2))[i % 2]
        assign(add_object(scene, f"Stripe{i}", stripe), material(f"Stripe{i}", diffuse=color))


def total_internal_reflection(scene):
    """A triangular glass prism (IOR 1.5) in front of a striped wall, seen along
    its axis at an angle: rays inside meet its faces beyond the critical angle."""
    world(scene)
    floor(scene, 10.0)
    _checker_wall(scene, 3.0)
    prism = add_object(scene, "Prism", cylinder_mesh("Prism", 3, 1.0, 2.5), (0.0, 0.0, 1.0))
    prism.rotation_euler = (math.radians(90.0), 0.0, math.radians(20.0))
    assign(prism, glass())
    sun(scene, 60.0, azimuth_degrees=20.0)
    camera(scene, (1.5, -6.0, 2.5), (0.0, 0.0, 1.0))
    return settings(scene, max_depth=12)


def water_in_glass(scene):
    """Water (IOR 1.33) in a glass (IOR 1.5): a solid glass cylinder and a water
    cylinder that overlaps its top, as artists model liquids (the liquid's wall
    inside the glass's, its surface above the rim)."""
    world(scene)
    floor(scene, 10.0)
    _checker_wall(scene, 3.0)
    cup = add_object(scene, "Glass", cylinder_mesh("Glass", 32, 1.0, 2.0, smooth=True), (0, 0, 1.0))
    assign(cup, glass("GlassMaterial"))
    water = add_object(
        scene, "Water", cylinder_mesh("Water", 32, 0.8, 2.0, smooth=True), (0, 0, 1.4)
    )
    assign(water, glass("WaterMaterial", ior=WATER_IOR))
    sun(scene, 60.0, azimuth_degrees=20.0)
    camera(scene, (0.0, -7.0, 3.0), (0.0, 0.0, 1.0))
    return settings(scene, max_depth=12)


def overlapping_spheres(scene, merged=False):
    """Two overlapping glass spheres of one material (`merged`: their union, one
    closed mesh, made by Blender's exact Boolean). Inside the overlap a ray is in
    the same glass whichever surface it crosses: no interface may show."""
    world(scene)
    floor(scene, 10.0)
    _checker_wall(scene, 3.0)
    mat = glass()
    left = add_object(scene, "Left", sphere_mesh("Left", 32, 16), (-0.6, 0.0, 1.2))
    right = add_object(scene, "Right", sphere_mesh("Right", 32, 16), (0.6, 0.0, 1.2))
    assign(left, mat)
    assign(right, mat)
    if merged:
        union = left.modifiers.new("Union", "BOOLEAN")
        union.operation = "UNION"
        union.solver = "EXACT"
        union.object = right
        right.hide_render = True
    sun(scene, 60.0, azimuth_degrees=20.0)
    camera(scene, (0.0, -7.0, 2.0), (0.0, 0.0, 1.2))
    return settings(scene, max_depth=12)


def camera_inside_glass(scene, ior=GLASS_IOR, sphere=True, inner_ball=False, offset=0.0):
    """The camera inside a big smooth glass sphere (radius 4, centred on the
    camera unless `offset` moves the camera along x), looking at a lit floor and
    stripes outside it. `inner_ball`: a small ball of the same glass in view,
    inside the big sphere, which a ray that starts in that glass must not see."""
    world(scene)
    floor(scene, 20.0)
    _checker_wall(scene, 6.0)
    eye = Vector((0.0, -2.0, 2.0))
    mat = glass(ior=ior)
    if sphere:
        big = add_object(scene, "Globe", sphere_mesh("Globe", 96, 48, radius=4.0), eye)
        assign(big, mat)
        big.location.x -= offset
    if inner_ball:
        assign(
            add_object(scene, "Marble", sphere_mesh("Marble", 32, 16, 0.6), (0.3, 0.5, 2.0)), mat
        )
    sun(scene, 60.0, azimuth_degrees=20.0)
    camera(scene, tuple(eye), (0.0, 6.0, 1.0), lens=24.0)
    # The case is about rays that start in glass, not about shadows: the sun's feelers
    # pass the globe tinted by its transmissivity (Glass Shadows: Tinted), so the floor
    # outside stays lit, and an index-1 globe changes nothing at all.
    scene.whitted.glass_shadows = "TINTED"
    # Nor about the sky's light: feelers to the world would be drawn one bounce deeper
    # behind the globe's surface (other draws, other noise), so the sky lights nothing.
    scene.world.cycles_visibility.diffuse = False
    return settings(scene, max_depth=12, fresnel="OFF")


def degenerate_geometry(scene):
    """Bad meshes in front of a lit backdrop: see `broken_mesh` and the objects
    named Flipped (reversed faces), NonManifold (three faces on one edge) and
    Mirrored (negative scale)."""
    world(scene)
    floor(scene, 10.0)
    grey = material("Grey", diffuse=(0.6, 0.6, 0.6), specular=0.2)
    assign(add_object(scene, "Broken", broken_mesh("Broken")), grey)

    def flipped(bm):
        bmesh.ops.create_uvsphere(bm, u_segments=12, v_segments=6, radius=0.7)
        bmesh.ops.reverse_faces(bm, faces=bm.faces)

    assign(add_object(scene, "Flipped", bmesh_mesh("Flipped", flipped, True), (-2.2, 0, 0.8)), grey)
    fan = bpy.data.meshes.new("NonManifold")
    fan.from_pydata(
        [(0, 0, 0), (0, 0, 1.5), (1, 0, 0.7), (-0.7, 0.7, 0.7), (-0.7, -0.7, 0.7)],
        [],
        [(0, 1, 2), (0, 1, 3), (0, 1, 4)],
    )
    assign(add_object(scene, "NonManifold", fan, (2.2, 0.0, 0.0)), grey)
    mirrored = add_object(scene, "Mirrored", sphere_mesh("Mirrored", 12, 6), (0.0, 1.8, 0.8), 0.6)
    mirrored.scale.x = -0.6
    assign(mirrored, material("GlassMirrored", transmissivity=(0.9, 0.9, 0.9)))
    sun(scene, 50.0)
    camera(scene, (0.0, -7.0, 3.0), (0.0, 0.0, 0.6))
    return settings(scene, max_depth=8)


def broken_mesh(name):
    """A smooth grid of quads (z = 0.5) plus every kind of bad triangle: 2 with
    a NaN vertex, 1 with an infinite one, 1 with a vertex at 2e7, 2 of zero area
    (collinear corners, two corners in one place), and 1 sliver (kept: it is valid)."""
    good = [(x, y, 0.5) for y in (-1.0, 0.0, 1.0) for x in (-1.0, 0.0, 1.0)]
    quads = [(0, 1, 4, 3), (1, 2, 5, 4), (3, 4, 7, 6), (4, 5, 8, 7)]
    extra = [
        (0.0, 0.0, 1.0),  # 9
        (0.5, 0.0, 1.0),  # 10
        (1.0, 0.0, 1.0),  # 11: collinear with 9 and 10
        (0.0, 0.5, 1.0),  # 12
        (0.0, 0.0, 0.0),  # 13: becomes NaN
        (0.0, 0.0, 0.0),  # 14: becomes +Inf
        (2.0e7, 0.0, 0.0),  # 15: too far
        (1.0, 1e-6, 1.0),  # 16: a sliver with 9 and 11
        (0.0, 0.0, 1.0),  # 17: where 9 is
    ]
    triangles = [
        (9, 10, 11),  # zero area: collinear
        (9, 12, 17),  # zero area: two corners in one place
        (13, 9, 12),  # NaN
        (13, 10, 12),  # NaN
        (14, 9, 10),  # Inf
        (15, 9, 12),  # distant
        (9, 11, 16),  # sliver
    ]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(good + extra, [], quads + triangles)
    coordinates = np.array(good + extra, dtype=np.float32)
    coordinates[13] = np.nan
    coordinates[14] = np.inf
    mesh.vertices.foreach_set("co", coordinates.reshape(-1))
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.update()
    return mesh


# Triangles broken_mesh's bad ones count as, per kind (export.mesh.Sanitised).
BROKEN_MESH_COUNTS = {"nonfinite": 3, "distant": 1, "zero_area": 2}


def facing_mirrors(scene, reflectivity=0.9):
    """Two parallel mirrors 4 apart facing each other, a lit ball between, seen
    from between them at an angle: the reflections of reflections go on until
    the weight cutoff (or max depth 256) stops them."""
    world(scene)
    floor(scene, 10.0)
    mirror = material("Mirror", diffuse=(0.02, 0.02, 0.02), reflectivity=(reflectivity,) * 3)
    for name, x, rotation in (("MirrorL", -2.0, 90.0), ("MirrorR", 2.0, -90.0)):
        plane = add_object(scene, name, quad_mesh(name, 3.0), (x, 0.0, 1.5))
        plane.rotation_euler = (0.0, math.radians(rotation), 0.0)
        assign(plane, mirror)
    ball = add_object(scene, "Ball", sphere_mesh("Ball", 24, 12, 0.5), (0.0, 1.0, 0.8))
    assign(ball, material("Red", diffuse=(0.8, 0.1, 0.1), specular=0.3))
    sun(scene, 60.0)
    camera(scene, (0.6, -4.0, 1.6), (-1.5, 1.5, 1.0), lens=28.0)
    return settings(scene, max_depth=256)


def coplanar_quads(scene):
    """Two overlapping coplanar quads, red and blue, in one plane: which one a
    ray hits is a tie that only the tracer's rule decides."""
    world(scene)
    red = add_object(scene, "RedQuad", quad_mesh("RedQuad", 1.0), (-0.4, 0.0, 0.0))
    blue = add_object(scene, "BlueQuad", quad_mesh("BlueQuad", 1.0), (0.4, 0.0, 0.0))
    assign(red, material("Red", diffuse=(0.8, 0.1, 0.1)))
    assign(blue, material("Blue", diffuse=(0.1, 0.1, 0.8)))
    sun(scene, 70.0)
    camera(scene, (0.0, -2.5, 3.5), (0.0, 0.0, 0.0))
    return settings(scene, max_depth=1)


def operator_sphere(scene):
    """A smooth, shiny UV sphere (64 x 32) on a floor, made by Blender's operator, which
    hands over the same faces in a new order each call: its vertex normals, summed
    around each vertex, must not depend on that order."""
    world(scene)
    floor(scene, 10.0)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, location=(0.0, 0.0, 1.0))
    ball = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    assign(ball, material("Shiny", diffuse=(0.6, 0.4, 0.2), specular=0.5, reflectivity=(0.3,) * 3))
    sun(scene, 40.0)
    camera(scene, (0.0, -4.0, 1.4), (0.0, 0.0, 1.0), lens=60.0)
    return settings(scene, max_depth=4)


# --- image measures ---------------------------------------------------------------


def _neighbourhood(image, radius):
    """float[(2r+1)^2, H-2r, W-2r]: every pixel's window, for the interior pixels."""
    height, width = image.shape
    size = 2 * radius + 1
    return np.stack(
        [
            image[dy : height - size + 1 + dy, dx : width - size + 1 + dx]
            for dy in range(size)
            for dx in range(size)
        ]
    )


def is_floor(rgb):
    return rgb[..., 1] > 2.0 * np.maximum(rgb[..., 0], rgb[..., 2])


def lit_floor_region(pixels, lit_fraction=0.25):
    """Mask of the interior pixels (a one-pixel border dropped) in flat lit floor:
    the 3x3 median is floor-coloured and brighter than `lit_fraction` of the
    brightest floor median, and so is every such median in the 5x5 window (so
    shadow and object edges are left out). Acne cannot hide itself: a speck is
    judged by its neighbours' median, not by its own value."""
    green = pixels[..., 1]
    median = np.median(_neighbourhood(green, 1), axis=0)  # H-2 x W-2
    median_rgb = np.stack(
        [np.median(_neighbourhood(pixels[..., c], 1), axis=0) for c in range(3)], axis=-1
    )
    floor_median = is_floor(median_rgb)
    brightest = median[floor_median].max() if floor_median.any() else 0.0
    lit = floor_median & (median > lit_fraction * brightest)
    eroded = np.zeros_like(lit)
    eroded[2:-2, 2:-2] = _neighbourhood(lit, 2).all(axis=0)
    return eroded, median


def acne_share(pixels, threshold=0.1):
    """Share of the flat lit floor's pixels whose green differs from their 3x3
    median by more than `threshold` of it (the issue's acne measure)."""
    region, median = lit_floor_region(pixels)
    green = pixels[1:-1, 1:-1, 1]
    far = np.abs(green - median) > threshold * median
    return float((far & region).sum()) / max(int(region.sum()), 1), int(region.sum())


# Every hard-case scene by name, each a builder(scene): the scenes that checks over all
# of them render (whitted_tools image-hashes, tests/blender/test_waves.py).
SCENES = {
    "acne": acne,
    "grazing": grazing,
    "total internal reflection": total_internal_reflection,
    "water in glass": water_in_glass,
    "overlapping spheres": overlapping_spheres,
    "camera inside glass": camera_inside_glass,
    "degenerate geometry": degenerate_geometry,
    "facing mirrors": facing_mirrors,
    "coplanar quads": coplanar_quads,
}
