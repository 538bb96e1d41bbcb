"""Building blocks of the scenes tests and benchmarks build with bpy (Blender 3.4 and 5.0):
meshes from bmesh operators or from face arrays, objects, Principled materials."""

import bpy

# isort: split
# Blender as a Python module makes bmesh and mathutils importable only after bpy.
import bmesh
import numpy as np
from mathutils import Vector

# Principled BSDF inputs by name, newest first (Blender 4.0 renamed some).
SPECULAR = ("Specular IOR Level", "Specular")
TRANSMISSION = ("Transmission Weight", "Transmission")


def add_object(owner, name, data, location=(0.0, 0.0, 0.0), scale=None):
    """A new object of `data` linked into `owner` (a scene's master collection, or a
    collection); scale a number or three."""
    obj = bpy.data.objects.new(name, data)
    obj.location = location
    if scale is not None:
        obj.scale = (scale, scale, scale) if np.isscalar(scale) else scale
    collection = owner.collection if isinstance(owner, bpy.types.Scene) else owner
    collection.objects.link(obj)
    return obj


def bmesh_mesh(name, build, smooth=False):
    """A mesh made by build(bm) on a fresh bmesh, every face smooth or flat."""
    bm = bmesh.new()
    try:
        build(bm)
        mesh = bpy.data.meshes.new(name)
        bm.to_mesh(mesh)
    finally:
        bm.free()
    mesh.polygons.foreach_set("use_smooth", [smooth] * len(mesh.polygons))
    return mesh


def sphere_mesh(name="Sphere", segments=16, rings=8, radius=1.0, smooth=True, scale=None):
    """A UV sphere about the origin (scaled by the three factors of scale, if given)."""

    def build(bm):
        bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=radius)
        if scale is not None:
            bmesh.ops.scale(bm, vec=scale, verts=bm.verts)

    return bmesh_mesh(name, build, smooth)


def cube_mesh(name="Cube", size=1.0, smooth=False):
    """A cube of edge `size` about the origin."""
    return bmesh_mesh(name, lambda bm: bmesh.ops.create_cube(bm, size=size), smooth)


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


def facing(direction):
    """The rotation that points an object's local -Z (where cameras look and lights
    shine) along `direction`, keeping local +Y up."""
    return Vector(direction).to_track_quat("-Z", "Y").to_euler()


def uses_node_tree_always():
    """Blender 5.0 always shades with node trees and deprecates `use_nodes`."""
    return bpy.app.version >= (5, 0, 0)


def principled_material(name, base_color, inputs):
    """A material whose Principled BSDF has `base_color` and `inputs` ({(names, newest
    first): value}); the viewport shows the same colour."""
    material = bpy.data.materials.new(name)
    material.diffuse_color = (*base_color, 1.0)
    if not uses_node_tree_always():
        material.use_nodes = True
    set_principled_inputs(material, {("Base Color",): (*base_color, 1.0), **inputs})
    return material


def set_principled_inputs(material, inputs):
    """Set inputs of the material's Principled BSDF: {(names, newest first): value}."""
    principled = next(
        node for node in material.node_tree.nodes if node.bl_idname == "ShaderNodeBsdfPrincipled"
    )
    for names, value in inputs.items():
        socket = next(principled.inputs[n] for n in names if n in principled.inputs)
        socket.default_value = value


def background_world(name, color, strength=1.0):
    """A world whose Background node shows `color` (linear) at `strength`."""
    world = bpy.data.worlds.new(name)
    world.color = color
    if not uses_node_tree_always():
        world.use_nodes = True
    background = next(
        node for node in world.node_tree.nodes if node.bl_idname == "ShaderNodeBackground"
    )
    background.inputs["Color"].default_value = (*color, 1.0)
    background.inputs["Strength"].default_value = strength
    return world


def geometry_nodes_tree(name):
    """(an empty geometry-nodes tree with a Geometry input and output, its Group Input
    node, its Group Output node)."""
    tree = bpy.data.node_groups.new(name, "GeometryNodeTree")
    if hasattr(tree, "interface"):  # Blender 4.0+
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        tree.inputs.new("NodeSocketGeometry", "Geometry")
        tree.outputs.new("NodeSocketGeometry", "Geometry")
    return tree, tree.nodes.new("NodeGroupInput"), tree.nodes.new("NodeGroupOutput")


def ico_sphere_on_points(name, radius=1.0, subdivisions=1):
    """A geometry-nodes tree that puts an ico sphere on every point of its input."""
    tree, group_input, group_output = geometry_nodes_tree(name)
    instance_on_points = tree.nodes.new("GeometryNodeInstanceOnPoints")
    ico_sphere = tree.nodes.new("GeometryNodeMeshIcoSphere")
    ico_sphere.inputs["Radius"].default_value = radius
    ico_sphere.inputs["Subdivisions"].default_value = subdivisions
    tree.links.new(group_input.outputs[0], instance_on_points.inputs["Points"])
    tree.links.new(ico_sphere.outputs["Mesh"], instance_on_points.inputs["Instance"])
    tree.links.new(instance_on_points.outputs["Instances"], group_output.inputs[0])
    return tree


def mesh_to_volume(owner, name, mesh_object, voxel_size):
    """A Volume object `name` whose Mesh to Volume modifier fills `mesh_object` with
    density 1 at voxels of `voxel_size` Blender units (its grid "density", evaluated:
    no file holds it)."""
    volume = add_object(owner, name, bpy.data.volumes.new(name))
    modifier = volume.modifiers.new("Fill", "MESH_TO_VOLUME")
    modifier.object = mesh_object
    modifier.resolution_mode = "VOXEL_SIZE"
    modifier.voxel_size = voxel_size
    if hasattr(modifier, "use_fill_volume"):  # 3.4 has it; 4.2 and 5.0 always fill
        modifier.use_fill_volume = True
    return volume
