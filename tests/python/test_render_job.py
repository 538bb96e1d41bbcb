"""RenderJob for the live viewport: cached compile, camera override, progressive passes,
the display buffer, live statistics, cancel and worker failures."""

import numpy as np
import whitted_native as wn
from test_scene import finish, lit_floor_scene, looking_down, quad


def test_an_unchanged_scene_or_a_new_camera_reuses_the_compiled_scene():
    scene = lit_floor_scene()
    assert scene.top_level_builds == 0
    first = wn.RenderJob(scene, wn.Settings(width=8, height=8))
    assert first.stats()["top_level_built"]
    assert scene.top_level_builds == 1
    scene.camera = looking_down(3.0, 0.5)
    again = wn.RenderJob(scene, wn.Settings(width=8, height=8))
    stats = again.stats()
    assert not stats["top_level_built"]
    assert stats["compile_seconds"] < 1e-3
    assert scene.top_level_builds == 1


def test_shading_changes_reuse_the_top_level_bvh_and_geometry_changes_rebuild_it():
    scene = lit_floor_scene()
    before = finish(wn.RenderJob(scene, wn.Settings(width=8, height=8)))
    scene.set_material("white", wn.Material(diffuse=(0.25, 0.25, 0.25), ambient=0.0))
    scene.set_light("fill", wn.Light(type=wn.LightType.SUN, color=(1, 1, 1)))
    scene.remove_light("fill")
    scene.background = (0.1, 0.2, 0.3)
    scene.ambient = (0.01, 0.01, 0.01)
    job = wn.RenderJob(scene, wn.Settings(width=8, height=8))
    after = finish(job)
    assert not job.stats()["top_level_built"]
    assert scene.top_level_builds == 1
    # The material change reached the image (ambient 0: exactly half the radiance).
    np.testing.assert_allclose(after[..., :3], 0.5 * before[..., :3], rtol=1e-6)
    scene.set_instance("floor", "floor", np.eye(4), ["white"])
    assert wn.RenderJob(scene, wn.Settings(width=8, height=8)).stats()["top_level_built"]
    assert scene.top_level_builds == 2
    scene.set_mesh("more", *quad(0, 1, 0, 1, 1))
    wn.RenderJob(scene, wn.Settings(width=8, height=8))
    assert scene.top_level_builds == 3


def test_a_camera_passed_to_the_job_overrides_the_scene_camera():
    scene = lit_floor_scene()
    settings = wn.Settings(width=12, height=12)
    wide = looking_down(5.0, 1.0)
    narrow = looking_down(5.0, 0.25)
    scene.camera = narrow
    expected = finish(wn.RenderJob(scene, settings))
    scene.camera = wide
    overridden = finish(wn.RenderJob(scene, settings, camera=narrow))
    np.testing.assert_array_equal(overridden, expected)
    assert not np.array_equal(finish(wn.RenderJob(scene, settings)), expected)
    assert scene.top_level_builds == 1
