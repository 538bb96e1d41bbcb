"""Light linking and shadow linking (Blender 4.0+, Object > Light Linking) against Cycles:
a lamp that lights only what its receiver collection includes, a lamp whose shadows only
its blocker collection casts, and an emissive panel that excludes a ball from its light
and lets it cast no shadow (export/light_linking.py, native scene/light.h)."""

import json

import bpy
import numpy as np
import pytest
from test_emitters import cycles_and_whitted, lit_sum_ratio
from whitted_tools import cycles_scenes
from whitted_tools.material_scenes import lambert_material, panel_room

pytestmark = pytest.mark.skipif(
    bpy.app.version < (4, 0, 0), reason="light linking came with Blender 4.0"
)


def linking_collection(name, links):
    """A collection (outside the scene, as Blender's Light Linking panel makes it) of
    (object, "INCLUDE" or "EXCLUDE")."""
    collection = bpy.data.collections.new(name)
    for obj, _ in links:
        collection.objects.link(obj)
    for entry, (_, state) in zip(collection.collection_objects, links, strict=True):
        entry.light_linking.link_state = state
    return collection


def lamp_scene(scene):
    case = cycles_scenes.CASES[0]  # the point light over the floor and the floating box
    lamp = cycles_scenes.build_scene(scene, case)
    cycles_scenes.set_whitted_direct_light(scene)
    cycles_scenes.set_cycles_direct_light(scene)
    return case, lamp


def both(scene, tmp_path):
    whitted = cycles_scenes.render_exr(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    cycles = cycles_scenes.render_exr(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    return whitted, cycles


def test_a_lamp_lights_only_its_receivers_as_cycles(empty_scene, tmp_path, native, monkeypatch):
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    case, lamp = lamp_scene(empty_scene)
    unlinked, _ = both(empty_scene, tmp_path)
    blocker = bpy.data.objects["Blocker"]
    lamp.light_linking.receiver_collection = linking_collection(
        "Lit by the lamp", [(blocker, "INCLUDE")]
    )
    whitted, cycles = both(empty_scene, tmp_path)
    measured = cycles_scenes.compare(empty_scene, whitted, cycles)
    floor_only = (unlinked.mean(axis=-1) > cycles_scenes.DARK) & (
        cycles.mean(axis=-1) <= cycles_scenes.DARK
    )
    print(f"\nreceivers: {measured}; floor pixels left dark {floor_only.sum()}")
    # The floor is dark in both, the box lit as in Cycles.
    assert floor_only.sum() > 0.5 * whitted.shape[0] * whitted.shape[1]
    assert whitted[floor_only].max() == 0.0
    assert measured.mean_ratio == pytest.approx(1.0, abs=0.02)
    assert measured.relative_rmse < case.max_relative_rmse * 3
    stats = json.loads(stats_path.read_text())
    linking = next(e for e in stats["effects"] if e["name"] == "light linking")
    assert linking["on"]
    assert linking["why"].startswith("1 light, 0 emissive objects linked; 1 object")


def test_only_a_lamps_blockers_cast_its_shadow_as_cycles(empty_scene, tmp_path, native):
    case, lamp = lamp_scene(empty_scene)
    sharp, _ = both(empty_scene, tmp_path)
    floor = bpy.data.objects["Floor"]
    # The box is not among the blockers: it casts no shadow of this lamp.
    lamp.light_linking.blocker_collection = linking_collection(
        "Shadows of the lamp", [(floor, "INCLUDE")]
    )
    whitted, cycles = both(empty_scene, tmp_path)
    measured = cycles_scenes.compare(empty_scene, whitted, cycles)
    row = measured.row
    print(f"\nblockers: {measured}")
    assert measured.mean_ratio == pytest.approx(1.0, abs=0.02)
    assert measured.relative_rmse < case.max_relative_rmse
    # Along the shadow row the floor is lit where the box's shadow was.
    assert measured.profile_error < case.max_profile_error
    assert whitted[row].mean() > 1.1 * sharp[row].mean()  # measured 1.18


def test_an_emissive_panel_links_like_a_lamp_as_cycles(empty_scene, tmp_path, native, monkeypatch):
    stats_path = tmp_path / "stats.json"
    monkeypatch.setenv("WHITTED_STATS", str(stats_path))
    panel = panel_room(empty_scene, lambert_material("Grey", 0.8))
    unlinked = cycles_scenes.render_rgba(empty_scene, "WHITTED", str(tmp_path / "unlinked.exr"))
    ball = bpy.data.objects["Ball"]
    floor = next(o for o in empty_scene.objects if o.type == "MESH" and o not in (ball, panel))
    # The ball gets none of the panel's light and casts none of its shadow.
    panel.light_linking.receiver_collection = linking_collection(
        "Lit by the panel", [(ball, "EXCLUDE")]
    )
    panel.light_linking.blocker_collection = linking_collection(
        "Shadows of the panel", [(floor, "INCLUDE")]
    )
    cycles, whitted = cycles_and_whitted(empty_scene, tmp_path)
    ratio, covered = lit_sum_ratio(cycles, whitted)
    lit = covered & (cycles[..., 0] > 0.01)
    per_pixel = np.median(whitted[lit][:, 0] / cycles[lit][:, 0])

    def relative_rmse(image):
        difference = image[covered][:, 0] - cycles[covered][:, 0]
        return np.sqrt(np.mean(difference**2)) / cycles[covered][:, 0].mean()

    print(
        f"\nlinked panel: summed Whitted / Cycles {ratio:.4f}, median {per_pixel:.4f}, "
        f"relative RMSE {relative_rmse(whitted):.4f} (unlinked {relative_rmse(unlinked):.4f})"
    )
    assert abs(ratio - 1.0) < 0.03
    assert abs(per_pixel - 1.0) < 0.05
    assert relative_rmse(whitted) < 0.5 * relative_rmse(unlinked)
    stats = json.loads(stats_path.read_text())
    linking = next(e for e in stats["effects"] if e["name"] == "light linking")
    assert linking["why"].startswith("0 lights, 1 emissive object linked")


def test_an_instance_takes_its_instancers_set_as_cycles(empty_scene, tmp_path, native):
    # The box shown through a collection instance: the instancer (an empty) excluded from
    # the lamp's light leaves the instanced box unlit, as Cycles reads the instancer's set.
    case, lamp = lamp_scene(empty_scene)
    blocker = bpy.data.objects["Blocker"]
    shown = bpy.data.collections.new("Shown")
    shown.objects.link(blocker)
    empty_scene.collection.objects.unlink(blocker)
    instancer = bpy.data.objects.new("Instancer", None)
    instancer.instance_type = "COLLECTION"
    instancer.instance_collection = shown
    empty_scene.collection.objects.link(instancer)
    lit, _ = both(empty_scene, tmp_path)
    lamp.light_linking.receiver_collection = linking_collection(
        "Not the instancer", [(instancer, "EXCLUDE")]
    )
    whitted, cycles = both(empty_scene, tmp_path)
    # (cycles_scenes.compare finds the shadow row by the box's name in the scene.)
    shown_lit = cycles.mean(axis=-1) > cycles_scenes.DARK
    ratio = whitted[shown_lit].mean() / cycles[shown_lit].mean()
    rmse = np.sqrt(np.mean((whitted - cycles) ** 2)) / cycles.mean()
    darkened = (lit.mean(axis=-1) > cycles_scenes.DARK) & ~shown_lit
    print(
        f"\ninstancer excluded: mean ratio {ratio:.4f}, relative RMSE {rmse:.4f}; "
        f"box pixels left dark {darkened.sum()}"
    )
    assert darkened.sum() > 50  # the box (91 pixels), lit before, dark in Cycles
    assert whitted[darkened].max() == 0.0
    assert ratio == pytest.approx(1.0, abs=0.02)
    assert rmse < case.max_relative_rmse * 3
