"""Mesh export: triangles, normals, per-face materials, shared meshes and instances."""

import dataclasses

import bpy

# isort: split
# Blender as a Python module makes bmesh importable only after bpy.
import bmesh
import numpy as np
import pytest
from exported import exported_meshes
from mathutils import Vector
from whitted.export.instance import DEFAULT_MATERIAL
from whitted.export.mesh import _finish
from whitted.export.sanitise import Sanitised
from whitted_tools import scenes
from whitted_tools.scenes import add_object, bmesh_mesh, ico_sphere_on_points, sphere_mesh

# How far the exported vertex normals may lie from Blender's own: before 4.1 Blender
# weights by the exact corner angle, as the export does; from 4.1 by an approximate
# arc cosine (safe_acos_approx in its mesh_normals.cc), measured 1.7e-5 apart on the
# jittered cylinder below.
BLENDERS_NORMALS_ATOL = 1e-6 if bpy.app.version < (4, 1, 0) else 5e-5


def cube_mesh(name="Cube"):
    return scenes.cube_mesh(name, size=2.0)


def convert(warnings):
    return exported_meshes(bpy.context.evaluated_depsgraph_get(), warnings)


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


def test_smooth_sphere_has_radial_vertex_normals(empty_scene, warnings):
    add_object(empty_scene.collection, "Sphere", sphere_mesh())
    (data,) = convert(warnings).meshes
    # Every corner takes its vertex's normal: one normal per vertex, none per corner.
    assert data.normals is None
    assert data.vertex_normals.dtype == np.float32
    assert data.vertex_normals.shape == data.positions.shape
    assert data.vertex_normals.flags.c_contiguous
    mesh = bpy.data.objects["Sphere"].data
    vertex_normals = np.empty((len(mesh.vertices), 3), dtype=np.float32)
    mesh.vertices.foreach_get("normal", vertex_normals.reshape(-1))
    np.testing.assert_allclose(data.vertex_normals, vertex_normals, atol=BLENDERS_NORMALS_ATOL)
    corners = data.corner_normals()
    assert corners.shape == (len(data.triangles), 3, 3)
    # On a unit sphere they point nearly along the position (within 2 degrees).
    cosines = np.sum(corners * data.positions[data.triangles], axis=-1)
    assert cosines.min() > np.cos(np.radians(2.0))


def test_vertex_normals_of_n_gons_equal_blenders_and_repeat_to_the_bit(empty_scene, warnings):
    # A smooth cylinder (two 32-gon caps), its vertices jittered so that the quads are
    # not planar and the angles all differ, and one cap made concave by pulling a
    # vertex inwards: the angle weighting and the polygons' own normals both count.
    bm = bmesh.new()
    bmesh.ops.create_cone(bm, cap_ends=True, segments=32, radius1=1.0, radius2=0.7, depth=2.0)
    rng = np.random.default_rng(7)
    for vertex in bm.verts:
        vertex.co += Vector(rng.uniform(-0.05, 0.05, 3))
    bm.verts.ensure_lookup_table()
    bm.verts[0].co.xy *= 0.3
    for face in bm.faces:
        face.smooth = True
    mesh = bpy.data.meshes.new("Cylinder")
    bm.to_mesh(mesh)
    bm.free()
    add_object(empty_scene.collection, "Cylinder", mesh)
    (data,) = convert(warnings).meshes
    blenders = np.empty((len(mesh.vertices), 3), dtype=np.float32)
    mesh.vertices.foreach_get("normal", blenders.reshape(-1))
    np.testing.assert_allclose(data.vertex_normals, blenders, atol=BLENDERS_NORMALS_ATOL)
    for _ in range(3):
        mesh.update()  # Blender computes its normals again, on threads
        assert convert(warnings).meshes[0].vertex_normals.tobytes() == data.vertex_normals.tobytes()


def test_custom_normals_are_exported_per_corner(empty_scene, warnings):
    mesh = sphere_mesh()
    if hasattr(mesh, "use_auto_smooth"):  # Blender < 4.1 reads custom normals only so
        mesh.use_auto_smooth = True
    up = np.tile(np.array([0.0, 0.0, 1.0], dtype=np.float32), (len(mesh.vertices), 1))
    mesh.normals_split_custom_set_from_vertices(up)
    add_object(empty_scene.collection, "Sphere", mesh)
    (data,) = convert(warnings).meshes
    assert data.vertex_normals is None
    assert data.normals.shape == (len(data.triangles), 3, 3)
    np.testing.assert_allclose(data.normals, np.broadcast_to(up[0], data.normals.shape), atol=1e-3)
    assert data.corner_normals() is data.normals


def test_sharp_edges_are_exported_per_corner(empty_scene, warnings):
    mesh = cube_mesh()
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    # The edges around the top face are sharp, the others smooth.
    for edge in mesh.edges:
        edge.use_edge_sharp = all(mesh.vertices[v].co.z > 0.0 for v in edge.vertices)
    if hasattr(mesh, "use_auto_smooth"):  # Blender < 4.1 honours sharp edges only so
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = np.pi
    add_object(empty_scene.collection, "Cube", mesh)
    (data,) = convert(warnings).meshes
    assert data.vertex_normals is None
    assert data.normals.shape == (12, 3, 3)
    # The top face's corners keep its normal; a side face's corners on top lean sideways
    # (they share a normal with the neighbouring side only), those at the bottom down too.
    top = (data.positions[data.triangles][..., 2] > 0.0).all(axis=1)
    assert top.sum() == 2
    np.testing.assert_allclose(data.normals[top], np.broadcast_to((0, 0, 1), (2, 3, 3)), atol=1e-6)
    corner_z = data.positions[data.triangles][..., 2]
    side_normals = data.normals[~top]
    np.testing.assert_allclose(side_normals[corner_z[~top] > 0.0][:, 2], 0.0, atol=1e-6)
    assert (side_normals[corner_z[~top] < 0.0][:, 2] < -0.5).all()


def test_a_zero_vertex_normal_makes_corner_normals_with_the_face_normal():
    # Vertex 3's normal is zero (Blender gives one to a vertex whose faces cancel out):
    # its corners take their triangle's face normal, the others keep the vertex normal.
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], dtype=np.float32)
    corners = np.array([[0, 1, 2], [1, 3, 2]], dtype=np.uint32)
    vertex_normals = np.array([[0, 0.6, 0.8], [0, 0, 1], [0, 0, 1], [0, 0, 0]], np.float32)
    data, sanitised = _finish("Mesh", positions, corners, None, vertex_normals, None, None)
    assert sanitised == Sanitised(normals=1)
    assert data.vertex_normals is None
    expected = [[[0, 0.6, 0.8], [0, 0, 1], [0, 0, 1]], [[0, 0, 1], [0, 0, 1], [0, 0, 1]]]
    np.testing.assert_array_equal(data.normals, np.array(expected, dtype=np.float32))


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


def test_meshes_read_in_place_equal_their_copies(empty_scene, warnings):
    # A render reads the depsgraph's meshes in place, the viewport copies them with
    # to_mesh(): every kind of normals, modifiers, slots and UVs come out the same.
    collection = empty_scene.collection
    add_object(collection, "Smooth", sphere_mesh("Smooth"))
    add_object(collection, "Flat", cube_mesh("Flat"), location=(3.0, 0.0, 0.0))
    mixed = cube_mesh("Mixed")
    mixed.polygons[0].use_smooth = True
    add_object(collection, "Mixed", mixed)
    sharp = sphere_mesh("Sharp")
    if hasattr(sharp, "use_auto_smooth"):
        sharp.use_auto_smooth = True
        sharp.auto_smooth_angle = np.radians(20.0)
    else:
        sharp.set_sharp_from_angle(angle=np.radians(20.0))
    sharp.materials.append(bpy.data.materials.new("A"))
    sharp.materials.append(bpy.data.materials.new("B"))
    sharp.polygons.foreach_set("material_index", np.arange(len(sharp.polygons)) % 2)
    add_object(collection, "Sharp", sharp)
    custom = sphere_mesh("Custom")
    if hasattr(custom, "use_auto_smooth"):
        custom.use_auto_smooth = True
    custom.normals_split_custom_set_from_vertices([(0.0, 0.6, 0.8)] * len(custom.vertices))
    add_object(collection, "Custom", custom)
    modified = add_object(collection, "Modified", sphere_mesh("Modified"))
    modified.modifiers.new("Subdivision", "SUBSURF").levels = 1
    uv = sphere_mesh("UV")
    uv.uv_layers.new(name="Map")
    uv.materials.append(bpy.data.materials.new("Textured"))
    add_object(collection, "UV", uv)

    def convert_all(in_place):
        depsgraph = bpy.context.evaluated_depsgraph_get()
        exported = exported_meshes(depsgraph, warnings, {"Textured": "Map"}, in_place=in_place)
        return {mesh.name: mesh for mesh in exported.meshes}

    copies = convert_all(in_place=False)
    in_place = convert_all(in_place=True)
    assert sorted(in_place) == sorted(copies) and len(copies) == 7
    for name, copy in copies.items():
        for field in dataclasses.fields(copy):
            a, b = getattr(copy, field.name), getattr(in_place[name], field.name)
            if isinstance(a, np.ndarray):
                np.testing.assert_array_equal(a, b, err_msg=f"{name}.{field.name}")
            else:
                assert a == b, f"{name}.{field.name}"
    kinds = {
        name.split(":", 1)[1]: (data.normals is not None, data.vertex_normals is not None)
        for name, data in copies.items()
    }
    assert kinds["Smooth"] == kinds["Modified"] == kinds["UV"] == (False, True)
    assert kinds["Flat"] == (False, False)
    assert kinds["Mixed"] == kinds["Sharp"] == kinds["Custom"] == (True, False)
    assert copies["mesh:Sharp"].material_slots is not None
    assert copies["mesh:UV"].uvs is not None
    assert warnings == []


def test_a_mesh_in_edit_mode_is_read_with_its_edits(empty_scene, warnings):
    obj = add_object(empty_scene.collection, "Cube", cube_mesh())
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    try:
        edit = bmesh.from_edit_mesh(obj.data)
        for vertex in edit.verts:
            vertex.co.z += 10.0
        bmesh.update_edit_mesh(obj.data)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        (data,) = exported_meshes(depsgraph, warnings, in_place=True).meshes
    finally:
        bpy.ops.object.mode_set(mode="OBJECT")
    assert data.positions[:, 2].min() == pytest.approx(9.0)


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
    tree = ico_sphere_on_points("Scatter")
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


def test_material_index_past_the_last_of_two_slots_uses_the_last(empty_scene, warnings):
    mesh = cube_mesh()
    mesh.materials.append(bpy.data.materials.new("First"))
    mesh.materials.append(bpy.data.materials.new("Last"))
    mesh.polygons.foreach_set("material_index", [0, 3, 1, 0, 7, 0])
    add_object(empty_scene.collection, "Cube", mesh)
    (data,) = convert(warnings).meshes
    faces = np.empty(len(data.triangles), dtype=np.int32)
    mesh.calc_loop_triangles()
    mesh.loop_triangles.foreach_get("polygon_index", faces)
    np.testing.assert_array_equal(data.material_slots, np.array([0, 1, 1, 0, 1, 0])[faces])


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
    exported = exported_meshes(depsgraph, warnings)
    in_depsgraph = {m.name_full for m in depsgraph.ids if isinstance(m, bpy.types.Material)}
    used = {name for i in exported.instances for name in i.materials}
    assert used == {"InExcludedCollection", "Object"}
    assert used <= in_depsgraph
