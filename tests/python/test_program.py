"""Shader programs through the bindings: validation, fields, hit inputs and the world."""

import importlib.util
import sys
import types
from pathlib import Path

import numpy as np
import pytest
import whitted_native as wn
from test_scene import finish, looking_down, point_light, quad

U = 0xFFFFFFFF
INPUT, MATH, VECTOR_MATH, IMAGE, ENVIRONMENT, NOISE = 1, 2, 3, 18, 19, 22
UV = 64
ATTRIBUTE = 128
GLOW = dict(diffuse=(0, 0, 0), ambient=0.0)


def program(rows, registers, constants=(), textures=()):
    code = np.array([list(r) + [U] * (8 - len(r)) for r in rows], np.uint32).reshape(-1, 8)
    return wn.Program(
        code,
        np.asarray(registers, np.float32).reshape(-1, 4),
        np.asarray(constants, np.float32),
        list(textures),
    )


def plane_scene(material, **mesh):
    scene = wn.Scene()
    positions, triangles = quad(-1, 1, -1, 1, 0)
    if "uvs" not in mesh:  # the textures' UVs; beside uv_sets, not UV set 0
        corner_uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 0], [1, 1], [0, 1]], np.float32)
        mesh["uvs"] = corner_uvs.reshape(2, 3, 2)
    scene.set_mesh("plane", positions, triangles, **mesh)
    scene.set_material("m", material)
    scene.set_instance("plane", "plane", np.eye(4), ["m"])
    scene.camera = looking_down(5.0, 0.2)  # the window spans the plane, +-1
    return scene


def test_uvs_alone_are_uv_set_0():
    material = wn.Material(
        **GLOW, program=program([(INPUT, UV, 0)], [0] * 4), outputs={"emission": 0}
    )
    scene = plane_scene(material, uvs=np.full((2, 3, 2), 0.5, np.float32))
    image = finish(wn.RenderJob(scene, wn.Settings(width=2, height=2)))
    np.testing.assert_array_equal(image[..., :3], [[[0.5, 0.5, 0]] * 2] * 2)


def test_every_op_name_the_compiler_reads_is_defined_once():
    # addon/export/nodes/ops.py takes the op codes, input modes and operation lists from
    # this module (the modes' fields too, through pack): every ops.NAME the add-on and its
    # tests read must be native or one of ops.py's own few, and none both.
    import ast
    import re
    from pathlib import Path

    root = Path(__file__).parents[2]
    tree = ast.parse((root / "addon" / "export" / "nodes" / "ops.py").read_text())
    own = {
        target.id
        for node in tree.body
        if isinstance(node, ast.Assign)
        for target in node.targets
        if isinstance(target, ast.Name)
    }
    native = {name for name, _, _ in wn.OPS} | set(wn.OP_NUMBERS)
    native |= {"OP_NAMES", "MATH_OPS", "VECTOR_MATH_OPS", "MIX_BLEND", "TABLE_OPS"}
    assert not own & native
    sources = [*(root / "addon").rglob("*.py"), *(root / "tests" / "blender").rglob("*.py")]
    used = {
        name
        for path in sources
        for name in re.findall(r"\bops\.([A-Z][A-Z0-9_]*)\b", path.read_text())
    }
    assert used and used - own - native == set()
    # The input modes are distinct, and the bits clear of the modes they flag.
    inputs = {name: v for name, v in wn.OP_NUMBERS.items() if name.startswith("IN_")}
    assert len(set(inputs.values())) == len(inputs)
    numbers = wn.OP_NUMBERS
    assert numbers["IN_UV"] + numbers["UV_SETS"] == numbers["IN_ATTRIBUTE"]
    assert numbers["IN_BUMP_X"] >= numbers["IN_ATTRIBUTE"] + numbers["ATTRIBUTES"]
    last = numbers["IN_ATTRIBUTE"] + numbers["ATTRIBUTES"] - 1
    program([(INPUT, last, 0), (INPUT, last | numbers["IN_BUMP_X"], 0)], [0] * 4)


def test_every_op_mode_is_fields_or_none():
    # INPUT's modes are OP_NUMBERS; every other op's mode is its fields (OP_MODES,
    # packed by ops.pack) or, for an op without one, 0: the program refuses any other.
    # The add-on writes no mode as a number but that 0, and compares none with a number.
    import re

    codes = {name: code for code, (name, _, _) in enumerate(wn.OPS) if code}
    modeless = set(codes) - set(wn.OP_MODES) - {"INPUT"}
    assert set(wn.OP_MODES) <= set(codes) and "INPUT" not in wn.OP_MODES
    assert {"MIX_VALUE", "SWIZZLE", "LAYER_WEIGHT", "BUMP"} <= set(wn.OP_MODES)
    assert {"GAMMA", "FRESNEL", "PACK", "RGB_TO_BW"} <= modeless
    for name in modeless:
        _mode_taken(codes[name], 0)
        for mode in (1, 1 << 8, 1 << 31):
            with pytest.raises(ValueError, match=f"\\({name}\\): mode {mode} is not one of"):
                program([(codes[name], mode, 0)], [0] * 4)
    root = Path(__file__).parents[2]
    written = []  # (op, its mode's expression up to a comma) of every Builder.op call
    for path in (root / "addon").rglob("*.py"):
        text = path.read_text()
        written += re.findall(r"\.op\(\s*ops\.([A-Z][A-Z0-9_]*),\s*([^,]+),", text)
        assert not re.search(r"\.mode\s*(==|!=|<=?|>=?)\s*\d", text), path
    assert {"MIX_VALUE", "SWIZZLE", "LAYER_WEIGHT", "BUMP", "GAMMA"} <= {op for op, _ in written}
    for op, mode in written:
        if re.search(r"(?<![\w.\"])\d", mode):
            assert op in modeless and mode.strip() == "0", (op, mode)


@pytest.fixture
def ops():
    """addon/export/nodes/ops.py as the add-on loads it (its package's load_native giving
    this build's module), without Blender."""
    package = "ops_under_test"
    native = types.ModuleType(f"{package}.native")
    native.load_native = lambda: wn
    modules = {package: types.ModuleType(package), f"{package}.native": native}
    sys.modules.update(modules)
    path = Path(__file__).parents[2] / "addon" / "export" / "nodes" / "ops.py"
    spec = importlib.util.spec_from_file_location(f"{package}.export.nodes.ops", path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
        yield module
    finally:
        for name in modules:
            del sys.modules[name]


def _values(count, identifiers, width):
    if identifiers:
        return list(identifiers)
    return [False, True] if width == 1 else list(range(count))


def _mode_taken(op, mode):
    # The program checks the mode first; what it refuses after (a COLOR_RAMP without its
    # constants, an IMAGE without a texture) is not the mode's fault.
    try:
        program([(op, mode, 0, 0, 0, 0, 0, 0)], [0] * 4)
    except ValueError as error:
        assert "mode" not in str(error), error


def test_packed_modes_are_what_the_program_decodes(ops):
    # ops.pack lays out every value of every field of every op whose mode is fields as
    # the native decoders read it back (mode_fields: the same ModeField constants), and
    # the program takes the mode; a value past a field's is refused by both sides.
    codes = {name: code for code, (name, _, _) in enumerate(wn.OPS)}
    assert set(wn.OP_MODES) >= {"NOISE", "VORONOI", "WAVE", "BRICK", "MAP_RANGE", "MIX_VALUE"}
    for op, fields in wn.OP_MODES.items():
        chosen = {}
        for name, shift, width, count, identifiers in fields:
            for index, value in enumerate(_values(count, identifiers, width)):
                mode = ops.pack(op, **{name: value})
                # The others read 0, but those in the same bits (WAVE's directions).
                assert wn.mode_fields(op, mode) == {
                    other: index if (s, w) == (shift, width) else 0 for other, s, w, *_ in fields
                }, (op, name, value)
                assert ops.unpack(op, mode)[name] == value
                _mode_taken(codes[op], mode)
            if count < 1 << width:
                with pytest.raises(ValueError, match="is not a mode of"):
                    wn.mode_fields(op, count << shift)
                with pytest.raises(ValueError, match="not one of its modes"):
                    program([(codes[op], count << shift, 0)], [0] * 4)
            taken = any(shift == s for n, s, *_ in fields if n in chosen)
            if not taken:  # WAVE's directions share their bits: one of them
                chosen[name] = _values(count, identifiers, width)[-1]
        # All fields at once, each at its last value: no field spills into another.
        mode = ops.pack(op, **chosen)
        assert ops.unpack(op, mode).items() >= chosen.items()
        decoded = wn.mode_fields(op, mode)
        for name, _, width, count, identifiers in fields:
            if name in chosen:
                assert decoded[name] == _values(count, identifiers, width).index(chosen[name])
        with pytest.raises(ValueError, match="is not a mode of"):
            wn.mode_fields(op, 1 << 31)  # no op's mode reaches bit 31


def test_pack_names_what_it_cannot_pack(ops):
    voronoi = ops.pack("VORONOI", feature="SMOOTH_F1", metric="MINKOWSKI", output="COLOR")
    assert wn.mode_fields("VORONOI", voronoi)["metric"] == 3
    with pytest.raises(ValueError, match="VORONOI feature: 'F3' is not one of F1, F2, "):
        ops.pack("VORONOI", feature="F3")
    with pytest.raises(TypeError, match="VORONOI has no mode field 'colour'"):
        ops.pack("VORONOI", colour=True)
    with pytest.raises(TypeError, match="a flag is a bool"):
        ops.pack("NOISE", normalize=1)
    with pytest.raises(ValueError, match=r"MAGIC turbulence_depth: 11 is not an int in \[0, 11\)"):
        ops.pack("MAGIC", turbulence_depth=11)
    with pytest.raises(TypeError, match="rings_direction: its bits are another field's"):
        ops.pack("WAVE", bands_direction="X", rings_direction="X")
    with pytest.raises(ValueError, match="INPUT has no mode fields"):
        ops.pack("INPUT")
    with pytest.raises(ValueError, match="GAMMA has no mode fields"):
        ops.pack("GAMMA")
    with pytest.raises(ValueError, match=r"SWIZZLE component: 4 is not an int in \[0, 4\)"):
        ops.pack("SWIZZLE", component=4)


def test_fold_op_runs_the_programs_maths():
    multiply_add = wn.MATH_OPS.index("MULTIPLY_ADD")
    three = [(2.0,) * 4, (3.0,) * 4, (0.5,) * 4]
    assert wn.fold_op(MATH, multiply_add, three, []) == (6.5,) * 4
    # The same instruction run by a program gives the same floats (float32: 0.1 * 3).
    registers = [[0.1] * 4, [3.0] * 4, [0.0] * 4, [0] * 4]
    multiply = wn.MATH_OPS.index("MULTIPLY")
    run = program([(MATH, multiply, 3, 0, 1, 2)], registers).run({})
    folded = wn.fold_op(MATH, multiply, [(0.1,) * 4, (3.0,) * 4, None], [])
    assert tuple(run[3]) == folded and folded[0] != 0.1 * 3.0
    # A colour ramp's stops in the constants: (count, then position, r, g, b, a per stop).
    ramp = [2, 0.0, 0, 0, 0, 1, 1.0, 1, 0.5, 0.25, 1]
    assert wn.fold_op(15, 1, [(0.5,) * 4], ramp) == pytest.approx((0.5, 0.25, 0.125, 1.0))
    # Ops that read the hit do not fold.
    assert wn.fold_op(INPUT, 0, [], []) is None
    assert wn.fold_op(IMAGE, 0, [(0.0,) * 4], []) is None
    with pytest.raises(ValueError, match="not one of its modes"):
        wn.fold_op(MATH, 99, three, [])


def test_blackbody_rgb_is_what_op_blackbody_computes():
    # One definition (shader/blackbody.h): the binding the add-on's constant media read, the
    # op a program runs and the compiler's folding give the same float32 colour; at 1500 K
    # its blue is below 0 (not clamped), its red and green Cycles' (3.26430678, 0.434046328
    # as Blender 5.0.1 renders the Blackbody node).
    blackbody = [name for name, _, _ in wn.OPS].index("BLACKBODY")
    rgb = wn.blackbody_rgb(1500.0)
    assert rgb[:2] == pytest.approx((3.26430678, 0.434046328), rel=1e-6) and rgb[2] < 0.0
    run = program([(blackbody, 0, 1, 0)], [[1500.0] * 4, [0] * 4]).run({})
    assert tuple(run[1]) == (*rgb, 1.0) == wn.fold_op(blackbody, 0, [(1500.0,) * 4], [])


def test_program_run_reads_the_given_inputs():
    normalize = wn.VECTOR_MATH_OPS.index("NORMALIZE")
    p = program([(INPUT, UV, 1), (VECTOR_MATH, normalize, 0, 1)], [0] * 8)
    np.testing.assert_allclose(p.run({UV: (3.0, 4.0, 0.0, 0.0)})[0, :3], (0.6, 0.8, 0.0))
    with pytest.raises(ValueError, match="input mode 64 is not given"):
        p.run({})


def test_operation_lists_follow_blenders_enums():
    # Blender 5.2's identifiers; 3.4 has the same ones in the same order, minus the new
    # (Math FLOORED_MODULO from 4.x, Vector Math ROUND from 5.1).
    assert wn.MATH_OPS[:5] == ["ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD"]
    assert wn.MATH_OPS.index("FLOORED_MODULO") == wn.MATH_OPS.index("MODULO") + 1
    assert wn.MATH_OPS[-1] == "DEGREES" and len(wn.MATH_OPS) == 41
    assert wn.VECTOR_MATH_OPS.index("POWER") == 16 and wn.VECTOR_MATH_OPS[-1] == "TANGENT"
    assert wn.VECTOR_MATH_OPS.index("ROUND") == wn.VECTOR_MATH_OPS.index("MAXIMUM") + 1
    assert len(wn.VECTOR_MATH_OPS) == 30
    assert wn.MIX_BLEND.index("EXCLUSION") == 12 and len(wn.MIX_BLEND) == 19
    blender_34_math = [op for op in wn.MATH_OPS if op != "FLOORED_MODULO"]
    assert blender_34_math[24:26] == ["MODULO", "WRAP"]


def test_program_validation_errors_are_value_errors():
    with pytest.raises(ValueError, match=r"shape \(K, 8\)"):
        wn.Program(
            np.zeros((1, 7), np.uint32), np.zeros((1, 4), np.float32), np.zeros(0, np.float32), []
        )
    with pytest.raises(ValueError, match=r"shape \(R, 4\)"):
        wn.Program(
            np.zeros((0, 8), np.uint32), np.zeros((1, 3), np.float32), np.zeros(0, np.float32), []
        )
    with pytest.raises(ValueError, match="unknown op 0"):
        program([(0, 0, 0)], [0, 0, 0, 0])
    with pytest.raises(ValueError, match=r"instruction 1 \(NOISE\): mode 20 is not one of"):
        program([(MATH, 0, 0), (NOISE, 5 << 2, 0)], [0, 0, 0, 0])  # no fractal 5
    with pytest.raises(ValueError, match="operand b register 3 out of range"):
        program([(MATH, 0, 0, 0, 3)], [0, 0, 0, 0])
    with pytest.raises(ValueError, match="mode 41"):
        program([(MATH, 41, 0)], [0, 0, 0, 0])
    with pytest.raises(ValueError, match="texture slot 0 out of range"):
        program([(IMAGE, 0, 0, U, U, U, U, 0)], [0, 0, 0, 0])
    p = program([(MATH, 0, 0)], [0, 0, 0, 0])
    assert (p.register_count, p.instruction_count) == (1, 1)
    with pytest.raises(ValueError, match="not a material field"):
        wn.Material(program=p, outputs={"colour": 0})
    with pytest.raises(ValueError, match="register 1 out of range"):
        wn.Material(program=p, outputs={"diffuse": 1})
    with pytest.raises(ValueError, match="need a program"):
        wn.Material(outputs={"diffuse": 0})
    with pytest.raises(ValueError, match="world output register 2"):
        wn.Scene().set_world(p, 2)
    m = wn.Material(program=p, outputs={"alpha": 0})
    assert m.outputs == {"alpha": 0} and m.program.register_count == 1


def test_program_textures_are_resolved_at_compile():
    uses = program([(INPUT, UV, 0), (IMAGE, 0, 0, 0, U, U, U, 0)], [0] * 4, textures=["img"])
    scene = plane_scene(wn.Material(program=uses, outputs={"diffuse": 0}))
    with pytest.raises(ValueError, match="missing texture 'img'"):
        wn.RenderJob(scene, wn.Settings(width=2, height=2))
    scene.set_texture("img", wn.CheckerTexture())
    with pytest.raises(ValueError, match="as an image, but it is a checker"):
        wn.RenderJob(scene, wn.Settings(width=2, height=2))


def test_image_through_a_program_equals_the_diffuse_texture_bit_for_bit():
    rng = np.random.default_rng(1)
    pixels = rng.random((5, 7, 4), dtype=np.float32)
    diffuse = (0.7, 0.5, 0.3)

    def render(material):
        scene = plane_scene(material)
        scene.set_texture("img", wn.ImageTexture(pixels))
        scene.set_light("key", point_light(30))
        scene.ambient = (0.1, 0.1, 0.1)
        return finish(wn.RenderJob(scene, wn.Settings(width=24, height=24, aa_samples=2)))

    old = render(wn.Material(diffuse=diffuse, diffuse_texture="img"))
    # r0 = UV set 0, r1 = the image there, r2 = the constant diffuse, r1 = r1 * r2.
    textured = program(
        [
            (INPUT, UV, 0),
            (IMAGE, 0, 1, 0, U, U, U, 0),
            (VECTOR_MATH, wn.VECTOR_MATH_OPS.index("MULTIPLY"), 1, 1, 2),
        ],
        [[0] * 4, [0] * 4, [*diffuse, 0]],
        textures=["img"],
    )
    new = render(wn.Material(diffuse=(0.1, 0.1, 0.1), program=textured, outputs={"diffuse": 1}))
    assert np.array_equal(old, new)
    assert len(np.unique(old[..., 0])) > 10  # the texture shows


def constant_program(value):
    return program([], [list(value) + [0] * (4 - len(value))])


@pytest.mark.parametrize(
    "field, value, constant",
    [
        ("diffuse", (0.2, 0.6, 0.4), dict(diffuse=(0.2, 0.6, 0.4))),
        ("specular", (0.5, 0.5, 0.1), dict(specular=(0.5, 0.5, 0.1))),
        ("shininess", (7.0,), dict(specular=(0.5, 0.5, 0.5), shininess=7.0)),
        ("reflectivity", (0.5, 0.25, 0.1), dict(reflectivity=(0.5, 0.25, 0.1))),
        ("transmissivity", (0.6, 0.6, 0.6), dict(transmissivity=(0.6, 0.6, 0.6))),
        ("ior", (1.33,), dict(transmissivity=(0.6, 0.6, 0.6), ior=1.33)),
        ("emission", (0.3, 0.2, 0.1), dict(emission=(0.3, 0.2, 0.1))),
        ("alpha", (0.4,), dict(alpha=0.4)),
        ("normal", (0.0, 0.0, -3.0), {}),  # any length, either side: the geometric normal
    ],
)
def test_every_field_can_come_from_a_program(field, value, constant):
    # Base constants the program's value replaces; the rest shared by both materials.
    shared = dict(specular=(0.5, 0.5, 0.5)) if field == "shininess" else {}
    if field == "ior":
        shared = dict(transmissivity=(0.6, 0.6, 0.6))
    base = {"diffuse": (0.9, 0.1, 0.1), "alpha": 1.0, **shared}
    expected_material = wn.Material(**{**base, **constant})
    driven = wn.Material(**base, program=constant_program(value), outputs={field: 0})

    def render(material):
        scene = plane_scene(material)
        scene.set_mesh("wall", *quad(-3, 3, -3, 3, -1))
        scene.set_material("wall", wn.Material(diffuse=(0.2, 0.3, 0.9)))
        scene.set_instance("wall", "wall", np.eye(4), ["wall"])
        scene.set_light("key", wn.Light(color=(40, 40, 40), position=(0.3, 0.2, 2)))
        scene.background = (0.1, 0.4, 0.1)
        scene.camera = looking_down(3.0, 0.5)
        job = wn.RenderJob(scene, wn.Settings(width=12, height=12))
        return finish(job), job.stats()

    expected, expected_stats = render(expected_material)
    got, stats = render(driven)
    assert np.array_equal(expected, got)
    if field == "reflectivity":
        assert stats["rays"]["reflection"] > 0
    if field in ("transmissivity", "ior"):
        assert stats["rays"]["refraction"] == expected_stats["rays"]["refraction"] > 0


def test_program_driven_reflectivity_turns_reflection_on():
    # Reflectivity = the U coordinate: reflective on the right half only.
    p = program(
        [(INPUT, UV, 0), (VECTOR_MATH, wn.VECTOR_MATH_OPS.index("MULTIPLY"), 1, 0, 2)],
        [[0] * 4, [0] * 4, [1, 1, 1, 0]],
    )
    scene = plane_scene(wn.Material(program=p, outputs={"reflectivity": 1}))
    scene.set_light("key", point_light(10))
    job = wn.RenderJob(scene, wn.Settings(width=8, height=8))
    finish(job)
    reflection = next(e for e in job.stats()["effects"] if e["name"] == "reflection")
    assert reflection["on"], reflection
    # Rays leave where u > 0 (every column but the u = 0 edge): the same count as pixels with
    # a non-zero weight would send, at most one per pixel.
    assert 0 < job.stats()["rays"]["reflection"] <= 64


def test_world_program_gives_the_background_by_direction():
    # |direction|: a camera looking straight down sees (0, 0, 1) in the middle.
    absolute = wn.VECTOR_MATH_OPS.index("ABSOLUTE")
    scene = wn.Scene()
    scene.background = (0.5, 0.5, 0.5)
    scene.camera = looking_down(5.0, 1.0)
    scene.set_world(program([(INPUT, 0, 0), (VECTOR_MATH, absolute, 0, 0)], [0] * 4), 0)
    image = finish(wn.RenderJob(scene, wn.Settings(width=3, height=3)))
    np.testing.assert_allclose(image[1, 1, :3], [0, 0, 1], atol=1e-6)
    corner = np.abs(np.array([-2 / 3, -2 / 3, -1.0]))
    np.testing.assert_allclose(image[0, 0, :3], corner / np.linalg.norm(corner), rtol=1e-5)
    # An environment image: straight down is its bottom row (v = 0), red; up its top, green.
    pixels = np.array([[[1, 0, 0, 1]] * 2, [[0, 1, 0, 1]] * 2], np.float32)
    scene.set_texture("sky", wn.ImageTexture(pixels, interpolation=wn.Interpolation.CLOSEST))
    scene.set_world(
        program([(INPUT, 0, 0), (ENVIRONMENT, 0, 0, 0, U, U, U, 0)], [0] * 4, textures=["sky"]), 0
    )
    image = finish(wn.RenderJob(scene, wn.Settings(width=3, height=3)))
    np.testing.assert_array_equal(image[1, 1, :3], [1, 0, 0])
    scene.set_world(None, 0)  # back to the constant
    image = finish(wn.RenderJob(scene, wn.Settings(width=3, height=3)))
    np.testing.assert_array_equal(image[..., :3], 0.5)


def test_world_program_gives_the_ambient_its_upward_mean():
    # L = z of the direction: weighted by cos(theta)/pi over the upper hemisphere, the
    # mean of cos(theta) is 2/3 (24 x 24 directions: within 1e-3).
    swizzle = 7
    scene = wn.Scene()
    scene.ambient = (0.25, 0.25, 0.25)
    assert scene.ambient == (0.25, 0.25, 0.25)  # without a program, the one set
    z = program([(INPUT, 0, 1), (swizzle, 2, 0, 1)], [0] * 8)
    scene.set_world(z, 0, ambient_strength=0.5)
    np.testing.assert_allclose(scene.ambient, (0.5 * 2.0 / 3.0,) * 3, rtol=1e-3)
    scene.set_world(z, 0, ambient_strength=0.0)  # a world that lights no diffuse surface
    assert scene.ambient == (0.0, 0.0, 0.0)
    scene.set_world(None, 0)
    assert scene.ambient == (0.25, 0.25, 0.25)


def test_uv_sets_attributes_and_instance_info_reach_input():
    m = 2
    uv0 = np.zeros((m, 3, 2), np.float32)
    uv1 = np.full((m, 3, 2), 0.25, np.float32)
    colour = np.tile(np.array([0.1, 0.2, 0.3, 0.4], np.float32), (m, 3, 1))
    weight = np.zeros((m, 3, 4), np.float32)
    weight[..., 0] = 0.7
    tangents = np.zeros((m, 3, 4), np.float32)

    def emission_of(mode):
        material = wn.Material(
            **GLOW, program=program([(INPUT, mode, 0)], [0] * 4), outputs={"emission": 0}
        )
        scene = plane_scene(
            material, uv_sets=[uv0, uv1], attributes=[colour, weight], tangents=[tangents]
        )
        scene.set_instance(
            "plane", "plane", np.eye(4), ["m"], info=(1, 2, 3, 0.625, 7, 0.5, 0.25, 0.125, 1)
        )
        return finish(wn.RenderJob(scene, wn.Settings(width=2, height=2)))[0, 0, :3]

    np.testing.assert_array_equal(emission_of(UV + 1), [0.25, 0.25, 0])
    np.testing.assert_array_equal(emission_of(UV), [0, 0, 0])  # uv_sets[0], not `uvs`
    np.testing.assert_array_equal(emission_of(UV + 2), [0, 0, 0])  # no such set: zero
    np.testing.assert_allclose(emission_of(ATTRIBUTE), [0.1, 0.2, 0.3], rtol=1e-6)
    np.testing.assert_allclose(emission_of(ATTRIBUTE + 1), [0.7, 0, 0], rtol=1e-6)
    np.testing.assert_array_equal(emission_of(32), [1, 2, 3])  # location
    np.testing.assert_array_equal(emission_of(33), [0.625] * 3)  # random
    np.testing.assert_array_equal(emission_of(34), [7] * 3)  # pass index
    np.testing.assert_array_equal(emission_of(35), [0.5, 0.25, 0.125])  # colour
    np.testing.assert_array_equal(emission_of(16), [1, 1, 1])  # is camera ray
    np.testing.assert_array_equal(emission_of(20), [0, 0, 0])  # ray depth
    np.testing.assert_array_equal(emission_of(9), [0, 0, 0])  # front face
    with pytest.raises(ValueError, match="one tangent set per UV set"):
        wn.Mesh(*quad(-1, 1, -1, 1, 0), tangents=[tangents])
    with pytest.raises(ValueError, match="each of attributes"):
        wn.Mesh(*quad(-1, 1, -1, 1, 0), attributes=[np.zeros((m, 3, 3), np.float32)])


def test_instance_attributes_reach_input():
    # Each instance's Object and Instancer attributes (RGBA) by index; past the end: 0.
    def emission_of(mode, attributes):
        material = wn.Material(
            **GLOW, program=program([(INPUT, mode, 0)], [0] * 4), outputs={"emission": 0}
        )
        scene = plane_scene(material)
        scene.set_instance("plane", "plane", np.eye(4), ["m"], attributes=attributes)
        return finish(wn.RenderJob(scene, wn.Settings(width=2, height=2)))[0, 0, :3]

    first, second = (0.5, 0.25, 0.125, 1.0), (2.0, 3.0, 4.0, 0.0)
    base = wn.OP_NUMBERS["IN_OBJECT_ATTRIBUTE"]
    np.testing.assert_array_equal(emission_of(base, [first, second]), first[:3])
    np.testing.assert_array_equal(emission_of(base + 1, [first, second]), second[:3])
    np.testing.assert_array_equal(emission_of(base + 1, [first]), [0, 0, 0])
    np.testing.assert_array_equal(emission_of(base, []), [0, 0, 0])
    with pytest.raises(ValueError, match="at most 8 attributes"):
        emission_of(base, [first] * (wn.OP_NUMBERS["OBJECT_ATTRIBUTES"] + 1))
    with pytest.raises(ValueError, match="finite"):
        emission_of(base, [(float("nan"), 0.0, 0.0, 1.0)])
