"""Opens or imports every output file tests/test_cli.py names and describes its objects."""
import bpy
from scene_tools import describe_objects, empty_scene


def run(paths: list) -> dict:
    described = {}
    for path in paths:
        if path.endswith(".blend"):
            bpy.ops.wm.open_mainfile(filepath=path, load_ui=False)
        else:
            empty_scene()
            bpy.ops.import_scene.gltf(filepath=path, disable_bone_shape=True)
        described[path] = describe_objects()
    return described
