"""The IES Texture in a lamp's node tree, against Cycles rendered in the same test.

Each profile is a small LM-63 file written here (type C: round, a quadrant, a half,
the full circle with light upwards; type B), feeding the Emission Strength of a point
lamp above cycles_scenes' floor; the pattern it throws on the floor is compared per
pixel with Cycles' at direct-light settings (512 samples, a centre-point filter: Cycles'
own noise on this floor is about 0.2% a pixel). Before, the node was ignored (its input
kept its unlinked value) and the floor was lit evenly."""

import math

import bpy
import numpy as np
import pytest
from exported import exported_lights
from whitted_tools import cycles_scenes

# Per pixel over the lit floor, Whitted / Cycles: the 5% and 95% quantiles. The profile's
# Catmull-Rom interpolation is Cycles' own; what is left is Cycles' noise.
PIXEL_BOUND = 0.03
SUM_BOUND = 0.01


def _lm63(kind, v_angles, h_angles, candela, tilt="NONE", multiplier=1.0):
    """An IES LM-63 file's text: photometric `kind` (1: C, 2: B), its angles, and
    candela[h][v]."""
    rows = "\n".join(" ".join(f"{c:g}" for c in row) for row in candela)
    return (
        "IESNA:LM-63-2002\n[TEST] Whitted test profile\n[MANUFAC] none\n"
        f"TILT={tilt}\n"
        f"1 1000 {multiplier:g} {len(v_angles)} {len(h_angles)} {kind} 2 0.1 0.1 0\n"
        "1.0 1.0 100\n"
        + " ".join(f"{a:g}" for a in v_angles)
        + "\n"
        + " ".join(f"{a:g}" for a in h_angles)
        + "\n"
        + rows
        + "\n"
    )


_DOWN = [0, 10, 20, 30, 40, 50, 60, 70, 80, 90]


def _round():
    # A downlight: a hot centre and a ring at 40 degrees.
    v = _DOWN
    return _lm63(1, v, [0], [[900, 850, 700, 800, 1000, 600, 300, 120, 40, 0]])


def _quadrant():
    # Brighter towards h = 0 than towards h = 90, mirrored to the whole circle.
    h = [0, 30, 60, 90]
    candela = [
        [1000 * (1.0 - 0.2 * i) * math.cos(math.radians(v)) for v in _DOWN] for i in range(4)
    ]
    return _lm63(1, _DOWN, h, candela)


def _half():
    h = [0, 45, 90, 135, 180]
    candela = [
        [(400 + 300 * math.sin(math.radians(a))) * (1.0 - v / 100.0) for v in _DOWN] for a in h
    ]
    return _lm63(1, _DOWN, h, candela, multiplier=1.5)


def _full_circle():
    # 0..180 vertical (light upwards too, met by nothing) and 0..360 horizontal.
    v = list(range(0, 181, 15))
    h = list(range(0, 361, 45))

    def candela(a, b):
        return 600 + 250 * math.cos(math.radians(2 * a)) * math.cos(math.radians(b))

    return _lm63(1, v, h, [[candela(a, b) for b in v] for a in h])


def _type_b():
    # Type B: horizontal angles -90..90 about the lamp's axis, vertical 0..90.
    v = [-90, -45, 0, 45, 90]
    h = [0, 30, 60, 90]
    return _lm63(2, v, h, [[500 + 5 * a + 100 * (i + 1) for a in v] for i in range(len(h))])


PROFILES = {
    "round": _round,
    "quadrant": _quadrant,
    "half": _half,
    "full_circle": _full_circle,
    "type_b": _type_b,
}


def _lamp_tree(scene, case, rotation=None):
    """cycles_scenes' scene of light `case` (turned by Euler `rotation`, degrees), both
    engines at direct-light settings: (the lamp, its node tree, the tree's Emission)."""
    lamp = cycles_scenes.build_scene(scene, next(c for c in cycles_scenes.CASES if c.name == case))
    if rotation is not None:
        lamp.rotation_euler = tuple(math.radians(a) for a in rotation)
    lamp.data.use_nodes = True
    tree = lamp.data.node_tree
    emission = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeEmission")
    cycles_scenes.set_whitted_direct_light(scene)
    cycles_scenes.set_cycles_direct_light(scene)
    return lamp, tree, emission


def _ies_lamp(scene, text, internal=True, tmp_path=None, rotation=None):
    """cycles_scenes' point case, its Emission Strength the IES Texture's Fac."""
    lamp, tree, emission = _lamp_tree(scene, "point", rotation)
    lamp.data.energy = 2000.0
    ies = tree.nodes.new("ShaderNodeTexIES")
    if internal:
        block = bpy.data.texts.new("profile.ies")
        block.write(text)
        ies.mode = "INTERNAL"
        ies.ies = block
    else:
        path = tmp_path / "profile.ies"
        if text is not None:
            path.write_text(text)
        ies.mode = "EXTERNAL"
        ies.filepath = str(path)
    tree.links.new(ies.outputs["Fac"], emission.inputs["Strength"])
    return lamp


def _compare(scene, tmp_path, label):
    whitted = cycles_scenes.render_exr(scene, "WHITTED", str(tmp_path / "whitted.exr"))
    cycles = cycles_scenes.render_exr(scene, "CYCLES", str(tmp_path / "cycles.exr"))
    lit = cycles.mean(axis=-1) > cycles_scenes.DARK
    ratio = whitted[lit].mean(axis=-1) / cycles[lit].mean(axis=-1)
    low, median, high = np.quantile(ratio, [0.05, 0.5, 0.95])
    summed = whitted[lit].sum() / cycles[lit].sum()
    spread = cycles[lit].mean(axis=-1).std() / cycles[lit].mean()
    print(
        f"\n{label}: Whitted / Cycles per pixel 5% {low:.4f} median {median:.4f} 95% "
        f"{high:.4f}, summed {summed:.4f}; {lit.sum()} lit pixels, Cycles' spread {spread:.3f}"
    )
    return lit, low, high, summed, spread


# Cycles 4.0+ turns a type B file into its layout otherwise than 3.x did (bpy 5.0: 0.87 of
# Cycles' light summed over the floor, and its pattern shifted); Whitted reads it as 3.x
# and warns. Not followed: that parser's source was not at hand.
_TYPE_B_AS_3X = pytest.mark.xfail(
    bpy.app.version >= (4, 0, 0), strict=True, reason="Cycles 4.0+'s type B layout"
)


@pytest.mark.parametrize(
    "profile",
    [pytest.param(p, marks=_TYPE_B_AS_3X) if p == "type_b" else p for p in PROFILES],
)
def test_an_ies_profile_lights_the_floor_as_cycles(empty_scene, tmp_path, native, profile):
    _ies_lamp(empty_scene, PROFILES[profile]())
    lit, low, high, summed, spread = _compare(empty_scene, tmp_path, profile)
    assert lit.sum() > 1000
    assert spread > 0.2  # the floor shows a pattern, not an even light
    assert low > 1.0 - PIXEL_BOUND and high < 1.0 + PIXEL_BOUND
    assert summed == pytest.approx(1.0, abs=SUM_BOUND)


def test_the_profile_turns_with_the_lamp_and_reads_a_file(empty_scene, tmp_path, native):
    # The lookup is in the lamp's object space: a lamp turned 35 degrees about Z and
    # tilted 20 turns the quadrant profile's brighter side with it. The profile is read
    # from a file beside the scene (External).
    _ies_lamp(empty_scene, _quadrant(), internal=False, tmp_path=tmp_path, rotation=(20, 0, 35))
    _, low, high, summed, _ = _compare(empty_scene, tmp_path, "turned, external")
    assert low > 1.0 - PIXEL_BOUND and high < 1.0 + PIXEL_BOUND
    assert summed == pytest.approx(1.0, abs=SUM_BOUND)


def test_a_missing_profile_is_reported_and_lights_as_cycles(empty_scene, tmp_path, native):
    # A file that is not there: Cycles' node falls back to 100 x Strength; Whitted does
    # the same and names the file in its report.
    _ies_lamp(empty_scene, None, internal=False, tmp_path=tmp_path)
    empty_scene.objects["Light"].data.energy = 20.0
    _, low, high, _, _ = _compare(empty_scene, tmp_path, "missing file")
    assert low > 1.0 - PIXEL_BOUND and high < 1.0 + PIXEL_BOUND
    warnings = []
    exported_lights(bpy.context.evaluated_depsgraph_get(), warnings)
    assert any("profile.ies" in w and "cannot be read" in w for w in warnings)


@pytest.mark.parametrize(("case", "output"), [("point", "Normal"), ("area_square", "Object")])
def test_texture_coordinates_in_a_lamps_tree_are_in_its_space(
    empty_scene, tmp_path, native, case, output
):
    # A lamp's Texture Coordinate gives its normal towards the lit point (a point lamp
    # turned 35 degrees about Z and tilted 20), in the lamp's object space, or the point on
    # it (a square lamp), in the lamp's space in Cycles 4.0+ and in the world in 3.x (its
    # lamps have no object to carry it): 1 + their X as the Emission Strength makes one
    # side of the floor brighter, per pixel as in Cycles.
    _, tree, emission = _lamp_tree(empty_scene, case, rotation=(20, 0, 35))
    coordinates = tree.nodes.new("ShaderNodeTexCoord")
    separate = tree.nodes.new("ShaderNodeSeparateXYZ")
    add = tree.nodes.new("ShaderNodeMath")
    add.inputs[1].default_value = 1.0
    tree.links.new(coordinates.outputs[output], separate.inputs[0])
    tree.links.new(separate.outputs["X"], add.inputs[0])
    tree.links.new(add.outputs["Value"], emission.inputs["Strength"])
    lit, low, high, summed, _ = _compare(empty_scene, tmp_path, f"{case} {output}")
    assert lit.sum() > 1000
    # The area lamp's soft light leaves Cycles' noise per pixel at 512 samples.
    bound = PIXEL_BOUND if case == "point" else 0.08
    assert low > 1.0 - bound and high < 1.0 + bound
    assert summed == pytest.approx(1.0, abs=SUM_BOUND)
