"""The renders and compositor trees of passes-page (in Blender 3.4; passes-page's).

Blender side of whitted_tools passes-page (docs/PASSES.md): renders the demo scene
with every pass Whitted writes into a multilayer EXR, the two compositing examples
(Combined rebuilt from the light passes; only what the mirror reflects tinted).

    blender -b --factory-startup --python-exit-code 1 --python tools/whitted_tools/__main__.py \\
        -- passes-render --out DIR [--resolution W H]

Writes DIR/passes.exr (every pass), DIR/rebuild.exr and DIR/tint.exr (the composites).
"""

import argparse
from pathlib import Path

import bpy

from whitted_tools import demo_scene
from whitted_tools.blender import factory_scene
from whitted_tools.render import enable_every_pass, use_multilayer_exr
from whitted_tools.verbs import prog

# The tint the second compositing example gives to what the mirror reflects.
TINT = (1.0, 0.45, 0.1, 1.0)


def number_objects(scene):
    """Pass indices 1, 2, ... for the demo's objects and materials, by name (they are all
    0 in the demo, which would make the index passes black)."""
    meshes = sorted((o for o in scene.objects if o.type == "MESH"), key=lambda o: o.name)
    for index, obj in enumerate(meshes, start=1):
        obj.pass_index = index
    for index, material in enumerate(sorted(bpy.data.materials, key=lambda m: m.name), start=1):
        material.pass_index = index


def set_output(scene, path, multilayer):
    """32-bit float OpenEXR: every pass (multilayer), or the composite's RGBA."""
    settings = scene.render.image_settings
    if multilayer:
        use_multilayer_exr(settings)
    else:
        settings.file_format, settings.color_depth = "OPEN_EXR", "32"
    scene.render.filepath = str(path)


def node(tree, kind, location, **inputs):
    n = tree.nodes.new(kind)
    n.location = location
    for name, value in inputs.items():
        setattr(n, name, value)
    return n


def mix(tree, blend, a, b, location):
    """A MixRGB node of factor 1: `blend`(a, b), each an output socket or a colour."""
    m = node(tree, "CompositorNodeMixRGB", location, blend_type=blend)
    m.inputs[0].default_value = 1.0
    for socket, value in ((m.inputs[1], a), (m.inputs[2], b)):
        if isinstance(value, tuple):
            socket.default_value = value
        else:
            tree.links.new(value, socket)
    return m.outputs[0]


def rebuild_tree(scene, result):
    """Combined rebuilt as Blender's manual recombines Cycles' passes: Color * (Direct
    + Indirect) for diffuse, glossy and transmission, plus Volume Direct and Indirect,
    Emission and Environment."""
    tree = scene.node_tree
    tree.nodes.clear()
    layers = node(tree, "CompositorNodeRLayers", (0, 0))
    out = {socket.name: socket for socket in layers.outputs}
    out = {short: out[result.blender_name(short)] for short in result.LONG_NAMES}
    total = None
    for i, component in enumerate(("Diff", "Gloss", "Trans")):
        light = mix(tree, "ADD", out[f"{component}Dir"], out[f"{component}Ind"], (300, -200 * i))
        term = mix(tree, "MULTIPLY", out[f"{component}Col"], light, (500, -200 * i))
        total = term if total is None else mix(tree, "ADD", total, term, (700, -200 * i))
    for i, name in enumerate(("VolumeDir", "VolumeInd", "Emit", "Env")):
        total = mix(tree, "ADD", total, out[name], (900 + 200 * i, 0))
    composite = node(tree, "CompositorNodeComposite", (1700, 0), use_alpha=False)
    tree.links.new(total, composite.inputs["Image"])


def tint_tree(scene, result):
    """Only what the mirror reflects tinted: Combined - G + TINT * G, where G =
    GlossCol * GlossInd is the reflected light in Combined."""
    tree = scene.node_tree
    tree.nodes.clear()
    layers = node(tree, "CompositorNodeRLayers", (0, 0))
    image = layers.outputs["Image"]
    out = {socket.name: socket for socket in layers.outputs}
    out = {short: out[result.blender_name(short)] for short in result.LONG_NAMES}
    reflected = mix(tree, "MULTIPLY", out["GlossCol"], out["GlossInd"], (300, 0))
    tinted = mix(tree, "MULTIPLY", reflected, TINT, (500, -200))
    rest = mix(tree, "SUBTRACT", image, reflected, (500, 0))
    total = mix(tree, "ADD", rest, tinted, (700, 0))
    composite = node(tree, "CompositorNodeComposite", (900, 0), use_alpha=False)
    tree.links.new(total, composite.inputs["Image"])


def render(scene, path, multilayer=True):
    set_output(scene, path, multilayer)
    bpy.ops.render.render(write_still=True)


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, type=Path)
    parser.add_argument("--resolution", nargs=2, type=int, default=(320, 240))
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    scene = demo_scene.build_demo_scene(factory_scene())
    from whitted import result

    scene.render.engine = "WHITTED"
    scene.render.resolution_x, scene.render.resolution_y = args.resolution
    scene.render.resolution_percentage = 100
    view_layer = scene.view_layers[0]
    enable_every_pass(view_layer, result, contribution_depth=3)
    number_objects(scene)
    scene.render.use_compositing = False
    render(scene, args.out / "passes.exr")

    scene.use_nodes = True
    scene.render.use_compositing = True
    rebuild_tree(scene, result)
    render(scene, args.out / "rebuild.exr", multilayer=False)
    tint_tree(scene, result)
    render(scene, args.out / "tint.exr", multilayer=False)
    scene.render.use_compositing = False

    print(f"passes_render: wrote {args.out}")
