"""RenderJob for the live viewport: cached compile, camera override, progressive passes,
the display buffer, live statistics, cancel and worker failures."""

import os
import time

import numpy as np
import pytest
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


def glass_scene():
    """A lit floor under a reflective, refractive pane: every kind of ray."""
    scene = lit_floor_scene()
    scene.set_mesh("pane", *quad(-0.5, 0.5, -0.5, 0.5, 1))
    scene.set_material(
        "glass",
        wn.Material(diffuse=(0, 0, 0), reflectivity=(0.1,) * 3, transmissivity=(0.8,) * 3),
    )
    scene.set_instance("pane", "pane", np.eye(4), ["glass"])
    return scene


def progressive_settings(**overrides):
    values = dict(width=41, height=29, aa_samples=2, tile_size=8, threads=2, progressive=True)
    values.update(overrides)
    return wn.Settings(**values)


@pytest.mark.parametrize("aa_mode", [wn.AntiAliasing.REGULAR, wn.AntiAliasing.JITTERED])
def test_progressive_ends_bit_identical_to_a_render_of_whole_pixels(aa_mode):
    # Exact: the last sample pass sums each pixel's samples in the order, and with the
    # weight, a whole pixel uses; packets off, since a packet may break a coplanar tie
    # differently.
    scene = glass_scene()
    whole = wn.Settings(width=41, height=29, aa_samples=2, aa_mode=aa_mode)
    whole.packets = False
    expected = finish(wn.RenderJob(scene, whole))
    job = wn.RenderJob(scene, progressive_settings(aa_mode=aa_mode, start_pixel_size=16))
    np.testing.assert_array_equal(finish(job), expected)
    np.testing.assert_array_equal(job.display(), expected)


@pytest.mark.parametrize("progressive", [False, True])
def test_a_replay_gives_the_recorded_pixels_without_embree(progressive):
    # Every query answered from the recording (two workers, each the tiles it took; the
    # progressive schedule's passes in order): the same image, bit for bit.
    recorded = wn.RenderJob(
        glass_scene(),
        progressive_settings(progressive=progressive),
        record_stride=1,
        record_results=True,
    )
    expected = finish(recorded)
    rays = recorded.stats()["rays"]
    replay = recorded.replay()
    del recorded  # the replay keeps the recording alive
    np.testing.assert_array_equal(finish(replay).view(np.uint32), expected.view(np.uint32))
    assert replay.stats()["rays"] == rays


def test_frame_counts_passes_up_to_the_schedule():
    job = wn.RenderJob(
        glass_scene(), progressive_settings(width=300, height=200, start_pixel_size=8)
    )
    assert job.frame == 0
    info = job.pass_info()
    assert info == {"pass": 0, "passes": 3 + 4, "pixel_size": 0, "samples": 0}
    job.start()
    frames = []
    while not job.wait(0.001):
        frames.append(job.frame)
    frames.append(job.frame)
    assert frames == sorted(frames)
    assert frames[-1] == info["passes"]
    assert job.pass_info() == {"pass": 7, "passes": 7, "pixel_size": 1, "samples": 4}


def test_display_is_a_new_clamped_float32_copy():
    scene = lit_floor_scene()
    scene.set_material("white", wn.Material(diffuse=(0, 0, 0), emission=(1e6, 2.0, 0.0)))
    job = wn.RenderJob(scene, wn.Settings(width=10, height=6))
    assert not job.display().any()  # nothing rendered yet
    finish(job)
    shown = job.display()
    assert shown.shape == (6, 10, 4)
    assert shown.dtype == np.float32
    assert shown.flags["C_CONTIGUOUS"] and shown.flags["OWNDATA"]
    np.testing.assert_array_equal(shown[..., 0], 65000.0)  # within half-float range
    np.testing.assert_array_equal(shown[..., 1], 2.0)
    assert job.image()[0, 0, 0] == 1e6  # the render itself is not clamped
    shown[...] = -1.0
    assert job.display()[0, 0, 1] == 2.0  # a copy, not a view
    with pytest.raises(ValueError, match="kind"):
        job.display("depth")


def test_display_cost_is_a_heat_map_of_rays_per_pixel():
    scene = glass_scene()  # the pane costs more rays than the bare floor
    job = wn.RenderJob(scene, wn.Settings(width=24, height=24))
    finish(job)
    heat = job.display("cost")
    assert heat.shape == (24, 24, 4)
    assert heat.dtype == np.float32
    np.testing.assert_array_equal(heat[..., 3], 1.0)
    cost = job.cost_image()
    luminance = heat[..., :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    assert luminance[cost == cost.max()].min() > luminance[cost == cost.min()].max()
    hottest = heat[cost == cost.max()][0]
    assert hottest[0] > 0.9 and hottest[2] < 0.1  # yellow
    coolest = heat[cost == cost.min()][0]
    assert coolest[2] > hottest[2]  # towards blue


def test_settings_check_the_progressive_start_size():
    assert wn.Settings(progressive=True, start_pixel_size=64).start_pixel_size == 64
    with pytest.raises(ValueError, match="power of two"):
        wn.Settings(progressive=True, start_pixel_size=12)
    with pytest.raises(ValueError, match="start_pixel_size"):
        wn.Settings(start_pixel_size=128)


def test_a_failing_worker_raises_from_wait_and_leaves_the_scene_usable():
    scene = glass_scene()
    settings = wn.Settings(width=512, height=512, tile_size=8, threads=2)
    settings.fault_tile = 100
    job = wn.RenderJob(scene, settings)
    job.start()
    with pytest.raises(MemoryError):
        while not job.wait(1.0):
            pass
    stats = job.stats()
    assert stats["cancelled"]
    assert stats["error"] == "std::bad_alloc"
    del job
    again = wn.RenderJob(scene, wn.Settings(width=16, height=16))
    finish(again)
    assert again.stats()["error"] == ""
    assert not again.stats()["cancelled"]


def test_stats_count_rays_while_the_render_runs():
    job = wn.RenderJob(
        glass_scene(), wn.Settings(width=2000, height=2000, aa_samples=3, tile_size=16, threads=2)
    )
    job.start()
    deadline = time.perf_counter() + 10
    while job.stats()["rays"]["camera"] == 0 and time.perf_counter() < deadline:
        time.sleep(0.005)
    assert not job.wait(0.0)  # still running
    assert job.stats()["rays"]["camera"] > 0
    job.cancel()
    assert job.wait(5.0)


@pytest.mark.parametrize("progressive", [False, True])
def test_a_cancelled_render_stops_well_within_a_second(progressive):
    settings = wn.Settings(
        width=4000, height=4000, aa_samples=4, threads=2, progressive=progressive
    )
    job = wn.RenderJob(glass_scene(), settings)
    job.start()
    assert not job.wait(0.05)
    t0 = time.perf_counter()
    job.cancel()
    assert job.wait(1.0)
    assert time.perf_counter() - t0 < 0.5
    assert job.stats()["cancelled"]


def _thread_nice_values():
    # Field 19 of /proc/<pid>/task/<tid>/stat is the thread's nice value (after the
    # command name in parentheses, which may hold spaces). A worker may exit between
    # the listing and the read: its entry is gone, and it is skipped.
    values = []
    for tid in os.listdir("/proc/self/task"):
        try:
            with open(f"/proc/self/task/{tid}/stat", encoding="ascii") as stat:
                fields = stat.read().rsplit(")", 1)[1].split()
        except (FileNotFoundError, ProcessLookupError):
            continue
        values.append(int(fields[16]))
    return values


def test_workers_run_at_the_niceness_asked_and_render_the_same_pixels():
    scene = glass_scene()
    expected = finish(wn.RenderJob(scene, progressive_settings()))
    settings = progressive_settings(width=401, height=301, aa_samples=4)
    settings.worker_nice = 7
    job = wn.RenderJob(scene, settings)
    job.start()
    seen = set()
    while not job.wait(0.002):
        seen.update(_thread_nice_values())
    assert 7 in seen  # the workers, while they ran
    assert os.getpriority(os.PRIO_PROCESS, 0) == 0  # this thread is untouched
    small = progressive_settings()
    small.worker_nice = 7
    np.testing.assert_array_equal(finish(wn.RenderJob(scene, small)), expected)
    small.worker_nice = 20
    with pytest.raises(ValueError, match="worker_nice"):
        wn.RenderJob(scene, small)
