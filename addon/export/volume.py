"""A material's Volume output as a medium (issue 48): the coefficients Cycles' volume
closures give, for the native material's volume_absorption, volume_scattering,
volume_anisotropy and volume_emission (native integrator/volume.h, heterogeneous.h).

Units: Cycles reads a volume's Density per Blender unit of length (per metre at unit
scale 1), and so do these coefficients: sigma_a and sigma_s in 1/unit, emission in
radiance per unit of length. What each node gives, as Cycles' SVM sets its closures up
(svm_node_closure_volume, svm_node_principled_volume; read in Blender 3.4 and 4.x
sources):

- Volume Absorption: sigma_a = (1 - Color) * Density.
- Volume Scatter: sigma_s = Color * Density (its extinction is sigma_s: it absorbs
  nothing), Henyey-Greenstein of its Anisotropy.
- Principled Volume: sigma_s = Color * Density, extinction (Color + (1 - Color) *
  (1 - sqrt(Absorption Color))) * Density, so sigma_a = (1 - Color) * (1 - sqrt(Absorption
  Color)) * Density (each factor at least 0); emission Emission Strength * Emission Color
  plus the blackbody emission where Blackbody Intensity is above 0: Blackbody Tint * sigma *
  mix(1, T^4, Blackbody Intensity) * the black body's colour at T (shader/blackbody.h, not
  clamped), T = max(Temperature, 0) in kelvin and sigma Stefan-Boltzmann's constant * 1e-6
  / pi (_blackbody_emission). The emission is not scaled by Density; by a Mix Shader's
  factor in Blender 5.0 (seen; its Cycles multiplies it by the closure's weight), not in
  3.4 (seen: its emission_setup takes the product alone). Cycles keeps the black body's
  negative channels; the native material clamps a medium's emission at 0.
- Emission (as a volume): its Color * Strength per unit of length.
- Add Shader sums, Mix Shader weighs its two by 1 - Fac and Fac (Fac clamped to [0, 1]).

Several scatterings keep one Henyey-Greenstein lobe whose anisotropy is their mean
weighted by the scattering (Cycles keeps a lobe each).

Where every input is a constant the medium is homogeneous: these constants (a `Medium`),
computed in Python as always. Where a link drives one (a Noise Texture through a Color
Ramp, Texture Coordinate, Math: anything export/nodes lowers), the same formulas, written
once over an algebra (`_Constants`, `_Program`), become expressions of the material's
program (its volume_* fields), which the native scene runs at points inside the mesh
(CompiledScene::medium: Generated and Object there are the point in the mesh's texture
space and in object space, as in Cycles). A link whose value folds to a constant (a Value
node) gives a homogeneous medium of those float32 values. Other phase functions than
Henyey-Greenstein and other nodes are not rendered: the material's report line says which.
"""

import math
from dataclasses import dataclass

import bpy

from ..native import load_native
from .nodes import ops
from .nodes.graph import source
from .nodes.ir import COLOR, FLOAT


@dataclass(frozen=True)
class Medium:
    """A homogeneous medium, per Blender unit of length (module docstring)."""

    absorption: tuple = (0.0, 0.0, 0.0)
    scattering: tuple = (0.0, 0.0, 0.0)
    anisotropy: float = 0.0
    emission: tuple = (0.0, 0.0, 0.0)

    def fields(self):
        """The native material's keywords (MATERIAL_PARAMS) for this medium."""
        return {
            "volume_absorption": self.absorption,
            "volume_scattering": self.scattering,
            "volume_anisotropy": self.anisotropy,
            "volume_emission": self.emission,
        }


class NotRendered(ValueError):
    """A volume shader Whitted does not render; its message says why."""


VOLUME_FIELDS = ("volume_absorption", "volume_scattering", "volume_anisotropy", "volume_emission")


def volume_medium(output_node, lowering):
    """What a material output node's Volume input fills its meshes with: None (nothing is
    linked), a Medium (a homogeneous medium), or {field: Expr} of VOLUME_FIELDS (a
    heterogeneous one, lowered with `lowering`, a nodes.values.Lowering); raises
    NotRendered naming what is not rendered."""
    socket = output_node.inputs.get("Volume")
    if socket is None or source(socket)[0] is None:
        return None
    constants = _Constants(lowering.grids)
    try:
        return Medium(*_combined(constants, _closure(constants, socket, 1.0)))
    except _Linked:
        pass
    program = _Program(lowering)
    return _folded(_combined(program, _closure(program, socket, program.object_density())))


def default_volume(lowering):
    """What a Volume object without a material fills its bounds with: Cycles' default
    volume, a Principled Volume of the node's defaults (Color 0.5, Density 1 scaled by
    the grid "density", Absorption Color black, no emission), as volume_medium gives."""
    program = _Program(lowering)
    density = program.object_density()
    grid = lowering.grid("density", "density")
    if grid is not None:
        density = program.positive(program.mul(density, grid))
    # sigma_s = 0.5 density; sigma_a = (1 - 0.5) (1 - sqrt(0)) density.
    half = program.scale(lowering.b.const((0.5, 0.5, 0.5), COLOR), density)
    return _folded((half, half, program.f(0.0), program.black()))


def _folded(coefficients):
    """(sigma_a, sigma_s, g, emission) as Exprs: a Medium where all are constants, else
    {field: Expr} of VOLUME_FIELDS."""
    absorption, scattering, anisotropy, emission = coefficients
    exprs = dict(zip(VOLUME_FIELDS, coefficients, strict=True))
    if all(e.is_const for e in exprs.values()):
        return Medium(
            tuple(absorption.value[:3]),
            tuple(scattering.value[:3]),
            anisotropy.value[0],
            tuple(emission.value[:3]),
        )
    return exprs


def _closure(alg, socket, weight, scope=()):
    """The parts of the volume closure feeding `socket` (inside the node groups `scope`),
    each scaled by `weight`: one (sigma_a, sigma_s, g, emission) a closure, in the
    algebra `alg`."""
    found, _socket = source(socket, scope)
    if found is None or alg.is_zero(weight):
        return []
    node = _Node(found.node, found.scope)
    kind = node.bl_idname
    if kind == "ShaderNodeAddShader":
        return _closure(alg, node.inputs[0], weight, node.scope) + _closure(
            alg, node.inputs[1], weight, node.scope
        )
    if kind == "ShaderNodeMixShader":
        fac = alg.clamp01(alg.value(node, "Fac"))
        return _closure(
            alg, node.inputs[1], alg.mul(weight, alg.sub(alg.f(1.0), fac)), node.scope
        ) + _closure(alg, node.inputs[2], alg.mul(weight, fac), node.scope)
    if kind == "ShaderNodeVolumeAbsorption":
        density = alg.mul(weight, alg.positive(alg.value(node, "Density")))
        absorption = alg.scale(alg.one_minus(alg.colour(node, "Color")), density)
        return [(absorption, alg.black(), alg.f(0.0), alg.black())]
    if kind == "ShaderNodeVolumeScatter":
        phase = getattr(node.node, "phase", "HENYEY_GREENSTEIN")  # Blender 4.3+ has others
        if phase != "HENYEY_GREENSTEIN":
            raise NotRendered(f"its Volume Scatter's {phase} phase function is not rendered")
        density = alg.mul(weight, alg.positive(alg.value(node, "Density")))
        scattering = alg.scale(alg.colour(node, "Color"), density)
        return [(alg.black(), scattering, alg.value(node, "Anisotropy"), alg.black())]
    if kind == "ShaderNodeVolumePrincipled":
        return [_principled(alg, node, weight)]
    if kind == "ShaderNodeEmission":
        strength = alg.mul(weight, alg.value(node, "Strength"))
        return [
            (alg.black(), alg.black(), alg.f(0.0), alg.scale(alg.colour(node, "Color"), strength))
        ]
    raise NotRendered(f"its {node.bl_idname} node '{node.name}' is not a volume shader rendered")


def _principled(alg, node, weight):
    """Principled Volume's part (module docstring)."""
    density = alg.mul(weight, alg.positive(alg.value(node, "Density")))
    # A Volume object's grids scale what their attributes name (Cycles: an attribute not
    # found scales nothing).
    grid = alg.attribute(node, "density", "Density Attribute")
    if grid is not None:
        density = alg.positive(alg.mul(density, grid))
    colour = alg.colour(node, "Color")
    grid = alg.attribute(node, "color", "Color Attribute", COLOR)
    if grid is not None:
        colour = alg.product(colour, grid)
    tint = alg.colour(node, "Absorption Color")
    kept = alg.product(
        alg.clamped(alg.one_minus(colour)),
        alg.clamped(alg.one_minus(alg.root(alg.clamped(tint)))),
    )
    absorption = alg.scale(kept, density)
    scattering = alg.scale(colour, density)
    emission = alg.scale(alg.colour(node, "Emission Color"), alg.value(node, "Emission Strength"))
    temperature = alg.value(node, "Temperature")
    grid = alg.attribute(node, "temperature", "Temperature Attribute")
    if grid is None:
        glow = _blackbody_emission(alg, node, temperature)
    elif not STOCHASTIC_GRID_READS:
        glow = _blackbody_emission(alg, node, alg.mul(temperature, alg.positive(grid)))
    else:
        # Cycles 5.x reads the grid at one of the eight voxels around the point, picked with
        # its trilinear weight, and the glow at that voxel's temperature: on average the
        # weighted sum of the eight glows, brighter than the glow of the interpolated
        # temperature where the voxels differ (T^4 is convex), as at a fire's rim.
        glow = alg.black()
        for voxel, share in alg.voxels("temperature"):
            at_voxel = alg.mul(temperature, alg.positive(voxel))
            glow = alg.plus(glow, alg.scale(_blackbody_emission(alg, node, at_voxel), share))
    emission = alg.plus(emission, glow)
    if _WEIGHTED_EMISSION:
        emission = alg.scale(emission, weight)
    return (absorption, scattering, alg.value(node, "Anisotropy"), emission)


# Whether Cycles reads Principled Volume's grids stochastically (one voxel at a time,
# picked with its trilinear weight: `primitive_volume_attribute(..., stochastic=true)` in
# svm_node_principled_volume since 5.0), which changes what a non-linear use of a grid gives:
# the blackbody glow of the Temperature grid (_principled). Its linear uses (Density,
# Color) give the interpolated value on average, as before. In 3.4 and 4.5 Cycles
# interpolates (seen: the .vdb fireball's glow of tests/blender/test_volume.py).
STOCHASTIC_GRID_READS = bpy.app.version >= (5, 0, 0)


# Whether Cycles scales Principled Volume's emission by the closure's weight (a Mix Shader's
# factor): seen in Blender 5.0, not in 3.4; the 4.x releases between were not tried.
_WEIGHTED_EMISSION = bpy.app.version >= (5, 0, 0)


# Stefan-Boltzmann's law: a black body at T kelvin emits sigma T^4 W/m^2, sigma = 5.670373e-8
# W m^-2 K^-4; its radiance is that over pi. Cycles scales it by 1e-6 more, per unit of
# length in a volume (svm_node_principled_volume).
_BLACKBODY_SIGMA = 5.670373e-8 * 1e-6 / math.pi


def _blackbody_emission(alg, node, temperature):
    """Principled Volume's blackbody emission per unit of length at `temperature` (kelvin, an
    expression of `alg`), as Cycles' svm_node_principled_volume adds it: none where Blackbody
    Intensity is 0 or less, else Blackbody Tint * sigma * mix(1, T^4, Blackbody Intensity) *
    blackbody_rgb(T), T = max(temperature, 0). Where a link drives Blackbody Intensity the
    program takes it at least 0 instead (a glow of sigma * blackbody_rgb(T), below 1e-13 per
    unit of length, where Cycles has none); Cycles 3.4 also skips an intensity below 1e-5
    (CLOSURE_WEIGHT_CUTOFF), a glow below 1e-5 per unit of length, kept here."""
    blackbody = alg.positive(alg.value(node, "Blackbody Intensity"))
    if alg.is_zero(blackbody):
        return alg.black()
    kelvin = alg.positive(temperature)
    squared = alg.mul(kelvin, kelvin)
    # mix(1, T^4, b) = 1 + b (T^4 - 1)
    mixed = alg.add(alg.f(1.0), alg.mul(blackbody, alg.sub(alg.mul(squared, squared), alg.f(1.0))))
    intensity = alg.mul(alg.f(_BLACKBODY_SIGMA), mixed)
    return alg.product(
        alg.colour(node, "Blackbody Tint"), alg.scale(alg.blackbody(kelvin), intensity)
    )


def _combined(alg, parts):
    """The sum of the parts, their anisotropy the scattering-weighted mean:
    (sigma_a, sigma_s, g, emission)."""
    absorption = scattering = emission = alg.black()
    g_sum = g_weight = alg.f(0.0)
    for sigma_a, sigma_s, g, e in parts:
        absorption = alg.plus(absorption, sigma_a)
        scattering = alg.plus(scattering, sigma_s)
        emission = alg.plus(emission, e)
        share = alg.mean(sigma_s)
        g_sum = alg.add(g_sum, alg.mul(g, share))
        g_weight = alg.add(g_weight, share)
    return absorption, scattering, alg.ratio(g_sum, g_weight), emission


class _Linked(Exception):
    """A link drives an input: the medium is heterogeneous (_Program's)."""


class _Constants:
    """The formulas on Python floats (colours as RGB tuples): a homogeneous medium's
    constants, the order of each product as it always was (its pixels kept). `grids`:
    the Lowering's (a Volume object's grids, or None)."""

    def __init__(self, grids):
        self.grids = grids

    def attribute(self, node, role, name, kind=FLOAT):
        # A grid the object has drives the medium, a program's (_Program, whose signature
        # this shares); an attribute not found scales nothing.
        del kind
        if self.grids is not None and self.grids.get(role) == node.inputs[name].default_value:
            raise _Linked
        return None

    def value(self, node, name):
        return float(self._socket(node, name).default_value)

    def colour(self, node, name):
        return tuple(float(c) for c in self._socket(node, name).default_value[:3])

    @staticmethod
    def _socket(node, name):
        found, socket = source(node.inputs[name], node.scope)
        if found is not None:
            raise _Linked
        return socket

    def blackbody(self, kelvin):
        # The native fit (shader/blackbody.h), in float32 as op BLACKBODY computes it.
        return load_native().blackbody_rgb(kelvin)

    def f(self, x):
        return x

    def black(self):
        return (0.0, 0.0, 0.0)

    def is_zero(self, x):
        return x == 0.0

    def add(self, a, b):
        return a + b

    def sub(self, a, b):
        return a - b

    def mul(self, a, b):
        return a * b

    def ratio(self, a, b):
        return a / b if b > 0.0 else 0.0

    def positive(self, x):
        return max(x, 0.0)

    def clamp01(self, x):
        return min(max(x, 0.0), 1.0)

    def scale(self, c, s):
        return tuple(x * s for x in c)

    def product(self, a, b):
        return tuple(x * y for x, y in zip(a, b, strict=True))

    def plus(self, a, b):
        return tuple(x + y for x, y in zip(a, b, strict=True))

    def one_minus(self, c):
        return tuple(1.0 - x for x in c)

    def clamped(self, c):
        return tuple(max(x, 0.0) for x in c)

    def root(self, c):
        return tuple(x**0.5 for x in c)

    def mean(self, c):
        return sum(c) / 3.0


class _Program:
    """The formulas as Exprs of the material's program (export/nodes/ir.py), linked
    inputs lowered by `lowering`: a heterogeneous medium."""

    def __init__(self, lowering):
        self.lowering = lowering
        self.b = lowering.b

    def value(self, node, name):
        return self.lowering.value(node.inputs[name], node.scope, FLOAT)

    def attribute(self, node, role, name, kind=FLOAT):
        # The grid named by input `name` in `role`, or None (not found: scales nothing).
        return self.lowering.grid(role, node.inputs[name].default_value, kind)

    def voxels(self, role):
        # The eight voxels of the grid in `role` around the point, with their trilinear
        # weights: (value, weight) pairs, the grid present (attribute() found it).
        return self.lowering.grid_voxels(role)

    def object_density(self):
        # Cycles' object_volume_density: every closure's weight inside a Volume object.
        if self.lowering.grids is None:
            return self.f(1.0)
        return self.lowering.hit(ops.IN_VOLUME_DENSITY, FLOAT)

    def colour(self, node, name):
        return self.lowering.value(node.inputs[name], node.scope, COLOR)

    def blackbody(self, kelvin):
        return self.b.op(ops.BLACKBODY, 0, (kelvin,), kind=COLOR)

    def f(self, x):
        return self.b.f(x)

    def black(self):
        return self.b.const((0.0, 0.0, 0.0), COLOR)

    def is_zero(self, x):
        return x.is_const and x.value[0] == 0.0

    def add(self, a, b):
        return self.b.add(a, b)

    def sub(self, a, b):
        return self.b.sub(a, b)

    def mul(self, a, b):
        return self.b.mul(a, b)

    def ratio(self, a, b):
        if self.is_zero(a):
            return a
        return self.b.div(a, b)  # Blender's Divide: 0 where b is 0

    def positive(self, x):
        return self.b.maximum(x, self.b.f(0.0))

    def clamp01(self, x):
        return self.b.clamp01(x)

    def scale(self, c, s):
        return self.b.vmul(s, c)

    def product(self, a, b):
        return self.b.vmul(a, b)

    def plus(self, a, b):
        return self.b.vadd(a, b)

    def one_minus(self, c):
        return self.b.vmath("SUBTRACT", self.b.const((1.0, 1.0, 1.0), COLOR), c, kind=COLOR)

    def clamped(self, c):
        return self.b.vmath("MAXIMUM", c, self.black(), kind=COLOR)

    def root(self, c):
        return self.b.vmath("POWER", c, self.b.const((0.5, 0.5, 0.5), COLOR), kind=COLOR)

    def mean(self, c):
        return self.b.average(c)


class _Node:
    """A node met in a volume's graph, with the node groups it is inside."""

    def __init__(self, node, scope):
        self.node = node
        self.scope = scope
        self.bl_idname = node.bl_idname
        self.name = node.name
        self.inputs = node.inputs


def volume_bounces_warning(scene, materials, world_medium=None):
    """The report's line when media are rendered and the scene asks Cycles for volume
    bounces (Render > Light Paths > Max Bounces > Volume, `scene.cycles.volume_bounces`),
    which Whitted does not trace; None otherwise. `materials`: the exported materials
    (MaterialExport: a heterogeneous medium's scattering is a program output);
    `world_medium`: the world's volume (a Medium), or None."""
    cycles = getattr(scene, "cycles", None)
    bounces = getattr(cycles, "volume_bounces", 0)
    scattering = any(
        max(m.data.volume_scattering) > 0.0
        or any(name == "volume_scattering" for name, _ in m.outputs)
        for m in materials
    ) or (world_medium is not None and max(world_medium.scattering) > 0.0)
    if bounces <= 0 or not scattering:
        return None
    return (
        f"Whitted: Volume Bounces is {bounces} (Light Paths): media scatter light once, "
        "as Cycles renders them with Volume Bounces 0"
    )
