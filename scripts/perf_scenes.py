"""The scenes of the performance suite (scripts/bench_performance.py), built with bpy.

    blender -b --factory-startup --python scripts/perf_scenes.py -- --scene NAME \\
        --resolution W H --save OUT.blend [--triangles N] [--depth D] [--instances N] \\
        [--ico-subdivisions N]
    .venv/bin/python scripts/perf_scenes.py --scene NAME ...            (bpy module)

    demo       the demo scene (scripts/demo_scene.py)
    million    the demo's layout with about --triangles (default 1,000,000) triangles:
               high-resolution glass and mirror spheres, a glass torus and a gold torus
    instances  --instances (default 10,000) ico spheres of 20,480 triangles (fewer with
               --ico-subdivisions) scattered by geometry nodes (scripts/bench_instances.py)
               over a mirror floor
    glass8     overlapping glass spheres and slabs, max depth 8
    triangles  one torus of about --triangles N triangles (1k..10M) beside a mirror
               quad on a one-quad floor: the triangle-count scaling curve

Every scene gets the same explicit settings: Whitted REGULAR 2x2 anti-aliasing, max
depth 5 (glass8: 8; --depth overrides), the default cutoff; Cycles on the CPU with 64
samples, no adaptive sampling and no denoising (default bounces); render threads at
Blender's default; the Standard view transform. The scene's custom properties
"perf_scene" and "perf_mesh_triangles" (the triangles of the distinct meshes Whitted
exports, each instanced mesh once) are saved with it.
"""

import argparse
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_instances
import cost_scenes
import demo_scene

DEFAULT_MAX_DEPTH = 5
GLASS8_MAX_DEPTH = 8
CYCLES_SAMPLES = 64
MILLION_TRIANGLES = 1_000_000
INSTANCES = 10_000
# The demo objects a derived scene replaces.
DEMO_OBJECTS = ("Glass Sphere", "Mirror Sphere", "Cube", "Cylinder")


def mesh_from_faces(name, positions, faces, smooth=True):
    """A mesh from float[N,3] positions and a list of int[K,n] face arrays (any n >= 3,
    counter-clockwise seen from outside), filled with foreach_set: fast for 10M faces."""
    sizes = np.concatenate([np.full(len(f), f.shape[1], dtype=np.int32) for f in faces])
    loops = np.concatenate([f.reshape(-1) for f in faces]).astype(np.int32)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", np.ascontiguousarray(positions, dtype=np.float32).ravel())
    mesh.loops.add(len(loops))
    mesh.loops.foreach_set("vertex_index", loops)
    mesh.polygons.add(len(sizes))
    mesh.polygons.foreach_set("loop_start", np.cumsum(sizes, dtype=np.int32) - sizes)
    mesh.polygons.foreach_set("loop_total", sizes)  # derived from loop_start in 4.0+
    mesh.polygons.foreach_set("use_smooth", np.full(len(sizes), smooth, dtype=bool))
    mesh.update(calc_edges=True)
    return mesh


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


def sphere_mesh(name, radius, triangles):
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
    obj = demo_scene._object(scene.collection, name, mesh, location)
    obj.rotation_euler = rotation
    mesh.materials.append(material)
    return obj


def _mirror(name, color=(0.9, 0.9, 0.9)):
    return demo_scene._material(name, color, {("Metallic",): 1.0, ("Roughness",): 0.0})


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
        sphere_mesh("Glass Sphere", demo_scene.GLASS_RADIUS, share),
        demo_scene.GLASS_CENTER,
        cost_scenes._glass("Glass", 1.5),
    )
    _add(
        scene,
        "Mirror Sphere",
        sphere_mesh("Mirror Sphere", demo_scene.MIRROR_RADIUS, share),
        demo_scene.MIRROR_CENTER,
        _mirror("Mirror"),
    )
    _add(
        scene,
        "Glass Torus",
        torus_mesh("Glass Torus", 0.8, 0.3, share),
        (-3.0, -2.6, 1.1),
        cost_scenes._glass("Torus Glass", 1.45),
        rotation=(math.radians(75.0), 0.0, math.radians(-20.0)),
    )
    _add(
        scene,
        "Gold Torus",
        torus_mesh("Gold Torus", 0.9, 0.3, share),
        (3.4, 2.4, 1.2),
        _mirror("Gold", (1.0, 0.75, 0.3)),
        rotation=(math.radians(90.0), 0.0, math.radians(10.0)),
    )
    return scene


def build_instances(scene, args):
    """args.instances ico spheres scattered by geometry nodes, over a mirror floor,
    seen in perspective."""
    count = args.instances or INSTANCES
    bench_instances.build_scene(scene, count, max(args.resolution))
    if args.ico_subdivisions:
        scatter = bpy.data.objects["Scatter"].modifiers["Scatter"].node_group
        ico = next(n for n in scatter.nodes if n.bl_idname == "GeometryNodeMeshIcoSphere")
        ico.inputs["Subdivisions"].default_value = args.ico_subdivisions
    side = math.ceil(math.sqrt(count))
    half = side / 2.0 + 1.0
    floor = floor_mesh("Floor", half)
    _add(
        scene, "Mirror Floor", floor, (0.0, 0.0, -0.45), _mirror("Mirror Floor", (0.35, 0.35, 0.4))
    )
    camera = scene.camera
    camera.data.type = "PERSP"
    camera.data.lens = 30.0
    # Low over one edge of the grid: the near spheres large, the far ones receding.
    camera.location = (0.0, -0.6 * side, 0.25 * side)
    camera.rotation_euler = demo_scene._facing((0.0, 0.6 * side, -0.3 * side))
    bpy.data.lights["Sun"].angle = 0.0  # hard shadows, as in the other scenes
    scene.world = demo_scene._sky_world()
    return scene


def build_glass8(scene, args):
    """A grid of overlapping glass spheres crossed by glass slabs, before a mirror."""
    del args
    _demo_without_objects(scene)
    iors = cost_scenes.GLASS_IORS
    index = 0
    for row in range(3):
        for column in range(4):
            ior = iors[index % len(iors)]
            _add(
                scene,
                f"Glass {index}",
                demo_scene._sphere_mesh(0.75),
                (-1.8 + 1.2 * column, -1.2 + 1.2 * row, 0.75 + 0.1 * (index % 3)),
                cost_scenes._glass(f"Glass {index} ({ior})", ior),
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
            demo_scene._cube_mesh(1.0),
            location,
            cost_scenes._glass(f"Slab Glass {slab_index}", 1.5),
            rotation=(0.0, 0.0, math.radians(angle)),
        )
        slab.scale = scale
    _add(
        scene,
        "Mirror",
        wall_mesh("Mirror", 4.0, 4.0),
        (0.0, 2.8, 0.0),
        _mirror("Mirror"),
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
        demo_scene._material("Floor", (0.6, 0.6, 0.6), {demo_scene._SPECULAR: 0.0}),
    )
    _add(
        scene,
        "Mirror",
        wall_mesh("Mirror", 3.0, 4.0),
        (0.0, 2.5, 0.0),
        _mirror("Mirror"),
        rotation=(0.0, 0.0, math.radians(-15.0)),
    )
    _add(
        scene,
        "Torus",
        torus_mesh("Torus", 1.6, 0.6, max(total - 4, 12)),
        (0.0, 0.0, 1.9),
        demo_scene._material("Torus", (0.1, 0.25, 0.8), {("Roughness",): 0.3}),
        rotation=(math.radians(70.0), 0.0, 0.0),
    )
    return scene


BUILDERS = {
    "demo": build_demo,
    "million": build_million,
    "instances": build_instances,
    "glass8": build_glass8,
    "triangles": build_triangles,
}


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


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", choices=sorted(BUILDERS), required=True)
    parser.add_argument("--resolution", nargs=2, type=int, required=True, metavar=("W", "H"))
    parser.add_argument("--save", required=True, help=".blend file to write")
    parser.add_argument("--triangles", type=int, help="million, triangles: triangle count")
    parser.add_argument("--instances", type=int, help="instances: instance count")
    parser.add_argument(
        "--ico-subdivisions",
        type=int,
        help="instances: subdivisions of the instanced ico sphere (default "
        f"{bench_instances.ICO_SUBDIVISIONS}: 20,480 triangles)",
    )
    parser.add_argument("--depth", type=int, help="Whitted's max depth (default 5; glass8: 8)")
    return parser.parse_args(argv)


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Blender's own module, importable once bpy is loaded.
    import addon_utils

    for module in ("whitted", "cycles"):
        if addon_utils.enable(module, default_set=True) is None:
            sys.exit(f"perf_scenes: the add-on '{module}' could not be enabled")
    scene = BUILDERS[args.scene](bpy.context.scene, args)
    default_depth = GLASS8_MAX_DEPTH if args.scene == "glass8" else DEFAULT_MAX_DEPTH
    configure(scene, args.resolution, default_depth if args.depth is None else args.depth)
    scene["perf_scene"] = args.scene
    scene["perf_mesh_triangles"] = mesh_triangles(scene)
    path = os.path.abspath(args.save)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=path)
    print(
        f"perf_scenes: saved {path} ({args.scene}, "
        f"{scene['perf_mesh_triangles']:,} mesh triangles)",
        flush=True,
    )


if __name__ == "__main__":
    main()
