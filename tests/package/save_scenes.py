"""Save the scenes every Blender version's render is compared on, as Blender 3.4 makes
them (the files the other versions open, as an artist's older files are opened):

    blender -b --factory-startup --python-exit-code 1 --python save_scenes.py -- FOLDER

FOLDER/demo.blend: the demo scene (whitted_tools.demo_scene).
FOLDER/nodes.blend: a model made by other people, KHR_texture_transform's test file
from Debian's assimp-testmodels, as Blender's glTF importer builds it (image textures
through Mapping nodes into Principled BSDFs), its images packed, framed as the
material gallery frames third-party models.
"""

import bpy
from whitted_tools.blender import factory_scene
from whitted_tools.cli import script_args
from whitted_tools.demo_scene import build_demo_scene
from whitted_tools.material_scenes import frame_subject, import_file
from whitted_tools.materials_page import THIRD_PARTY_MODELS

NODES_MODEL = THIRD_PARTY_MODELS / "glTF2" / "textureTransform" / "TextureTransformTest.gltf"


def save(path):
    scene = bpy.context.scene
    scene.render.engine = "WHITTED"
    scene.view_settings.view_transform = "Standard"
    bpy.ops.wm.save_as_mainfile(filepath=path)


def main():
    (folder,) = script_args()
    build_demo_scene(factory_scene())
    save(f"{folder}/demo.blend")

    scene = factory_scene()
    import_file(NODES_MODEL)
    frame_subject(scene)
    bpy.ops.file.pack_all()
    save(f"{folder}/nodes.blend")


main()
