"""The binding API without Blender: scenes from numpy arrays, rendered and checked."""

import math
import time

import numpy as np
import pytest
import whitted_native as wn


def quad(x0, x1, y0, y1, z):
    positions = np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]], np.float32)
    triangles = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
    return positions, triangles


def looking_down(height, half):
    to_world = np.eye(4)
    to_world[2, 3] = height
    return wn.Camera(to_world=to_world, window=(-half, half, -half, half), clip_end=1e4)


def finish(job):
    job.start()
    while not job.wait(1.0):
        pass
    return job.image()


def point_light(power):
    return wn.Light(type=wn.LightType.POINT, color=(power,) * 3, position=(0, 0, 2))


def lit_floor_scene():
    scene = wn.Scene()
    scene.set_mesh("floor", *quad(-10, 10, -10, 10, 0))
    scene.set_material("white", wn.Material(diffuse=(0.5, 0.5, 0.5), ambient=0.0))
    scene.set_instance("floor", "floor", np.eye(4), ["white"])
    scene.set_light("key", point_light(40))
    scene.camera = looking_down(5.0, 1.0)
    scene.background = (0.0, 0.0, 0.0)
    return scene


def test_lambertian_floor_matches_the_inverse_square_cosine_law():
    image = finish(wn.RenderJob(lit_floor_scene(), wn.Settings(width=33, height=33)))
    assert image.shape == (33, 33, 4)
    assert image.dtype == np.float32
    # The centre pixel looks straight down at the point under the light.
    assert image[16, 16, 0] == pytest.approx(0.5 / math.pi * 40 / 4, rel=1e-4)
    # A corner: camera ray through the window corner meets the floor at (+-x, +-y) * 5.
    x = (-1 + 2 * 0.5 / 33) * 5  # centre of column 0 in the window [-1, 1], on the floor
    r2 = 2 * x * x + 4
    expected = 0.5 / math.pi * 40 * (2 / math.sqrt(r2)) / r2
    assert image[0, 0, 1] == pytest.approx(expected, rel=1e-3)
    assert np.all(image[..., 3] == 1.0)


def test_rows_run_bottom_to_top_like_blenders_render_result():
    scene = lit_floor_scene()
    scene.remove_light("key")
    scene.set_mesh("marker", *quad(-10, 10, -10, 0, 0.5))  # covers the lower half (y < 0)
    # A marker: its emission shows, it lights nothing (the floor stays black).
    glow = wn.Material(
        diffuse=(0, 0, 0),
        ambient=0,
        emission=(1, 0, 0),
        emission_sampling=wn.EmissionSampling.NONE,
    )
    scene.set_material("glow", glow)
    scene.set_instance("marker", "marker", np.eye(4), ["glow"])
    image = finish(wn.RenderJob(scene, wn.Settings(width=8, height=8)))
    assert np.all(image[:4, :, 0] == 1.0)  # first rows: the bottom of the picture
    assert np.all(image[4:, :, 0] == 0.0)


def test_an_emissive_mesh_lights_the_floor_and_the_report_names_it():
    scene = lit_floor_scene()
    scene.remove_light("key")
    scene.set_mesh("panel", *quad(-1, 1, -1, 1, 2))
    for sampling in ("NONE", "BOTH"):
        glow = wn.Material(
            diffuse=(0, 0, 0),
            ambient=0,
            emission=(3, 3, 3),
            emission_sampling=getattr(wn.EmissionSampling, sampling),
        )
        assert glow.emission_sampling == getattr(wn.EmissionSampling, sampling)
        scene.set_material("glow", glow)
        scene.set_instance(
            "panel", "panel", np.eye(4), ["glow"], visibility=wn.RayVisibility.SHADOW
        )
        job = wn.RenderJob(scene, wn.Settings(width=8, height=8, emitter_samples=3))
        image = finish(job)
        decision = next(
            e for e in job.stats()["effects"] if e["name"] == "emissive meshes as lights"
        )
        if sampling == "NONE":
            assert np.all(image[..., 0] == 0.0)
            assert decision == {
                "name": "emissive meshes as lights",
                "on": False,
                "why": "no mesh emits with its Emission Sampling on",
            }
        else:
            assert np.all(image[..., 0] > 0.0)
            assert decision["on"] and decision["why"] == "1 object, 2 triangles"
            assert job.stats()["rays"]["shadow"] > 0


def test_replacing_one_light_changes_only_its_contribution():
    scene = lit_floor_scene()
    before = finish(wn.RenderJob(scene, wn.Settings(width=16, height=16)))
    scene.set_light("key", point_light(80))
    after = finish(wn.RenderJob(scene, wn.Settings(width=16, height=16)))
    np.testing.assert_allclose(after[..., :3], 2 * before[..., :3], rtol=1e-6)


def test_instances_share_one_mesh():
    scene = wn.Scene()
    scene.set_mesh("tile", *quad(-0.4, 0.4, -0.4, 0.4, 0))
    scene.set_material("glow", wn.Material(diffuse=(0, 0, 0), ambient=0, emission=(1, 1, 1)))
    for i in range(100):
        transform = np.eye(4)
        transform[0, 3] = (i % 10) - 4.5
        transform[1, 3] = (i // 10) - 4.5
        scene.set_instance(f"tile.{i}", "tile", transform, ["glow"])
    assert scene.mesh_count == 1
    assert scene.instance_count == 100
    scene.camera = looking_down(10, 0.5)
    job = wn.RenderJob(scene, wn.Settings(width=100, height=100))
    image = finish(job)
    stats = job.stats()
    assert stats["instances"] == 100
    assert stats["triangles"] == 200
    # 80% of the floor is covered by tiles (0.8 x 0.8 of each unit cell).
    assert image[..., 0].mean() == pytest.approx(0.64, abs=0.03)


def test_stats_count_rays_by_type():
    scene = lit_floor_scene()
    scene.set_material("white", wn.Material(diffuse=(0.5, 0.5, 0.5), reflectivity=(0.5, 0.5, 0.5)))
    job = wn.RenderJob(scene, wn.Settings(width=10, height=10, aa_samples=2, max_depth=3))
    finish(job)
    stats = job.stats()
    assert stats["rays"]["camera"] == 400
    assert stats["rays"]["reflection"] == 400  # each reflects once, into the sky
    assert stats["rays"]["shadow"] == 400
    assert stats["rays"]["refraction"] == 0
    assert stats["rays"]["total"] == 1200


def test_waves_are_a_setting_the_statistics_report():
    scene = lit_floor_scene()
    scene.set_material("white", wn.Material(diffuse=(0.5, 0.5, 0.5), reflectivity=(0.5, 0.5, 0.5)))
    assert wn.Settings().waves is True  # the default; the recursion is the reference
    images = {}
    for waves in (False, True):
        settings = wn.Settings(width=10, height=10, aa_samples=2)
        settings.waves = waves
        job = wn.RenderJob(scene, settings)
        images[waves] = finish(job)
        stats = job.stats()
        assert stats["waves"] is waves
        assert (stats["wave_bytes"] > 0) is waves
        assert stats["rays"]["total"] == 1200
    np.testing.assert_allclose(images[True], images[False], rtol=1e-6, atol=1e-7)


@pytest.mark.parametrize(
    ("positions", "triangles", "message"),
    [
        (np.zeros((4, 2), np.float32), np.zeros((1, 3), np.uint32), "positions"),
        (np.zeros((4, 3), np.float32), np.zeros((3,), np.uint32), "triangles"),
        (np.array([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]]), np.array([[0, 1, 2]]), "NaN"),
        (np.array([[0, 0, 0], [1, 0, 0], [0, np.inf, 0]]), np.array([[0, 1, 2]]), "NaN"),
        (np.zeros((3, 3), np.float32), np.array([[0, 1, 5]], np.uint32), "vertex"),
    ],
)
def test_bad_mesh_arrays_raise_value_error(positions, triangles, message):
    with pytest.raises(ValueError, match=message):
        wn.Scene().set_mesh("bad", positions, triangles)


def test_bad_normals_and_slots_shapes_raise():
    scene = wn.Scene()
    positions, triangles = quad(0, 1, 0, 1, 0)
    with pytest.raises(ValueError, match="normals"):
        scene.set_mesh("m", positions, triangles, normals=np.zeros((2, 3), np.float32))
    with pytest.raises(ValueError, match="material_slots"):
        scene.set_mesh("m", positions, triangles, material_slots=np.zeros(5, np.int32))


def test_bad_vertex_normals_raise():
    positions, triangles = quad(0, 1, 0, 1, 0)
    with pytest.raises(ValueError, match="vertex_normals"):
        wn.Mesh(positions, triangles, vertex_normals=np.zeros((2, 3), np.float32))
    with pytest.raises(ValueError, match="not both"):
        wn.Mesh(
            positions,
            triangles,
            normals=np.ones((2, 3, 3), np.float32),
            vertex_normals=np.ones((4, 3), np.float32),
        )


def smooth_dome():
    """A coarse dome of shared vertices over the floor, and its (radial) vertex normals."""
    rings, segments = 4, 8
    theta = np.linspace(0.0, 0.5 * math.pi, rings + 1)[:, None]
    phi = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)[None, :]
    unit = np.stack(
        np.broadcast_arrays(
            np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)
        ),
        axis=-1,
    ).reshape(-1, 3)
    r, k = np.meshgrid(np.arange(1, rings), np.arange(segments), indexing="ij")
    a, b = r * segments + k, (r + 1) * segments + k
    c, d = (r + 1) * segments + (k + 1) % segments, r * segments + (k + 1) % segments
    cap = np.stack(
        [
            np.zeros(segments, int),
            segments + np.arange(segments),
            segments + (np.arange(segments) + 1) % segments,
        ],
        axis=-1,
    )
    triangles = np.concatenate(
        [cap, np.stack([a, b, d], -1).reshape(-1, 3), np.stack([b, c, d], -1).reshape(-1, 3)]
    ).astype(np.uint32)
    return unit.astype(np.float32), triangles


def test_a_mesh_moves_into_the_scene_and_vertex_normals_shade_as_corner_normals():
    positions, triangles = smooth_dome()

    def render(**mesh):
        scene = lit_floor_scene()
        scene.set_mesh("dome", positions, triangles, **mesh)
        scene.set_instance("dome", "dome", np.eye(4), ["white"])
        return finish(wn.RenderJob(scene, wn.Settings(width=24, height=24)))

    by_corner = render(normals=positions[triangles])
    by_vertex = render(vertex_normals=positions)
    np.testing.assert_array_equal(by_vertex, by_corner)
    assert not np.array_equal(render(), by_corner)  # flat: the normals do shade

    # A Mesh made first (so the caller can free its arrays) renders the same; the scene
    # takes its arrays, leaving it empty.
    mesh = wn.Mesh(positions, triangles, vertex_normals=positions)
    assert (mesh.vertex_count, mesh.triangle_count) == (len(positions), len(triangles))
    scene = lit_floor_scene()
    scene.set_mesh("dome", mesh)
    assert (mesh.vertex_count, mesh.triangle_count) == (0, 0)
    with pytest.raises(ValueError, match="already set"):
        scene.set_mesh("again", mesh)
    scene.set_instance("dome", "dome", np.eye(4), ["white"])
    image = finish(wn.RenderJob(scene, wn.Settings(width=24, height=24)))
    np.testing.assert_array_equal(image, by_vertex)


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"color": (np.inf, 1, 1)}, "light colour, position and axes must be finite"),
        ({"direction": (0, 0, 0)}, "light direction must not be zero"),
        ({"spot_size": np.nan}, "light spot size, blend and area size must be finite"),
        ({"radius": np.inf}, "light radius, angle and spread must be finite"),
        ({"samples": 65}, "light samples must be between 1 and 64"),
    ],
)
def test_the_core_refuses_what_cannot_be_a_light(fields, message):
    with pytest.raises(ValueError, match=message):
        wn.Light(**fields)


def test_the_core_clamps_a_light_to_the_nearest_one():
    light = wn.Light(color=(-1, 2, 3), direction=(0, 0, -4), radius=-1, angle=7)
    assert light.color == (0, 2, 3)
    assert light.direction == (0, 0, -1)
    assert light.radius == 0
    assert light.angle == pytest.approx(np.pi)


def test_bad_values_raise_instead_of_crashing():
    scene = wn.Scene()
    with pytest.raises(ValueError):
        scene.set_instance("i", "m", np.full((4, 4), np.nan))
    with pytest.raises(ValueError):
        scene.set_instance("i", "m", np.eye(3))
    with pytest.raises(ValueError):
        wn.Material(diffuse=(np.nan, 0, 0))
    with pytest.raises(ValueError):
        wn.Material(ior=0.0)
    with pytest.raises(ValueError):
        wn.Light(color=(np.inf, 1, 1))
    with pytest.raises(ValueError):
        wn.Settings(width=100000)
    with pytest.raises(ValueError):
        wn.Settings(width=60000, height=60000)
    with pytest.raises(ValueError, match="missing mesh"):
        scene.set_instance("i", "nothing", np.eye(4))
        wn.RenderJob(scene, wn.Settings(width=4, height=4))
    with pytest.raises(ValueError, match="no light"):
        scene.remove_light("nothing")


def test_cancel_returns_within_a_fifth_of_a_second():
    scene = lit_floor_scene()
    job = wn.RenderJob(scene, wn.Settings(width=4000, height=4000, aa_samples=4, threads=2))
    job.start()
    assert not job.wait(0.02)
    t0 = time.perf_counter()
    job.cancel()
    assert job.wait(5.0)
    assert time.perf_counter() - t0 < 0.2
    assert job.stats()["cancelled"]


def test_tiles_cover_the_image_and_match_it():
    job = wn.RenderJob(lit_floor_scene(), wn.Settings(width=40, height=24, tile_size=16))
    image = finish(job)
    tiles = job.take_finished_tiles()
    assert sum(w * h for _, _, w, h in tiles) == 40 * 24
    for x, y, w, h in tiles:
        expected = image[y : y + h, x : x + w].reshape(-1, 4)
        np.testing.assert_array_equal(job.tile(x, y, w, h), expected)
    with pytest.raises(ValueError):
        job.tile(30, 0, 16, 16)


def test_analysis_names_what_it_skips_and_the_plain_tracer_changes_no_pixel():
    scene = lit_floor_scene()
    pruned = wn.RenderJob(scene, wn.Settings(width=16, height=16, cutoff=0.0))
    plain = wn.RenderJob(
        scene, wn.Settings(width=16, height=16, analysis=False, feeler_pruning=False)
    )
    np.testing.assert_array_equal(finish(pruned), finish(plain))
    off = {"name": "reflection", "on": False, "why": "no reflective or transmissive material"}
    assert off in pruned.stats()["effects"]
    assert [e["name"] for e in pruned.stats()["effects"]] == [
        "shadows",
        "emissive meshes as lights",
        "world light",
        "reflection",
        "glossy reflection",
        "refraction",
        "translucency",
        "volumes",
        "shadow catcher",
        "hair and points",
        "light linking",
        "lamps seen by rays",
        "lamp node trees",
        "ray-traced nodes",
        "UDIM tiles",
        "depth of field",
        "motion blur",
        "pruning",
    ]
    assert plain.stats()["effects"] == [
        {"name": "analysis", "on": False, "why": "every effect on"},
        {"name": "pruning", "on": False, "why": "a feeler to every light sample"},
    ]
    # A zero coefficient is never traced, with the analysis or without.
    assert pruned.stats()["rays"]["reflection"] == plain.stats()["rays"]["reflection"] == 0
    assert set(pruned.stats()["shadow_rays_skipped"]) == {"backfacing", "unlit", "cutoff"}


def test_a_panorama_is_bound_with_its_projection():
    fisheye = wn.Panorama(type=wn.PanoramaType.FISHEYE_EQUIDISTANT, fisheye_fov=math.pi)
    # The centre looks down the view axis; the rim of a 180-degree fisheye at 90 degrees;
    # outside the circle there is no direction.
    assert fisheye.direction(0.5, 0.5) == pytest.approx((0.0, 0.0, -1.0), abs=1e-6)
    assert fisheye.direction(0.5, 1.0) == pytest.approx((0.0, 1.0, 0.0), abs=1e-6)
    assert fisheye.direction(0.0, 0.0) is None
    camera = wn.Camera(
        projection=wn.Projection.PANORAMIC, window=(0.0, 1.0, 0.0, 1.0), panorama=fisheye
    )
    assert camera.projection == wn.Projection.PANORAMIC
    with pytest.raises(ValueError, match="PANORAMIC"):
        wn.Camera(panorama=fisheye)  # a perspective camera with a panorama
    with pytest.raises(ValueError, match="PANORAMIC"):
        wn.Camera(projection=wn.Projection.PANORAMIC)
    with pytest.raises(ValueError, match="sensor"):
        wn.Panorama(sensor=(0.0, 24.0))


def test_outside_a_fisheyes_circle_is_opaque_black():
    # As Cycles: the corners of a square fisheye image see nothing and cover the pixel.
    scene = lit_floor_scene()
    to_world = np.eye(4)
    to_world[2, 3] = 5.0
    scene.camera = wn.Camera(
        to_world=to_world,
        projection=wn.Projection.PANORAMIC,
        window=(0.0, 1.0, 0.0, 1.0),
        panorama=wn.Panorama(type=wn.PanoramaType.FISHEYE_EQUIDISTANT),
        clip_end=1e4,
    )
    settings = wn.Settings(width=16, height=16, aa_samples=1, transparent_background=True)
    image = finish(wn.RenderJob(scene, settings))
    assert image[0, 0].tolist() == [0.0, 0.0, 0.0, 1.0]
    assert image[8, 8, 0] > 0.1  # the floor under the camera, lit


def test_the_shutter_is_bound_with_the_camera():
    # A flat curve is a box; a rolling shutter's Duration is a share of the shutter.
    assert wn.Camera(shutter_curve=[0.5, 0.5, 0.5]).shutter_box
    ramp = wn.Camera(shutter_curve=[0.0, 0.5, 1.0], rolling_shutter=0.1)
    assert not ramp.shutter_box and ramp.rolling_shutter
    assert not wn.Camera().rolling_shutter
    for duration in (1.5, math.nan):
        with pytest.raises(ValueError, match="rolling_shutter"):
            wn.Camera(rolling_shutter=duration)


def shadow_edge_scene():
    """A blocker's hard shadow on a lit floor: flat light and shade, noisy edges."""
    scene = lit_floor_scene()
    scene.set_mesh("blocker", *quad(-0.3, 0.3, -0.3, 0.3, 1.0))
    scene.set_instance("blocker", "blocker", np.eye(4), ["white"])
    return scene


SHADOW_EDGE = dict(width=24, height=24, aa_samples=6, aa_mode=wn.AntiAliasing.JITTERED)


def test_noise_driven_sampling_stops_flat_pixels_and_reports_samples_per_pixel():
    scene = shadow_edge_scene()
    kwargs = SHADOW_EDGE
    settings = wn.Settings(**kwargs, adaptive_sampling=True, adaptive_min_samples=4)
    assert (settings.noise_threshold, settings.adaptive_min_samples) == (pytest.approx(0.01), 4)
    job = wn.RenderJob(scene, settings)
    finish(job)
    low, mean, high = job.stats()["samples_per_pixel"]
    assert (low, high) == (16, 36)  # the first check, the grid
    assert low < mean < 30
    assert job.stats()["samples"] == round(mean * 24 * 24)
    # Threshold 0 takes every sample: the fixed-count render up to the order of the sums.
    settings = wn.Settings(**kwargs, adaptive_sampling=True, noise_threshold=0.0)
    job = wn.RenderJob(scene, settings)
    fixed = finish(wn.RenderJob(scene, wn.Settings(**kwargs)))
    np.testing.assert_allclose(finish(job), fixed, rtol=1e-5, atol=1e-6)
    assert job.stats()["samples_per_pixel"] == (36, 36.0, 36)


def test_an_expired_time_limit_ends_after_the_first_round():
    scene = shadow_edge_scene()
    settings = wn.Settings(**SHADOW_EDGE, adaptive_sampling=True, adaptive_min_samples=4)
    assert settings.time_limit == 0.0 and wn.LIMITS["time_limit"] == (0.0, 1e6)
    job = wn.RenderJob(scene, settings)
    finish(job)
    assert not job.stats()["time_limited"] and job.stats()["rounds"] == 3  # checks 16, 32; 36
    settings.time_limit = 1e-9
    job = wn.RenderJob(scene, settings)
    finish(job)
    stats = job.stats()
    assert stats["time_limited"] and stats["rounds"] == 1
    assert stats["samples_per_pixel"] == (16, 16.0, 16)
    # Ignored without noise-driven sampling.
    fixed = wn.Settings(**SHADOW_EDGE, time_limit=1e-9)
    job = wn.RenderJob(scene, fixed)
    finish(job)
    assert not job.stats()["time_limited"] and job.stats()["samples"] == 36 * 24 * 24
    with pytest.raises(ValueError, match="time_limit"):
        wn.Settings(time_limit=-1.0)


def test_the_sample_count_pass_shows_each_pixels_camera_samples():
    scene = shadow_edge_scene()
    assert wn.FILM_PASSES["sample_count"] == 1
    settings = wn.Settings(
        **SHADOW_EDGE, adaptive_sampling=True, adaptive_min_samples=4, passes=["sample_count"]
    )
    job = wn.RenderJob(scene, settings)
    image = finish(job)
    counts = job.pass_tile("sample_count", 0, 0, 24, 24)[:, 0]
    assert counts.min() == 16 and counts.max() == 36  # flat pixels, the shadow's edge
    assert counts.sum() == job.stats()["samples"]
    np.testing.assert_array_equal(job.pass_tile("sample_count", 3, 2, 4, 5)[:, 0].shape, (20,))
    # Kept or not, the kernel and the image are the same.
    settings.passes = []
    np.testing.assert_array_equal(finish(wn.RenderJob(scene, settings)), image)


def test_stats_give_the_final_noise_estimate_of_a_noise_driven_render():
    scene = shadow_edge_scene()
    means = []
    for aa_samples in (4, 8):
        kwargs = dict(SHADOW_EDGE, aa_samples=aa_samples)
        job = wn.RenderJob(scene, wn.Settings(**kwargs, adaptive_sampling=True, noise_threshold=0))
        finish(job)
        noise = job.stats()["noise"]
        assert set(noise) == {"mean", "max"} and 0 < noise["mean"] < noise["max"]
        means.append(noise["mean"])
    assert means[1] < 0.75 * means[0]  # 64 samples a pixel against 16
    job = wn.RenderJob(scene, wn.Settings(**SHADOW_EDGE))
    finish(job)
    assert "noise" not in job.stats()  # absent without noise-driven sampling
