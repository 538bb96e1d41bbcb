"""Mesh export: triangles, normals, per-face materials, shared meshes and instances."""

import bpy

# isort: split
# Blender as a Python module makes bmesh importable only after bpy.
import bmesh
import node_trees
import numpy as np
import pytest
from whitted.export.mesh import DEFAULT_MATERIAL, convert_meshes


def bmesh_mesh(name, build, smooth=False):
    bm = bmesh.new()
    try:
        build(bm)
        mesh = bpy.data.meshes.new(name)
        bm.to_mesh(mesh)
    finally:
        bm.free()
    mesh.polygons.foreach_set("use_smooth", [smooth] * len(mesh.polygons))
    return mesh


def cube_mesh(name="Cube"):
    return bmesh_mesh(name, lambda bm: bmesh.ops.create_cube(bm, size=2.0))


def sphere_mesh(name="Sphere", smooth=True):
    return bmesh_mesh(
        name,
        lambda bm: bmesh.ops.create_uvsphere(bm, u_segments=16, v_segments=8, radius=1.0),
        smooth=smooth,
    )


def add_object(collection, name, data, location=(0.0, 0.0, 0.0)):
    obj = bpy.data.objects.new(name, data)
    obj.location = location
    collection.objects.link(obj)
    return obj


def convert(warnings):
    return convert_meshes(bpy.context.evaluated_depsgraph_get(), warnings)


def test_cube_triangles_and_per_face_materials(empty_scene, warnings):
    mesh = cube_mesh()
    red, blue = bpy.data.materials.new("Red"), bpy.data.materials.new("Blue")
    mesh.materials.append(red)
    mesh.materials.append(blue)
    mesh.polygons.foreach_set("material_index", [0, 1, 0, 1, 0, 1])
    add_object(empty_scene.collection, "Cube", mesh, location=(1.0, 2.0, 3.0))

    exported = convert(warnings)
    (data,) = exported.meshes
    (instance,) = exported.instances
    assert data.positions.dtype == np.float32
    assert data.positions.shape == (8, 3)
    assert data.triangles.dtype == np.uint32
    assert data.triangles.shape == (12, 3)
    assert data.positions.flags.c_contiguous
    assert data.triangles.flags.c_contiguous
    assert np.abs(data.positions).max() == pytest.approx(1.0)
    assert data.normals is None  # every face flat
    # Each quad became two triangles of its face's slot.
    polygon_of_triangle = np.empty(12, dtype=np.int32)
    mesh.calc_loop_triangles()
    mesh.loop_triangles.foreach_get("polygon_index", polygon_of_triangle)
    np.testing.assert_array_equal(data.material_slots, polygon_of_triangle % 2)
    assert data.material_slots.dtype == np.int32
    assert instance.mesh == data.name
    assert instance.materials == ("Red", "Blue")
    np.testing.assert_allclose(instance.transform[:3, 3], (1.0, 2.0, 3.0))
    assert warnings == []


def test_smooth_sphere_has_radial_corner_normals(empty_scene, warnings):
    add_object(empty_scene.collection, "Sphere", sphere_mesh())
    (data,) = convert(warnings).meshes
    assert data.normals.dtype == np.float32
    assert data.normals.shape == (len(data.triangles), 3, 3)
    # Smooth corners carry the vertex normals ...
    mesh = bpy.data.objects["Sphere"].data
    vertex_normals = np.empty((len(mesh.vertices), 3), dtype=np.float32)
    mesh.vertices.foreach_get("normal", vertex_normals.reshape(-1))
    np.testing.assert_allclose(data.normals, vertex_normals[data.triangles], atol=1e-5)
    # ... which on a unit sphere point nearly along the position (within 2 degrees).
    cosines = np.sum(data.normals * data.positions[data.triangles], axis=-1)
    assert cosines.min() > np.cos(np.radians(2.0))


def test_flat_sphere_has_no_normals(empty_scene, warnings):
    add_object(empty_scene.collection, "Sphere", sphere_mesh(smooth=False))
    (data,) = convert(warnings).meshes
    assert data.normals is None


def test_mixed_smooth_and_flat_faces(empty_scene, warnings):
    mesh = cube_mesh()
    mesh.polygons[0].use_smooth = True
    add_object(empty_scene.collection, "Cube", mesh)
    (data,) = convert(warnings).meshes
    assert data.normals is not None
    # A flat face's corners keep its face normal.
    polygon_of_triangle = np.empty(12, dtype=np.int32)
    mesh.calc_loop_triangles()
    mesh.loop_triangles.foreach_get("polygon_index", polygon_of_triangle)
    for triangle, polygon in enumerate(polygon_of_triangle):
        if polygon != 0:
            face_normal = np.array(mesh.polygons[polygon].normal)
            np.testing.assert_allclose(data.normals[triangle], [face_normal] * 3, atol=1e-6)


def test_collection_instances_share_one_mesh(empty_scene, warnings):
    source = bpy.data.collections.new("Source")
    empty_scene.collection.children.link(source)
    add_object(source, "Ball", sphere_mesh())
    # Keep the source out of the render; only its instances show.
    bpy.context.view_layer.layer_collection.children["Source"].exclude = True
    count = 5
    for i in range(count):
        instancer = add_object(empty_scene.collection, f"Instancer {i}", None, (3.0 * i, 0.0, 0.0))
        instancer.instance_type = "COLLECTION"
        instancer.instance_collection = source

    exported = convert(warnings)
    assert len(exported.meshes) == 1
    assert len(exported.instances) == count
    assert {instance.mesh for instance in exported.instances} == {exported.meshes[0].name}
    assert len({instance.name for instance in exported.instances}) == count
    offsets = sorted(instance.transform[0, 3] for instance in exported.instances)
    assert offsets == pytest.approx([0.0, 3.0, 6.0, 9.0, 12.0])


def test_objects_sharing_a_mesh_share_it(empty_scene, warnings):
    mesh = cube_mesh()
    add_object(empty_scene.collection, "A", mesh)
    add_object(empty_scene.collection, "B", mesh, (5.0, 0.0, 0.0))
    exported = convert(warnings)
    assert len(exported.meshes) == 1
    assert [instance.name for instance in exported.instances] == ["A", "B"]


def test_modifiers_are_applied_per_object(empty_scene, warnings):
    mesh = cube_mesh()
    add_object(empty_scene.collection, "Plain", mesh)
    smooth = add_object(empty_scene.collection, "Subdivided", mesh)
    smooth.modifiers.new("Subdivision", "SUBSURF").levels = 1
    exported = convert(warnings)
    assert len(exported.meshes) == 2
    triangles = {
        instance.name: next(m for m in exported.meshes if m.name == instance.mesh).triangles
        for instance in exported.instances
    }
    assert len(triangles["Plain"]) == 12
    assert len(triangles["Subdivided"]) == 48  # each quad split in 4, then in 2


def test_object_linked_materials_differ_per_instance(empty_scene, warnings):
    mesh = cube_mesh()
    mesh.materials.append(bpy.data.materials.new("Data"))
    add_object(empty_scene.collection, "A", mesh)
    b = add_object(empty_scene.collection, "B", mesh)
    b.material_slots[0].link = "OBJECT"
    b.material_slots[0].material = bpy.data.materials.new("Object")
    exported = convert(warnings)
    assert len(exported.meshes) == 1
    assert {i.name: i.materials for i in exported.instances} == {"A": ("Data",), "B": ("Object",)}


def test_geometry_nodes_instances_share_one_mesh(empty_scene, warnings):
    grid = bmesh_mesh(
        "Grid", lambda bm: bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=2.0)
    )
    obj = add_object(empty_scene.collection, "Scatter", grid)
    tree = node_trees.ico_sphere_on_points("Scatter")
    obj.modifiers.new("Scatter", "NODES").node_group = tree

    exported = convert(warnings)
    # The grid's 4 corners each get an ico sphere; the grid itself is replaced.
    assert len(exported.meshes) == 1
    assert len(exported.instances) == 4
    assert len(exported.meshes[0].triangles) == 20  # an ico sphere of subdivision 1
    assert len({instance.name for instance in exported.instances}) == 4


def text_data():
    text = bpy.data.curves.new("Text", "FONT")
    text.body = "Hi"
    return text


def filled_curve_data():
    curve = bpy.data.curves.new("Curve", "CURVE")
    curve.dimensions = "2D"
    curve.fill_mode = "BOTH"
    spline = curve.splines.new("BEZIER")
    spline.use_cyclic_u = True
    spline.bezier_points.add(2)
    for point, co in zip(spline.bezier_points, [(0, 0, 0), (1, 0, 0), (0, 1, 0)], strict=True):
        point.co = co
        point.handle_left_type = point.handle_right_type = "AUTO"
    return curve


def metaball_data():
    metaball = bpy.data.metaballs.new("Meta")
    metaball.elements.new()
    return metaball


@pytest.mark.parametrize("make_data", [text_data, filled_curve_data, metaball_data])
def test_curves_text_and_metaballs_are_exported_once_as_meshes(empty_scene, warnings, make_data):
    add_object(empty_scene.collection, "Shape", make_data())
    exported = convert(warnings)
    # The depsgraph yields the object and a MESH instance of its evaluated mesh:
    # the geometry must be exported once, not twice.
    assert len(exported.meshes) == 1
    assert len(exported.instances) == 1
    assert len(exported.meshes[0].triangles) > 0


def test_hidden_and_non_geometry_objects_are_skipped(empty_scene, warnings):
    add_object(empty_scene.collection, "Shown", cube_mesh())
    add_object(empty_scene.collection, "Hidden", cube_mesh("Other")).hide_render = True
    add_object(empty_scene.collection, "Empty", None)
    add_object(empty_scene.collection, "Camera", bpy.data.cameras.new("Camera"))
    assert [instance.name for instance in convert(warnings).instances] == ["Shown"]


def test_empty_slots_use_the_default_material(empty_scene, warnings):
    add_object(empty_scene.collection, "NoSlots", cube_mesh())
    mesh = cube_mesh("Slots")
    mesh.materials.append(None)
    mesh.materials.append(bpy.data.materials.new("Second"))
    add_object(empty_scene.collection, "EmptySlot", mesh)
    materials = {i.name: i.materials for i in convert(warnings).instances}
    assert materials == {
        "NoSlots": (DEFAULT_MATERIAL,),
        "EmptySlot": (DEFAULT_MATERIAL, "Second"),
    }


def test_material_index_past_the_last_slot_uses_the_last_slot(empty_scene, warnings):
    mesh = cube_mesh()
    mesh.materials.append(bpy.data.materials.new("Only"))
    mesh.polygons.foreach_set("material_index", [0, 3, 0, 0, 0, 0])
    add_object(empty_scene.collection, "Cube", mesh)
    (data,) = convert(warnings).meshes
    assert data.material_slots is None  # clamped to slot 0 everywhere


def test_every_instance_material_is_in_the_depsgraph(empty_scene, warnings):
    # scene.py exports the materials it finds in depsgraph.ids; instances must not
    # name any other (the native scene refuses a missing material).
    source = bpy.data.collections.new("Source")
    empty_scene.collection.children.link(source)
    hidden_mesh = cube_mesh("Hidden")
    hidden_mesh.materials.append(bpy.data.materials.new("InExcludedCollection"))
    add_object(source, "Source Cube", hidden_mesh)
    bpy.context.view_layer.layer_collection.children["Source"].exclude = True
    instancer = add_object(empty_scene.collection, "Instancer", None)
    instancer.instance_type = "COLLECTION"
    instancer.instance_collection = source
    mesh = cube_mesh()
    mesh.materials.append(bpy.data.materials.new("Data"))
    obj = add_object(empty_scene.collection, "Object Linked", mesh)
    obj.material_slots[0].link = "OBJECT"
    obj.material_slots[0].material = bpy.data.materials.new("Object")

    depsgraph = bpy.context.evaluated_depsgraph_get()
    exported = convert_meshes(depsgraph, warnings)
    in_depsgraph = {m.name_full for m in depsgraph.ids if isinstance(m, bpy.types.Material)}
    used = {name for i in exported.instances for name in i.materials}
    assert used == {"InExcludedCollection", "Object"}
    assert used <= in_depsgraph
