"""A material's Volume output as a homogeneous medium (issue 48): the constant
coefficients Cycles' volume closures give, for the native material's volume_absorption,
volume_scattering, volume_anisotropy and volume_emission (native integrator/volume.h).

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
  Color)) * Density (each factor at least 0); emission Emission Strength * Emission Color,
  not scaled by Density nor by a Mix Shader's factor (Cycles' emission_setup there takes
  the product alone).
- Emission (as a volume): its Color * Strength per unit of length.
- Add Shader sums, Mix Shader weighs its two by 1 - Fac and Fac (Fac clamped to [0, 1]).

Several scatterings keep one Henyey-Greenstein lobe whose anisotropy is their mean
weighted by the scattering (Cycles keeps a lobe each). A linked input (a texture, an
attribute: a heterogeneous volume), Blackbody emission and other nodes are not rendered
yet: the material's report line says which.
"""

from dataclasses import dataclass

from .nodes.graph import source


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


class NotHomogeneous(ValueError):
    """A volume shader this slice does not render; its message says why."""


def homogeneous_medium(output_node):
    """The Medium of a material output node's Volume input (None when nothing is linked);
    raises NotHomogeneous naming what is not rendered."""
    socket = output_node.inputs.get("Volume")
    if socket is None or source(socket)[0] is None:
        return None
    return _combined(_closure(socket, 1.0))


def _closure(socket, weight, scope=()):
    """The parts of the volume closure feeding `socket` (inside the node groups `scope`),
    each scaled by `weight`: one (sigma_a, sigma_s, g, emission) a closure."""
    found, _socket = source(socket, scope)
    if found is None or weight == 0.0:
        return []
    node = _Node(found.node, found.scope)
    kind = node.bl_idname
    if kind == "ShaderNodeAddShader":
        return _closure(node.inputs[0], weight, node.scope) + _closure(
            node.inputs[1], weight, node.scope
        )
    if kind == "ShaderNodeMixShader":
        fac = min(max(_value(node, "Fac"), 0.0), 1.0)
        return _closure(node.inputs[1], weight * (1.0 - fac), node.scope) + _closure(
            node.inputs[2], weight * fac, node.scope
        )
    if kind == "ShaderNodeVolumeAbsorption":
        density = weight * max(_value(node, "Density"), 0.0)
        colour = _colour(node, "Color")
        return [(tuple((1.0 - c) * density for c in colour), _BLACK, 0.0, _BLACK)]
    if kind == "ShaderNodeVolumeScatter":
        phase = getattr(node.node, "phase", "HENYEY_GREENSTEIN")  # Blender 4.3+ has others
        if phase != "HENYEY_GREENSTEIN":
            raise NotHomogeneous(f"its Volume Scatter's {phase} phase function is not rendered")
        density = weight * max(_value(node, "Density"), 0.0)
        scattering = tuple(c * density for c in _colour(node, "Color"))
        return [(_BLACK, scattering, _value(node, "Anisotropy"), _BLACK)]
    if kind == "ShaderNodeVolumePrincipled":
        return [_principled(node, weight)]
    if kind == "ShaderNodeEmission":
        strength = weight * _value(node, "Strength")
        return [(_BLACK, _BLACK, 0.0, tuple(c * strength for c in _colour(node, "Color")))]
    raise NotHomogeneous(f"its {node.bl_idname} node '{node.name}' is not a volume shader rendered")


def _principled(node, weight):
    """Principled Volume's part (module docstring)."""
    if _value(node, "Blackbody Intensity") > 0.0:
        raise NotHomogeneous(f"its Principled Volume '{node.name}' has blackbody emission")
    density = weight * max(_value(node, "Density"), 0.0)
    colour = _colour(node, "Color")
    tint = _colour(node, "Absorption Color")
    absorption = tuple(
        max(1.0 - c, 0.0) * max(1.0 - max(a, 0.0) ** 0.5, 0.0) * density
        for c, a in zip(colour, tint, strict=True)
    )
    scattering = tuple(c * density for c in colour)
    strength = _value(node, "Emission Strength")
    emission = tuple(c * strength for c in _colour(node, "Emission Color"))
    return (absorption, scattering, _value(node, "Anisotropy"), emission)


_BLACK = (0.0, 0.0, 0.0)


def _combined(parts):
    """The sum of the parts, their anisotropy the scattering-weighted mean."""
    absorption = [0.0, 0.0, 0.0]
    scattering = [0.0, 0.0, 0.0]
    emission = [0.0, 0.0, 0.0]
    g_sum = 0.0
    g_weight = 0.0
    for sigma_a, sigma_s, g, e in parts:
        for i in range(3):
            absorption[i] += sigma_a[i]
            scattering[i] += sigma_s[i]
            emission[i] += e[i]
        share = sum(sigma_s) / 3.0
        g_sum += g * share
        g_weight += share
    anisotropy = g_sum / g_weight if g_weight > 0.0 else 0.0
    return Medium(tuple(absorption), tuple(scattering), anisotropy, tuple(emission))


class _Node:
    """A node met in a volume's graph, with the node groups it is inside."""

    def __init__(self, node, scope):
        self.node = node
        self.scope = scope
        self.bl_idname = node.bl_idname
        self.name = node.name
        self.inputs = node.inputs


def _input(node, name):
    """The socket whose value `node`'s input `name` takes (a group node's, where it comes
    from a group's input); raises NotHomogeneous where a link drives it."""
    found, socket = source(node.inputs[name], node.scope)
    if found is not None:
        raise NotHomogeneous(
            f"its {node.name}'s {name} is linked (a heterogeneous volume is not rendered yet)"
        )
    return socket


def _value(node, name):
    return float(_input(node, name).default_value)


def _colour(node, name):
    return tuple(float(c) for c in _input(node, name).default_value[:3])


def volume_bounces_warning(scene, materials):
    """The report's line when media are rendered and the scene asks Cycles for volume
    bounces (Render > Light Paths > Max Bounces > Volume, `scene.cycles.volume_bounces`),
    which Whitted does not trace; None otherwise. `materials`: the exported materials'
    native data."""
    cycles = getattr(scene, "cycles", None)
    bounces = getattr(cycles, "volume_bounces", 0)
    scattering = any(max(m.volume_scattering) > 0.0 for m in materials)
    if bounces <= 0 or not scattering:
        return None
    return (
        f"Whitted: Volume Bounces is {bounces} (Light Paths): media scatter light once, "
        "as Cycles renders them with Volume Bounces 0"
    )
