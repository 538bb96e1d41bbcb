"""Cryptomatte (issue 13): Object, Material and Asset layers at the view layer's depth,
decoded by Blender's own Cryptomatte compositor node and compared with Cycles' matte
of the same object; the multilayer EXR read back with the OpenEXR library."""

import json
import subprocess

import bpy
import numpy as np
import pytest
from test_passes import VENV_PYTHON
from whitted import cryptomatte
from whitted_tools.render import use_multilayer_exr

WIDTH, HEIGHT = 96, 72
SUBJECT = "Mirror Sphere"  # a demo object with a parent-free name
# A matte value differs from Cycles' by more than this only where the edge samples
# differ (Cycles: 64 random samples; Whitted: a 4 x 4 grid per pixel).
TOLERANCE = 0.25

# .venv's CPython: the header fields and the channels of a multilayer EXR as JSON and
# .npz (the OpenEXR bindings, not our code).
_READ = """
import json, sys
import numpy as np
import OpenEXR
with OpenEXR.File(sys.argv[1], separate_channels=True) as exr:
    header, channels = {}, {}
    for part in exr.parts:
        header.update({k: v for k, v in part.header.items() if isinstance(v, str)})
        channels.update({n: c.pixels.astype(np.float32) for n, c in part.channels.items()})
    np.savez(sys.argv[2], **channels)
    print(json.dumps(header))
"""


@pytest.fixture
def demo(empty_scene, demo_scene_module):
    scene = demo_scene_module.build_demo_scene(empty_scene)
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    scene.whitted.aa_mode = "ADAPTIVE"
    scene.whitted.aa_depth = 2  # coverage from a 4 x 4 grid
    layer = scene.view_layers[0]
    layer.use_pass_cryptomatte_object = True
    layer.use_pass_cryptomatte_material = True
    layer.use_pass_cryptomatte_asset = True
    layer.pass_cryptomatte_depth = 4
    scene.cycles.samples = 64
    scene.cycles.use_denoising = False
    return scene


def _matte_tree(scene, name):
    """The compositor shows Blender's Cryptomatte node's matte of object `name`."""
    if bpy.app.version >= (5, 0, 0):
        tree = bpy.data.node_groups.new("Matte", "CompositorNodeTree")
        tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
        scene.compositing_node_group = tree
        output = tree.nodes.new("NodeGroupOutput")
    else:
        scene.use_nodes = True
        tree = scene.node_tree
        tree.nodes.clear()
        output = tree.nodes.new("CompositorNodeComposite")
        output.use_alpha = False
    layers = tree.nodes.new("CompositorNodeRLayers")
    node = tree.nodes.new("CompositorNodeCryptomatteV2")
    node.source = "RENDER"
    node.scene = scene
    node.layer_name = f"{scene.view_layers[0].name}.CryptoObject"
    node.matte_id = name
    tree.links.new(layers.outputs["Image"], node.inputs["Image"])
    tree.links.new(node.outputs["Matte"], output.inputs[0])


def _matte(scene, engine, path):
    """The matte the compositor made of `scene` rendered by `engine`, float[h, w]."""
    scene.render.engine = engine
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):
        settings.media_type = "IMAGE"
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(str(path))
    pixels = np.array(image.pixels[:], dtype=np.float32).reshape(HEIGHT, WIDTH, 4)
    bpy.data.images.remove(image)
    return pixels[..., 0]


def test_blenders_node_decodes_our_matte_as_cycles_matte(demo, tmp_path):
    _matte_tree(demo, SUBJECT)
    ours = _matte(demo, "WHITTED", tmp_path / "whitted.exr")
    theirs = _matte(demo, "CYCLES", tmp_path / "cycles.exr")
    assert 0.01 < (theirs > 0.5).mean() < 0.5  # the subject is in the frame
    agree = np.abs(ours - theirs) <= TOLERANCE
    assert agree.mean() >= 0.99, f"{agree.mean():.4f} of pixels agree"
    # Anti-aliased edges: some pixels are partly covered.
    assert ((ours > 0.05) & (ours < 0.95)).any()


def test_exr_holds_the_layers_and_their_metadata(demo, tmp_path):
    demo.render.engine = "WHITTED"
    use_multilayer_exr(demo.render.image_settings)
    path = tmp_path / "crypto.exr"
    demo.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    out = str(path) + ".npz"
    run = subprocess.run(
        [VENV_PYTHON, "-c", _READ, str(path), out], check=True, capture_output=True, text=True
    )
    header = json.loads(run.stdout)
    with np.load(out) as data:
        channels = {name: data[name] for name in data.files}
    view_layer = demo.view_layers[0].name
    for kind in cryptomatte.KINDS:
        # depth 4: two passes of two ranks, RGBA each, named as Blender names them.
        for name in cryptomatte.pass_names(kind, 4):
            for c in "RGBA":
                assert f"{view_layer}.{name}.{c}" in channels
        expected = cryptomatte.metadata(view_layer, kind, [])
        for field in expected:
            assert field in header, field
        key = next(iter(expected)).split("/")[1]
        assert header[f"cryptomatte/{key}/name"] == f"{view_layer}.{kind}"
        assert header[f"cryptomatte/{key}/hash"] == "MurmurHash3_32"
        assert header[f"cryptomatte/{key}/conversion"] == "uint32_to_float32"
    # The object layer's manifest names the subject with its id, and rank 0 of a pixel
    # at the subject's centre is that id with full coverage.
    key = next(iter(cryptomatte.metadata(view_layer, "CryptoObject", []))).split("/")[1]
    manifest = json.loads(header[f"cryptomatte/{key}/manifest"])
    assert manifest[SUBJECT] == f"{cryptomatte.id_bits(SUBJECT):08x}"
    ids = channels[f"{view_layer}.CryptoObject00.R"]
    coverage = channels[f"{view_layer}.CryptoObject00.G"]
    subject = ids == np.float32(cryptomatte.id_float(SUBJECT))
    assert subject.any()
    assert (coverage[subject] > 0.0).all() and (coverage[subject] == 1.0).any()
    # Ranks are sorted: rank 1's coverage never exceeds rank 0's.
    assert (channels[f"{view_layer}.CryptoObject00.A"] <= coverage + 1e-6).all()


def test_a_moving_objects_matte_smears_as_cycles(empty_scene, tmp_path):
    # Motion blur spreads an object's coverage as it spreads its colour: the cube moving
    # 1 m within the shutter covers a streak partly, in Whitted's matte as in Cycles'.
    from whitted_tools.camera_scenes import cube_crossing

    cube_crossing(empty_scene)
    empty_scene.render.resolution_x, empty_scene.render.resolution_y = WIDTH, HEIGHT
    layer = empty_scene.view_layers[0]
    layer.use_pass_cryptomatte_object = True
    layer.pass_cryptomatte_depth = 4
    empty_scene.whitted.aa_mode = "ADAPTIVE"
    empty_scene.whitted.aa_depth = 3  # coverage from an 8 x 8 grid over the shutter
    empty_scene.cycles.samples = 64
    empty_scene.cycles.use_denoising = False
    _matte_tree(empty_scene, "Cube")
    ours = _matte(empty_scene, "WHITTED", tmp_path / "whitted.exr")
    theirs = _matte(empty_scene, "CYCLES", tmp_path / "cycles.exr")
    partial = ((ours > 0.05) & (ours < 0.95)).sum()
    partial_cycles = ((theirs > 0.05) & (theirs < 0.95)).sum()
    agree = np.abs(ours - theirs) <= TOLERANCE
    print(
        f"\nmoving cube's matte: {agree.mean():.4f} of pixels agree; partly covered "
        f"{partial} (Cycles {partial_cycles})"
    )
    assert agree.mean() >= 0.99
    # The streak's pixels are partly covered (sharp, only its outline would be).
    assert partial > 0.7 * partial_cycles
