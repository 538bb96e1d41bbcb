"""Volume objects' grids (issue 48; export/volume_object.py, sync/volumes.py, native
scene/vdb_file.h; rendered against Cycles in tests/blender/test_volume.py): a Mesh to
Volume object's evaluated grids written and read, the grid's
voxels, bounds and transform against Blender's own; an imported .vdb read from its file
and placed by its object; an image sequence's file for the frame; a geometry-nodes
volume on a mesh object; a missing file, an object without grids and a material that
reads no grid of the file, each skipped with its reason, the render going on."""

import os

import bpy
import numpy as np
import pytest
from whitted.export.volume_object import material_grids, volume_object_data
from whitted.properties.presets import quality_of
from whitted.sync.frame import sync_frame
from whitted.sync.scene import SyncParams
from whitted_tools.scenes import add_object, cube_mesh, geometry_nodes_tree, mesh_to_volume

VOXEL = 0.1  # the Mesh to Volume modifier's voxel size, Blender units


@pytest.fixture
def stage(empty_scene):
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    empty_scene.collection.objects.link(camera)
    empty_scene.camera = camera
    camera.location = (0.0, -8.0, 0.0)
    camera.rotation_euler = (1.5708, 0.0, 0.0)
    empty_scene.render.resolution_x = empty_scene.render.resolution_y = 16
    return empty_scene


def _frame(native):
    return sync_frame(bpy.context.evaluated_depsgraph_get(), native)


def _smoke(scene):
    """A Volume object 'Smoke' whose Mesh to Volume modifier fills a cube of edge 2
    (hidden from the render) centred at the origin with density 1."""
    cube = add_object(scene, "Source", cube_mesh("Source", 2.0))
    cube.hide_render = True
    return mesh_to_volume(scene, "Smoke", cube, VOXEL)


def _read(frame, name):
    return frame.sync._volumes[name]


def test_a_mesh_to_volume_objects_grid_is_read_with_its_voxels_and_bounds(stage, native):
    smoke = _smoke(stage)
    frame = _frame(native)
    read = _read(frame, "Smoke")
    (grid,) = read.grids
    assert grid.name == "density" and grid.channels == 1
    # Edge 2 at voxels of 0.1: 20 voxels across inside, and the modifier's exterior band.
    x, y, z = grid.resolution
    assert x == y == z and 20 <= x <= 26, grid.resolution
    assert grid.active_voxels >= 20**3
    # The grid's transform is the one Blender holds for it (index -> object space).
    evaluated = smoke.evaluated_get(bpy.context.evaluated_depsgraph_get())
    blender_grid = evaluated.data.grids["density"]
    assert np.allclose(grid.index_to_object, np.array(blender_grid.matrix_object), atol=1e-6)
    lower, upper = read.native.world_bounds
    assert np.allclose(lower, -1.0, atol=3.5 * VOXEL) and np.allclose(upper, 1.0, atol=3.5 * VOXEL)
    # Filled with density 1 inside, nothing far outside.
    assert read.native.sample((0.0, 0.0, 0.0))["density"] == pytest.approx(1.0, abs=1e-6)
    assert read.native.sample((0.3, -0.5, 0.7))["density"] == pytest.approx(1.0, abs=1e-6)
    assert read.native.sample((3.0, 0.0, 0.0))["density"] == 0.0
    # Rendered (tests/blender/test_volume.py): nothing skipped; an instance of its mesh
    # filled by its material read with its grid.
    assert not [w for w in frame.warnings if "Volume object" in w], frame.warnings
    instance = frame.sync._instances["Smoke"]
    assert instance.volume is read.native and instance.mesh == "volume:Smoke"
    assert instance.materials == ("\x1fgrids:density=density",)  # no material: Cycles' default
    assert frame.memory.volume_bytes == read.native.bytes > 4 * grid.active_voxels


def _saved_grids(scene, folder):
    """The Smoke object's evaluated grids saved to FOLDER/smoke.vdb by Blender; the
    object removed."""
    smoke = _smoke(scene)
    evaluated = smoke.evaluated_get(bpy.context.evaluated_depsgraph_get())
    path = os.path.join(folder, "smoke.vdb")
    assert evaluated.data.grids.save(path)
    bpy.data.objects.remove(smoke)
    return path


def test_an_imported_vdb_is_read_from_its_file_and_placed_by_its_object(stage, native, tmp_path):
    path = _saved_grids(stage, str(tmp_path))
    volume = bpy.data.volumes.new("Imported")
    volume.filepath = path
    add_object(stage, "Imported", volume, location=(5.0, 0.0, 0.0), scale=2.0)
    frame = _frame(native)
    read = _read(frame, "Imported")
    assert read.key is not None and read.key[0] == path  # the file itself, not a copy
    lower, upper = read.native.world_bounds
    # The cube's box [-1, 1] (with its band), scaled by 2 and moved to x = 5.
    assert lower[0] == pytest.approx(5.0 - 2.0, abs=2 * 3.5 * VOXEL)
    assert upper[0] == pytest.approx(5.0 + 2.0, abs=2 * 3.5 * VOXEL)
    assert upper[2] == pytest.approx(2.0, abs=2 * 3.5 * VOXEL)
    assert read.native.sample((5.0, 0.0, 0.0))["density"] == pytest.approx(1.0, abs=1e-6)
    assert read.native.sample((5.0 + 1.0, 0.0, 0.0))["density"] == pytest.approx(1.0, abs=1e-6)
    assert read.native.sample((0.0, 0.0, 0.0))["density"] == 0.0
    # Moving the object (the viewport's next sync, fed the depsgraph's updates as
    # view_update is) keeps the grids read from the same file and moves the bounds.
    kept = read.grids
    reports = []

    def on_update(scene, depsgraph):
        reports.append(frame.sync.sync(depsgraph, SyncParams.of(scene, quality_of(scene.whitted))))

    bpy.app.handlers.depsgraph_update_post.append(on_update)
    try:
        bpy.data.objects["Imported"].location = (0.0, 0.0, 0.0)
        bpy.context.view_layer.update()
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(on_update)
    assert reports and reports[-1].walked, reports
    moved = _read(frame, "Imported")
    assert moved.grids is kept
    assert moved.native.world_bounds[0][0] == pytest.approx(-2.0, abs=2 * 3.5 * VOXEL)
    # Its mesh, the same, is not built again; another Clipping (the same file, its grids
    # kept) builds it anew.
    assert read.mesh is not None and moved.mesh is None
    bpy.app.handlers.depsgraph_update_post.append(on_update)
    try:
        volume.render.clipping = 1.0
        volume.update_tag()
        bpy.context.view_layer.update()
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(on_update)
    clipped = _read(frame, "Imported")
    assert clipped.grids is kept and clipped.data.clipping == 1.0
    assert clipped.mesh is not None  # (handed to the scene since: Scene.set_mesh takes it)


def test_missing_and_empty_volumes_are_skipped_with_their_reason(stage, native):
    missing = bpy.data.volumes.new("Missing")
    missing.filepath = "/nonexistent/folder/smoke.vdb"
    add_object(stage, "Missing", missing)
    add_object(stage, "Empty", bpy.data.volumes.new("Empty"))
    add_object(stage, "Plain", cube_mesh("Plain", 1.0))
    frame = _frame(native)  # nothing raised: the scene still renders
    lines = [w for w in frame.warnings if "Volume object" in w]
    print("\n".join(lines))
    assert len(lines) == 2, frame.warnings
    empty, missing_line = lines
    assert "Volume object 'Empty' skipped: it has no grids" in empty
    assert "Volume object 'Missing' skipped" in missing_line
    assert "/nonexistent/folder/smoke.vdb" in missing_line or "not found" in missing_line.lower()
    assert frame.sync._volumes == {}
    assert frame.memory.volume_bytes == 0


def test_a_material_that_reads_no_grid_of_the_object_skips_it(stage, native):
    smoke = _smoke(stage)
    material = bpy.data.materials.new("Heat")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    principled = tree.nodes.new("ShaderNodeVolumePrincipled")
    principled.inputs["Density Attribute"].default_value = "heat"
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    tree.links.new(principled.outputs[0], output.inputs["Volume"])
    smoke.data.materials.append(material)
    assert material_grids(material) == {"density": "heat"}
    lines = [w for w in _frame(native).warnings if "Volume object" in w]
    assert lines == [
        "Whitted: Volume object 'Smoke' skipped: its material reads none of its grids "
        "(density; readable: density)"
    ]


def test_which_grids_a_material_reads():
    # No material: Cycles' default volume, a Principled Volume reading "density".
    assert material_grids(None) == {"density": "density"}
    material = bpy.data.materials.new("Fire")
    if bpy.app.version < (5, 0, 0):
        material.use_nodes = True
    tree = material.node_tree
    principled = tree.nodes.new("ShaderNodeVolumePrincipled")
    output = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    tree.links.new(principled.outputs[0], output.inputs["Volume"])
    # The node's defaults: density read; temperature only once blackbody emission is on.
    assert material_grids(material) == {"density": "density"}
    principled.inputs["Blackbody Intensity"].default_value = 1.0
    principled.inputs["Color Attribute"].default_value = "color"
    assert material_grids(material) == {
        "density": "density",
        "color": "color",
        "temperature": "temperature",
    }


def test_a_sequence_reads_the_file_of_the_frame(stage, native, tmp_path):
    # Two frames of a cache: the cube filled at voxels of 0.1, then of 0.2.
    cube = add_object(stage, "Source", cube_mesh("Source", 2.0))
    cube.hide_render = True
    for frame, voxel in ((1, 0.1), (2, 0.2)):
        smoke = mesh_to_volume(stage, f"Frame {frame}", cube, voxel)
        grids = smoke.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.grids
        assert grids.save(str(tmp_path / f"smoke_{frame:04d}.vdb"))
        bpy.data.objects.remove(smoke)
    volume = bpy.data.volumes.new("Cache")
    volume.filepath = str(tmp_path / "smoke_0001.vdb")
    volume.is_sequence = True
    volume.frame_start, volume.frame_duration = 1, 2
    add_object(stage, "Cache", volume)
    read = {}
    for frame in (1, 2):
        stage.frame_set(frame)
        read[frame] = _read(_frame(native), "Cache")
    assert read[1].key[0].endswith("smoke_0001.vdb") and read[2].key[0].endswith("smoke_0002.vdb")
    coarse, fine = read[2].grids[0].resolution[0], read[1].grids[0].resolution[0]
    assert fine > 1.7 * coarse, (fine, coarse)


def test_a_geometry_nodes_volume_is_written_and_read(stage, native):
    # A mesh object whose geometry nodes make a volume (Mesh to Volume): no file holds it.
    holder = add_object(stage, "Cloud", cube_mesh("Cloud", 2.0))
    tree, group_input, group_output = geometry_nodes_tree("Cloud")
    to_volume = tree.nodes.new("GeometryNodeMeshToVolume")
    if hasattr(to_volume, "resolution_mode"):  # 3.4; a menu input in 5.0
        to_volume.resolution_mode = "VOXEL_SIZE"
    else:
        to_volume.inputs["Resolution Mode"].default_value = "Size"
    to_volume.inputs["Voxel Size"].default_value = VOXEL
    tree.links.new(group_input.outputs[0], to_volume.inputs["Mesh"])
    tree.links.new(to_volume.outputs["Volume"], group_output.inputs[0])
    holder.modifiers.new("Nodes", "NODES").node_group = tree
    frame = _frame(native)
    (name,) = frame.sync._volumes
    read = frame.sync._volumes[name]
    assert read.key is None  # written for this sync, not a file of the scene's
    assert read.grids[0].name == "density" and read.grids[0].active_voxels > 15**3
    assert read.native.sample((0.0, 0.0, 0.0))["density"] > 0.0
    assert not [w for w in frame.warnings if "Volume object" in w], frame.warnings


def test_a_packed_volume_is_read_from_its_evaluated_grids(stage, native, tmp_path):
    path = _saved_grids(stage, str(tmp_path))
    volume = bpy.data.volumes.new("Packed")
    volume.filepath = path
    add_object(stage, "Packed", volume)
    bpy.ops.file.pack_all()
    assert volume.packed_file is not None
    os.remove(path)  # only the .blend's packed copy is left
    read = _read(_frame(native), "Packed")
    assert read.key is None  # written from the evaluated grids, not the gone file
    assert read.grids[0].active_voxels >= 20**3


def test_the_export_carries_the_render_settings_and_transform(stage, tmp_path):
    smoke = _smoke(stage)
    smoke.location = (1.0, 2.0, 3.0)
    render = smoke.data.render
    render.space, render.step_size, render.clipping, render.precision = "WORLD", 0.05, 0.02, "HALF"
    depsgraph = bpy.context.evaluated_depsgraph_get()
    # An instance is valid only while the depsgraph's iteration is on it.
    (data,) = [
        volume_object_data(i, str(tmp_path))
        for i in depsgraph.object_instances
        if i.object.type == "VOLUME"
    ]
    assert (data.name, data.written, data.grids) == ("Smoke", True, (("density", "density"),))
    assert os.path.dirname(data.path) == str(tmp_path) and os.path.isfile(data.path)
    assert (data.space, data.precision) == ("WORLD", "HALF")
    assert data.step_size == pytest.approx(0.05) and data.clipping == pytest.approx(0.02)
    assert np.allclose(data.to_world[:3, 3], (1.0, 2.0, 3.0))  # row-major, object -> world


def test_its_clipping_shapes_the_mesh_rays_enter_its_medium_through(stage, native):
    # The mesh is Cycles' (VolumeObject.bound_mesh): the blocks of 8^3 voxels that hold a
    # voxel at least Clipping, and the ones next to them. The cube's voxels of density
    # 0.5: at Clipping 0.4 they count, at 0.6 (Blender's Clipping is at most 1) none does.
    smoke = _smoke(stage)
    smoke.modifiers["Fill"].density = 0.5
    read = _read(_frame(native), "Smoke")
    assert read.data.clipping == pytest.approx(0.001)  # Blender's default
    assert read.native.bound_mesh().triangle_count >= 12
    smoke.data.render.clipping = 0.4
    assert _read(_frame(native), "Smoke").native.bound_mesh().triangle_count >= 12
    # None counts: skipped, and said why.
    smoke.data.render.clipping = 0.6
    frame = _frame(native)
    assert "Smoke" not in frame.sync._volumes and "Smoke" not in frame.sync._instances
    skipped = [w for w in frame.warnings if "Smoke" in w]
    assert skipped and "no voxel of its grids (density) reaches its Clipping (0.6)" in skipped[0]
