"""Each node and mode against Cycles: an emission-only plane whose colour is the
node's output, rendered by Cycles with one sample at each pixel centre and nothing
lit, so Cycles' image is the node's value (tests/blender/node_cases.py).

Checked here first at exact points: the material's program run by the native
program on one hit (Program.run) at each pixel's inputs, offsets within Cycles'
filter included, must give Cycles' values. This checks the lowering (which op,
which operands, which modes) and the program's node maths, which the compiler's
constant folding runs too. Cases reading images (sampling) and procedural textures
are checked by the rendered comparison below only.
"""

import bpy
import numpy as np
import pytest
from exported import run_program
from node_cases import CASES, SIZE, NodeCase, build_scene, render, set_cycles, uv_grid
from whitted.export.instance import object_info
from whitted.export.material import convert_material
from whitted.export.nodes import ops
from whitted.export.world import convert_world
from whitted_tools.scenes import background_world

# Cases whose reference needs inputs pixel_inputs does not model.
NOT_RUN = {"texture_coordinate_normal"}


def pixel_inputs(u, v, info):
    x, y = 2.0 * u - 1.0, 2.0 * v - 1.0
    # Cycles measures a camera ray from its near clip distance: the camera looks down at
    # the plane (z = 0) from its height.
    camera = bpy.context.scene.camera
    ray_length = camera.location.z - camera.data.clip_start
    # Point attributes, interpolated over the quad's triangles (0, 1, 2) and (0, 2, 3).
    corners = np.array([(-1, -1), (1, -1), (1, 1), (-1, 1)], dtype=np.float64)
    paint = np.array([[0.9, 0.1, 0.1, 1], [0.1, 0.9, 0.1, 1], [0.1, 0.1, 0.9, 1], [1, 1, 1, 1]])
    height = np.array([0.0, 0.25, 0.5, 1.0])
    triangle = (0, 1, 2) if y <= x else (0, 2, 3)
    a, b, c = corners[list(triangle)]
    matrix = np.array([[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]])
    s, t = np.linalg.solve(matrix, np.array([x - a[0], y - a[1]]))
    weights = np.array([1.0 - s - t, s, t])
    color = weights @ paint[list(triangle)]
    # The triangle's corners (world: the plane lies at z = 0).
    vertices = {ops.IN_TRIANGLE + k: (*corners[i], 0.0, 0.0) for k, i in enumerate(triangle)}
    h = float(weights @ height[list(triangle)])
    inputs = {
        ops.IN_POSITION: (x, y, 0.0, 0.0),
        ops.IN_NORMAL: (0.0, 0.0, 1.0, 0.0),
        ops.IN_TRUE_NORMAL: (0.0, 0.0, 1.0, 0.0),
        ops.IN_INCOMING: (0.0, 0.0, 1.0, 0.0),
        ops.IN_GENERATED: (u, v, 0.5, 0.0),
        ops.IN_OBJECT: (x, y, 0.0, 0.0),
        ops.IN_CAMERA: (x, y, -5.0, 0.0),  # Blender's camera space, looking down -Z
        ops.IN_WINDOW: (u, v, 0.0, 0.0),
        ops.IN_REFLECTION: (0.0, 0.0, 1.0, 0.0),
        ops.IN_BACKFACING: (0.0,) * 4,
        ops.IN_IS_CAMERA_RAY: (1.0,) * 4,
        ops.IN_IS_SHADOW_RAY: (0.0,) * 4,
        ops.IN_IS_REFLECTION_RAY: (0.0,) * 4,
        ops.IN_IS_TRANSMISSION_RAY: (0.0,) * 4,
        ops.IN_RAY_DEPTH: (0.0,) * 4,
        ops.IN_IS_DIFFUSE_RAY: (0.0,) * 4,
        ops.IN_IS_SINGULAR_RAY: (0.0,) * 4,
        ops.IN_RAY_LENGTH: (ray_length,) * 4,
        **vertices,
        ops.IN_OBJECT_LOCATION: (*info[0:3], 0.0),
        ops.IN_OBJECT_RANDOM: (info[3],) * 4,
        ops.IN_OBJECT_INDEX: (info[4],) * 4,
        ops.IN_OBJECT_COLOR: tuple(info[5:9]),
        ops.IN_UV: (u, v, 0.0, 0.0),
    }
    return inputs, tuple(color), h


def reference_images(exported, info, offsets):
    """The reference at each pixel, sampled at the pixel centre moved by each of
    `offsets` (in pixels): float64[len(offsets), SIZE, SIZE, 3]."""
    images = np.zeros((len(offsets), SIZE, SIZE, 3))
    if exported.program is None:
        images[:] = exported.data.emission
        return images
    register = dict(exported.outputs)["emission"]
    for k, (du, dv) in enumerate(offsets):
        for row, columns in enumerate(uv_grid()):
            for column, (u, v) in enumerate(columns):
                inputs, color, height = pixel_inputs(u + du / SIZE, v + dv / SIZE, info)
                for index, (kind, _) in enumerate(exported.attributes):
                    value = color if kind == "COLOR" else (height, height, height, 1.0)
                    inputs[ops.IN_ATTRIBUTE + index] = value
                images[k, row, column] = run_program(exported.program, inputs)[register][:3]
    return images


def pixel_grid(exported, info, row, column, steps=9):
    """float64[steps, steps, 3]: the reference over a grid of the pixel's square."""
    register = dict(exported.outputs)["emission"]
    u0, v0 = uv_grid()[row, column]
    values = []
    for du in np.linspace(-JITTER, JITTER, steps):
        for dv in np.linspace(-JITTER, JITTER, steps):
            inputs, color, height = pixel_inputs(u0 + du / SIZE, v0 + dv / SIZE, info)
            for index, (kind, _) in enumerate(exported.attributes):
                value = color if kind == "COLOR" else (height, height, height, 1.0)
                inputs[ops.IN_ATTRIBUTE + index] = value
            values.append(run_program(exported.program, inputs)[register][:3])
    return np.array(values).reshape(steps, steps, 3)


# Cycles' one sample lands within its 0.01-pixel filter around the centre: the
# reference is taken at the centre and at the corners of a square twice that size,
# and Cycles must lie within their range, widened by the case's tolerance (which also
# covers a discontinuity).
JITTER = 0.01
OFFSETS = [(0.0, 0.0)] + [(du, dv) for du in (-JITTER, JITTER) for dv in (-JITTER, JITTER)]


@pytest.mark.parametrize(
    "case", [c for c in CASES if not c.image and not c.procedural], ids=lambda c: c.name
)
def test_compiler_reference_matches_cycles(case, empty_scene, tmp_path):
    material = build_scene(empty_scene, case)
    set_cycles(empty_scene)
    cycles = render(empty_scene, "CYCLES", str(tmp_path), case.name)
    if case.name in NOT_RUN:
        pytest.skip("its inputs are not modelled by pixel_inputs")
    warnings = []
    exported = convert_material(material, warnings)
    assert warnings == []
    depsgraph = bpy.context.evaluated_depsgraph_get()
    info = None
    for instance in depsgraph.object_instances:
        if instance.object.name == "Plane":
            info = object_info(instance)
    images = reference_images(exported, info, OFFSETS)
    tolerance = case.tolerance
    low, high = images.min(axis=0) - tolerance, images.max(axis=0) + tolerance
    outside = np.maximum(low - cycles, cycles - high)
    # Near a discontinuity the corners miss values inside the square: try a grid.
    # Each cell of the grid is continuous but for a measure-zero set: Cycles' value
    # must lie within the range of the four corners of some cell.
    for row, column in zip(*np.nonzero((outside > 0.0).any(axis=-1)), strict=True):
        grid = pixel_grid(exported, info, row, column)
        cells = np.stack([grid[:-1, :-1], grid[1:, :-1], grid[:-1, 1:], grid[1:, 1:]])
        lo, hi = cells.min(axis=0) - tolerance, cells.max(axis=0) + tolerance
        value = cycles[row, column]
        miss = np.maximum(lo - value, value - hi).reshape(-1, 3).min(axis=0)
        # Where the reference jumps inside the square, the sample may sit as close to
        # the jump as it likes: any value within the square's range is right.
        jumps = (cells.max(axis=0) - cells.min(axis=0)).max(axis=(0, 1)) > 100 * tolerance
        # The grid's points stop short of the jump by up to one step: widen the range
        # by twice the largest step between neighbours that is not the jump itself.
        steps = np.concatenate(
            [
                np.abs(np.diff(grid, axis=0)).reshape(-1, 3),
                np.abs(np.diff(grid, axis=1)).reshape(-1, 3),
            ]
        )
        margin = 2.0 * np.percentile(steps, 90, axis=0) + tolerance
        hull = np.maximum(
            grid.min(axis=(0, 1)) - margin - value, value - grid.max(axis=(0, 1)) - margin
        )
        outside[row, column] = np.where(jumps & (hull <= 0.0), hull, miss)
    error = np.abs(images[0] - cycles)
    print(f"\n{case.name}: max |reference - Cycles| = {error.max():.2e}")
    worst = np.unravel_index(np.argmax(outside), outside.shape)
    assert outside.max() <= 0.0, (
        f"{case.name}: at pixel {worst[:2]} channel {worst[2]}: reference "
        f"{low[worst]!r}..{high[worst]!r}, Cycles {cycles[worst]!r}"
    )


# Whitted's renders against Cycles' (the native program). Bounds: images 1e-3 (the
# issue's); every other node 2e-4 plus what the value changes within Cycles' filter
# (the same bracket as above), except the entries here, measured and stated in
# docs/SUPPORT.md.
WHITTED_BOUNDS = {}
IMAGE_BOUND = 1e-3
VALUE_BOUND = 2e-4
PROCEDURAL_BOUND = 2e-5  # hashed textures, value for value (Cycles' own float rounding)
# The Noise Texture's Color output evaluates its second and third channels at the point
# moved by a seed offset of 100 to 200 on each axis, where a float's spacing is 1.5e-5:
# one rounding of p * scale + offset taken differently (a fused multiply-add, say)
# moves the value by that times the noise's slope (up to about 2). Cycles 5.2 differs
# from Whitted by up to 3.1e-5 there (4D, 2.4e-5 3D, 1.8e-5 2D with no distortion) and
# by at most 1.1e-6 on the Fac outputs (near the origin); Cycles 5.0 by 8.2e-6.
OFFSET_NOISE_BOUND = 5e-5


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_whitted_matches_cycles(case, empty_scene, tmp_path, native):
    if not hasattr(native, "Program"):
        pytest.fail("whitted_native has no Program: rebuild it (cmake --build build)")
    build_scene(empty_scene, case)
    set_cycles(empty_scene)
    cycles = render(empty_scene, "CYCLES", str(tmp_path), case.name)
    whitted = render(empty_scene, "WHITTED", str(tmp_path), case.name)
    error = np.abs(whitted - cycles)
    # Where the value changes fast (or jumps) within a pixel, Cycles' sample may sit
    # off the centre: compare against the neighbourhood of Cycles' own image too.
    slope = np.maximum(*(np.abs(g) for g in np.gradient(cycles, axis=(0, 1))))
    bound = WHITTED_BOUNDS.get(case.name, IMAGE_BOUND if case.image else VALUE_BOUND)
    if case.procedural:  # constant over each pixel: no allowance for Cycles' offset
        bound, slope = PROCEDURAL_BOUND, np.zeros_like(slope)
        if case.name.startswith("noise_") and case.name.endswith("_color"):
            bound = OFFSET_NOISE_BOUND
    # float32 on both sides: the bound is relative where values are large (tangent).
    excess = error - (bound * np.maximum(1.0, np.abs(cycles)) + 0.02 * slope)
    # Pixels on a discontinuity of the node (a step far above the image's typical
    # one) are where one sample of either renderer may fall on either side.
    typical = np.median(slope, axis=(0, 1)) + 1e-6
    smooth = ~((slope > 20.0 * typical) & (slope > 1e-2))
    measured = float(error[smooth].max()) if smooth.any() else 0.0
    print(f"\n{case.name}: max |Whitted - Cycles| = {measured:.2e} (all pixels {error.max():.2e})")
    RESULTS[case.name] = measured
    bad = (np.where(smooth, excess, -1.0) > 0.0).any(axis=-1)
    if case.name in DISCONTINUOUS:
        # Functions with jumps (or poles) where the jump falls inside a pixel: a few
        # pixels where Cycles' sample, off the centre, lands on the other side.
        assert bad.sum() <= 3, f"{case.name}: {bad.sum()} pixels differ"
        smooth &= ~bad[..., None]
    worst = np.unravel_index(np.argmax(np.where(smooth, excess, -1.0)), excess.shape)
    assert (excess[smooth] <= 0.0).all(), (
        f"{case.name}: pixel {worst[:2]}: Whitted {whitted[worst[:2]]}, Cycles {cycles[worst[:2]]}"
    )


RESULTS = {}  # case name -> measured max error (smooth pixels), for the report

# Nodes with jumps or poles inside the tested range (Whitted samples the pixel centre
# exactly: test_compiler_reference_matches_cycles checks Cycles there).
DISCONTINUOUS = {
    f"math_{name}"
    for name in (
        "modulo",
        "floored_modulo",
        "wrap",
        "snap",
        "pingpong",
        "tangent",
        "floor",
        "ceil",
        "round",
        "trunc",
        "fract",
        "compare",
        "less_than",
        "greater_than",
        "sign",
    )
}


@pytest.mark.parametrize("kelvin", [800.0, 1500.0, 3000.0, 6500.0, 12000.0])
@pytest.mark.parametrize("owner", ["surface", "world"])
def test_a_constant_blackbody_colours_as_in_cycles(kelvin, owner, empty_scene, tmp_path):
    # The Blackbody node of a constant temperature colouring an Emission surface, or the
    # world's Background the camera sees past the plane: folded by the compiler (no
    # program), within 1% of Cycles' colour per channel (0 where Cycles clamps it).
    def blackbody(tree):
        node = tree.nodes.new("ShaderNodeBlackbody")
        node.inputs["Temperature"].default_value = kelvin
        return node.outputs["Color"]

    material = build_scene(
        empty_scene, NodeCase("blackbody", lambda tree, uv: blackbody(tree), "Blackbody")
    )
    if owner == "world":
        empty_scene.objects["Plane"].hide_render = True
        world = background_world("Glow", (0.0, 0.0, 0.0))
        tree = world.node_tree
        background = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBackground")
        tree.links.new(blackbody(tree), background.inputs["Color"])
        empty_scene.world = world
        warnings = []
        data = convert_world(world, 0.0, warnings)
        assert data.program is None and not warnings, warnings
        folded = data.background
    else:
        warnings = []
        exported = convert_material(material, warnings)
        assert exported.program is None and not warnings, warnings
        folded = exported.data.emission
    set_cycles(empty_scene)
    cycles = render(empty_scene, "CYCLES", str(tmp_path), "blackbody").reshape(-1, 3)
    whitted = render(empty_scene, "WHITTED", str(tmp_path), "blackbody").reshape(-1, 3)
    colour = cycles.mean(axis=0)
    print(f"\n{owner} {kelvin:.0f} K: Cycles {colour}, Whitted {whitted.mean(axis=0)}")
    assert np.ptp(cycles, axis=0).max() < 1e-6  # one colour
    for image in (whitted, np.asarray(folded)[None, :3]):
        expected = np.broadcast_to(colour, image.shape)
        np.testing.assert_allclose(image, expected, rtol=0.01, atol=1e-6)
