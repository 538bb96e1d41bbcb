"""Blender materials as Whitted parameters: a Phong local term, a mirror and glass.

Colours are linear RGB (Blender's scene linear), as the tracer uses them.

`map_material` is the node mapping: a pure function from a material's node data
to a MaterialExport (Whitted parameters plus the textures they name), reading
no pixels. `convert_material` applies the artist's Whitted override on top.

Each shader node maps to Whitted parameters plus an alpha: the surface returns
`alpha * shade + (1 - alpha) * (what lies behind)`, as the tracer does. A Mix
Shader blends two shaders by those weights (see `_mix`).
"""

import math
from dataclasses import dataclass, replace

from .nodes import find_input, input_value, linked_output, surface_node, uses_nodes
from .nodes import warn as _warn
from .texture import checker_texture_spec, image_texture_spec

Color = tuple[float, float, float]

# Principled BSDF inputs by name, newest name first: Blender 4.0 renamed
# Specular -> Specular IOR Level, Transmission -> Transmission Weight and
# Emission -> Emission Color. Never by index: the order changed too.
PRINCIPLED_INPUTS = {
    "base_color": ("Base Color",),
    "metallic": ("Metallic",),
    "roughness": ("Roughness",),
    "specular": ("Specular IOR Level", "Specular"),
    "specular_tint": ("Specular Tint",),
    "transmission": ("Transmission Weight", "Transmission"),
    "ior": ("IOR",),
    "emission_color": ("Emission Color", "Emission"),
    "emission_strength": ("Emission Strength",),
    "alpha": ("Alpha",),
}

# Values for inputs a node lacks, Blender 3.4's defaults. Emission is black by
# default in 3.x; in 4.x the colour is white but the strength is 0.
PRINCIPLED_DEFAULTS = {
    "base_color": (0.8, 0.8, 0.8, 1.0),
    "metallic": 0.0,
    "roughness": 0.5,
    "specular": 0.5,
    "specular_tint": 0.0,
    "transmission": 0.0,
    "ior": 1.45,
    "emission_color": (0.0, 0.0, 0.0, 1.0),
    "emission_strength": 1.0,
    "alpha": 1.0,
}

# Principled lobes Whitted does not have: when their weight is above 0 they are
# ignored, with a warning (names across versions, newest first).
PRINCIPLED_IGNORED_WEIGHTS = (
    ("Subsurface Weight", "Subsurface"),
    ("Coat Weight", "Clearcoat"),
    ("Sheen Weight", "Sheen"),
    ("Anisotropic",),
    ("Thin Film Thickness",),
)

# Principled inputs the mapping reads (all others are ignored; linked ones warn).
PRINCIPLED_READ = {name for names in PRINCIPLED_INPUTS.values() for name in names}

# Phong exponents past this make highlights smaller than a pixel anyway.
MAX_SHININESS = 10000.0

# Rec. 709 luminance weights (Blender's default scene linear space).
LUMINANCE = (0.2126, 0.7152, 0.0722)

BLACK = (0.0, 0.0, 0.0)
WHITE = (1.0, 1.0, 1.0)


@dataclass(frozen=True)
class MaterialData:
    """The fields of whitted_native.Material."""

    diffuse: Color  # kd, the albedo of the diffuse term kd/pi * E
    specular: Color  # ks of the normalised Phong highlight
    shininess: float  # Phong exponent
    ambient: float  # weight of the ambient term ka * Ia * kd
    reflectivity: Color  # weight of the mirror ray
    transmissivity: Color  # weight of the refracted ray
    ior: float
    emission: Color  # radiance added as is, W/(m^2 sr)
    alpha: float = 1.0  # coverage: 1 - alpha of the light passes straight through
    diffuse_texture: str = ""  # texture name whose RGB multiplies `diffuse`
    alpha_texture: str = ""  # texture name whose A multiplies `alpha`


@dataclass(frozen=True)
class MaterialExport:
    data: MaterialData
    textures: tuple = ()  # ImageTextureSpec / CheckerTextureSpec named by `data`

    @property
    def uv_map(self):
        """The UV map the textures read ("" = the active render map), or None
        when no texture uses UV coordinates."""
        return next((t.uv_map for t in self.textures if t.coordinates == "UV"), None)


# What a material without a surface shader renders as in Cycles.
_BLACK = MaterialData(
    diffuse=BLACK,
    specular=BLACK,
    shininess=1.0,
    ambient=1.0,
    reflectivity=BLACK,
    transmissivity=BLACK,
    ior=1.45,
    emission=BLACK,
)


@dataclass(frozen=True)
class _Context:
    material: object  # bpy.types.Material
    warnings: list

    @property
    def owner(self):
        return f"material '{self.material.name}'"

    def warn(self, node, message):
        _warn(self.warnings, f"Whitted: {self.owner}, node '{node.name}': {message}")


def convert_material(material, warnings):
    """Convert one material: the node mapping, or with the Whitted material
    panel's override on, its values (emission, alpha and textures still come
    from the nodes)."""
    exported = map_material(material, warnings)
    settings = material.whitted
    if not settings.use_override:
        return exported
    data = replace(
        exported.data,
        # The panel splits each colour into a weight and a colour of that weight 1.
        diffuse=tuple(settings.diffuse_weight * c for c in settings.diffuse_color),
        specular=tuple(settings.specular_weight * c for c in settings.specular_color),
        shininess=settings.shininess,
        ambient=settings.ambient,
        reflectivity=tuple(settings.reflectivity),
        transmissivity=tuple(settings.transmissivity),
        ior=settings.ior,
    )
    return replace(exported, data=data)


def map_material(material, warnings):
    """The node mapping: a material's surface shader as Whitted parameters.

    Without nodes, the viewport display values are used. A material without a
    surface shader renders black, as in Cycles.
    """
    if not uses_nodes(material):
        return MaterialExport(_viewport_material(material))
    context = _Context(material, warnings)
    node = surface_node(material.node_tree)
    if node is None:
        _warn(
            warnings,
            f"Whitted: {context.owner} has no surface shader; it renders black, as in Cycles",
        )
        return MaterialExport(_BLACK)
    return _shader(node, context)


def _shader(node, context):
    entry = _SHADERS.get(node.bl_idname)
    if entry is None:
        context.warn(
            node,
            f"shader '{node.bl_idname}' is not supported; "
            "using the material's viewport display colour",
        )
        return MaterialExport(_viewport_material(context.material))
    convert, read = entry
    # Inputs the mapping does not read (Normal, Tangent, ...) are ignored: say so
    # when something is linked to them.
    for socket in node.inputs:
        if socket.name not in read and linked_output(socket) is not None:
            context.warn(node, f"input '{socket.name}' is linked; Whitted ignores it")
    return convert(node, context)


def _principled(node, context):
    values = {
        key: _scalar_or_color(node, names, PRINCIPLED_DEFAULTS[key], context)
        for key, names in PRINCIPLED_INPUTS.items()
        if key not in ("base_color", "alpha")
    }
    base_color, base_texture = _color_input(node, ("Base Color",), (0.8, 0.8, 0.8), context)
    alpha, alpha_texture = _alpha_input(node, context)
    metallic = _clamp(values["metallic"], 0.0, 1.0)
    transmission = _clamp(values["transmission"], 0.0, 1.0)
    ior = values["ior"]
    if base_texture is not None and (metallic > 0.0 or transmission > 0.0):
        context.warn(
            node,
            "a textured Base Color tints only the diffuse term; the metallic and "
            "transmissive parts use white",
        )
    # Dielectric reflectance at normal incidence, F0 (the highlight's weight).
    specular_socket = find_input(node, PRINCIPLED_INPUTS["specular"])
    if specular_socket is not None and specular_socket.name == "Specular IOR Level":
        # 4.x: F0 follows the IOR, ((n-1)/(n+1))^2, scaled by 2 * level (0.5 = as is).
        f0 = _fresnel_f0(ior) * 2.0 * max(0.0, values["specular"])
    else:
        # 3.x: F0 = 0.08 * Specular, whatever the IOR (0.5 -> 0.04, as for IOR 1.5).
        f0 = 0.08 * max(0.0, values["specular"])
    tint = values["specular_tint"]
    if isinstance(tint, float):
        # 3.x: Specular Tint blends white towards the base colour's hue (the base
        # colour over its luminance).
        luminance = sum(w * c for w, c in zip(LUMINANCE, base_color, strict=True))
        hue = tuple(c / luminance for c in base_color) if luminance > 0.0 else WHITE
        tint = tuple(1.0 - tint + tint * h for h in hue)
    else:
        # 4.x: a colour that multiplies the dielectric reflection.
        tint = tint[:3]
    _warn_ignored_principled_inputs(node, context)
    strength = values["emission_strength"]
    data = _whitted_material(
        base_color=base_color,
        metallic=metallic,
        roughness=values["roughness"],
        f0=tuple(f0 * t for t in tint),
        transmission=transmission,
        ior=ior,
        # The Principled BSDF emits Emission Color * Emission Strength as radiance.
        emission=tuple(c * strength for c in values["emission_color"][:3]),
    )
    return _with_textures(data, alpha, base_texture, alpha_texture)


def _warn_ignored_principled_inputs(node, context):
    for names in PRINCIPLED_IGNORED_WEIGHTS:
        socket = find_input(node, names)
        if socket is not None and linked_output(socket) is None and socket.default_value > 0.0:
            context.warn(node, f"'{socket.name}' has no Whitted equivalent; it is ignored")


def _diffuse(node, context):
    color, texture = _color_input(node, ("Color",), (0.8, 0.8, 0.8), context)
    roughness = _scalar_or_color(node, ("Roughness",), 0.0, context)
    if roughness > 0.0:
        context.warn(node, "Oren-Nayar roughness is not supported; the surface is Lambertian")
    # A Lambertian reflector of albedo `color` is exactly Whitted's diffuse term.
    return _with_textures(replace(_BLACK, diffuse=color), 1.0, texture, None)


def _glossy(node, context):
    color = _plain_color(node, ("Color",), (0.8, 0.8, 0.8), context)
    # Blender 3.x's Sharp distribution is a perfect mirror whatever the roughness.
    roughness = (
        0.0
        if node.distribution == "SHARP"
        else _scalar_or_color(node, ("Roughness",), 0.5, context)
    )
    anisotropy = find_input(node, ("Anisotropy",))
    if anisotropy is not None and (linked_output(anisotropy) or anisotropy.default_value != 0.0):
        context.warn(node, "anisotropy is not supported; the highlight is round")
    # A glossy reflector of colour C is a metal of base colour C: sharp -> mirror
    # (reflectivity), rough -> Phong highlight.
    data = _whitted_material(
        base_color=color,
        metallic=1.0,
        roughness=roughness,
        f0=BLACK,
        transmission=0.0,
        ior=1.45,
        emission=BLACK,
    )
    return MaterialExport(data)


def _glass(node, context):
    color = _plain_color(node, ("Color",), (1.0, 1.0, 1.0), context)
    roughness = _scalar_or_color(node, ("Roughness",), 0.0, context)
    ior = _scalar_or_color(node, ("IOR",), 1.45, context)
    # A Principled BSDF of full transmission: refraction weighted by the colour
    # (the tracer's Fresnel moves the reflected share to the mirror ray) and a
    # highlight of the IOR's F0.
    f0 = _fresnel_f0(ior)
    data = _whitted_material(
        base_color=color,
        metallic=0.0,
        roughness=roughness,
        f0=(f0, f0, f0),
        transmission=1.0,
        ior=ior,
        emission=BLACK,
    )
    return MaterialExport(data)


def _refraction(node, context):
    color = _plain_color(node, ("Color",), (1.0, 1.0, 1.0), context)
    ior = _scalar_or_color(node, ("IOR",), 1.45, context)
    # Refraction only: no highlight. The tracer's Fresnel setting (if on) still
    # sends the reflected share to the mirror ray.
    return MaterialExport(replace(_BLACK, transmissivity=color, ior=ior))


def _transparent(node, context):
    color = _plain_color(node, ("Color",), (1.0, 1.0, 1.0), context)
    # Transparent BSDF = coverage: light passes straight through, unbent, with
    # weight `color`, and the surface adds nothing of its own. Whitted's alpha
    # does that for a grey colour exactly (alpha = 1 - grey; camera and shadow
    # rays both pass). Alpha rather than transmissivity with IOR 1, so a Mix with
    # another shader keeps that shader's IOR, and the classic cut-out set-up
    # (Mix of Transparent and a BSDF) is an alpha cut-out.
    grey = sum(color) / 3.0
    if max(color) - min(color) > 1e-6:
        context.warn(node, "a coloured Transparent BSDF is approximated by its mean grey")
    return MaterialExport(replace(_BLACK, alpha=1.0 - _clamp(grey, 0.0, 1.0)))


def _emission(node, context):
    color = _plain_color(node, ("Color",), (1.0, 1.0, 1.0), context)
    strength = _scalar_or_color(node, ("Strength",), 1.0, context)
    # Emission emits Color * Strength as radiance and reflects nothing.
    return MaterialExport(replace(_BLACK, emission=tuple(strength * c for c in color)))


def _mix_shader(node, context):
    # Both shader sockets are called "Shader": by position (1 and 2) here.
    first, second = (_mix_input(node.inputs[index], context) for index in (1, 2))
    factor_socket = find_input(node, ("Factor", "Fac"))
    factor_output = linked_output(factor_socket)
    if factor_output is None:
        return _mix(first, second, _clamp(factor_socket.default_value, 0.0, 1.0), node, context)
    source = factor_output.node
    if (
        source.bl_idname == "ShaderNodeTexImage"
        and factor_output.name == "Alpha"
        and first.data.alpha == 0.0
        and not second.data.alpha_texture
    ):
        # The classic cut-out: Mix(Transparent, BSDF) by an image's alpha is the
        # BSDF with that alpha texture.
        spec = image_texture_spec(source, context.owner, context.warnings)
        if spec is not None:
            data = replace(second.data, alpha_texture=spec.name)
            return MaterialExport(data, (*second.textures, spec))
    context.warn(node, f"Factor linked to '{source.name}' is not supported; using 0.5")
    return _mix(first, second, 0.5, node, context)


def _mix_input(socket, context):
    output = linked_output(socket)
    if output is None:
        # An empty shader socket absorbs everything: black, as in Cycles.
        return MaterialExport(_BLACK)
    return _shader(output.node, context)


def _mix(first, second, factor, node, context):
    """(1 - factor) * first + factor * second.

    Each shader contributes `alpha * shade`; shading is linear in the colour
    parameters, so the mix is a surface of alpha w1 + w2 (w1 = (1 - factor) *
    alpha1, w2 = factor * alpha2) whose colours are the w-weighted means.
    Phong exponent, ambient weight and IOR are not linear: their w-weighted
    means are an approximation.
    """
    if factor == 0.0:
        return first
    if factor == 1.0:
        return second
    a, b = first.data, second.data
    wa = (1.0 - factor) * a.alpha
    wb = factor * b.alpha
    alpha = wa + wb
    if alpha == 0.0:
        return MaterialExport(replace(_BLACK, alpha=0.0))

    def blend(x, y):
        if isinstance(x, float):
            return (wa * x + wb * y) / alpha
        return tuple((wa * xi + wb * yi) / alpha for xi, yi in zip(x, y, strict=True))

    if a.diffuse_texture and b.diffuse_texture and a.diffuse_texture != b.diffuse_texture:
        context.warn(node, "mixes two diffuse textures; only the first one is used")
    elif bool(a.diffuse_texture) != bool(b.diffuse_texture):
        context.warn(
            node, "mixes a textured and an untextured diffuse colour; the texture tints both"
        )
    if a.alpha_texture or b.alpha_texture:
        context.warn(node, "mixes a shader with an alpha texture; the texture covers the whole mix")
    data = MaterialData(
        diffuse=blend(a.diffuse, b.diffuse),
        specular=blend(a.specular, b.specular),
        shininess=blend(a.shininess, b.shininess),
        ambient=blend(a.ambient, b.ambient),
        reflectivity=blend(a.reflectivity, b.reflectivity),
        transmissivity=blend(a.transmissivity, b.transmissivity),
        ior=blend(a.ior, b.ior),
        emission=blend(a.emission, b.emission),
        alpha=alpha,
        diffuse_texture=a.diffuse_texture or b.diffuse_texture,
        alpha_texture=a.alpha_texture or b.alpha_texture,
    )
    return MaterialExport(data, first.textures + second.textures)


# Shader node id -> (its mapping, the names of the inputs that mapping reads).
_GLOSSY = (_glossy, {"Color", "Roughness", "Anisotropy"})
_SHADERS = {
    "ShaderNodeBsdfPrincipled": (_principled, PRINCIPLED_READ),
    "ShaderNodeBsdfDiffuse": (_diffuse, {"Color", "Roughness"}),
    "ShaderNodeBsdfGlossy": _GLOSSY,
    # Blender 4.0 merged Glossy into Anisotropic: the Glossy BSDF has this id there.
    "ShaderNodeBsdfAnisotropic": _GLOSSY,
    "ShaderNodeBsdfGlass": (_glass, {"Color", "Roughness", "IOR"}),
    "ShaderNodeBsdfRefraction": (_refraction, {"Color", "IOR"}),
    "ShaderNodeBsdfTransparent": (_transparent, {"Color"}),
    "ShaderNodeEmission": (_emission, {"Color", "Strength"}),
    "ShaderNodeMixShader": (_mix_shader, {"Fac", "Factor", "Shader"}),
}


def _scalar_or_color(node, names, default, context):
    # A linked input is not evaluated: input_value warns and uses its unlinked value.
    return input_value(node, names, default, context.owner, context.warnings)


def _plain_color(node, names, default, context):
    """An RGB input that cannot take a texture (linked -> warning, unlinked value)."""
    return tuple(_scalar_or_color(node, names, default, context)[:3])


def _color_input(node, names, default, context):
    """(rgb, texture spec or None) of a colour input that may hold a texture.

    A texture multiplies the colour in the tracer, so a textured input's colour is
    white. An Image Texture's Color output or a Checker Texture is a texture;
    anything else linked warns and falls back to the unlinked value.
    """
    socket = find_input(node, names)
    if socket is None:
        return default, None
    output = linked_output(socket)
    if output is not None and output.name == "Color":
        source = output.node
        spec = None
        if source.bl_idname == "ShaderNodeTexImage":
            spec = image_texture_spec(source, context.owner, context.warnings)
            if spec is None:
                context.warn(source, f"no image; '{socket.name}' uses its unlinked value")
                return _plain_color(node, names, default, context), None
        elif source.bl_idname == "ShaderNodeTexChecker":
            spec = checker_texture_spec(source, context.owner, context.warnings)
        if spec is not None:
            return WHITE, spec
    return _plain_color(node, names, default, context), None


def _alpha_input(node, context):
    """(alpha, image texture spec or None): an image's Alpha output linked to the
    Alpha input is an alpha texture; other links warn and use the unlinked value."""
    socket = find_input(node, PRINCIPLED_INPUTS["alpha"])
    if socket is None:
        return 1.0, None
    output = linked_output(socket)
    if (
        output is not None
        and output.name == "Alpha"
        and output.node.bl_idname == "ShaderNodeTexImage"
    ):
        spec = image_texture_spec(output.node, context.owner, context.warnings)
        if spec is not None:
            return 1.0, spec
    return _clamp(_scalar_or_color(node, (socket.name,), 1.0, context), 0.0, 1.0), None


def _with_textures(data, alpha, diffuse_texture, alpha_texture):
    textures = tuple(t for t in (diffuse_texture, alpha_texture) if t is not None)
    return MaterialExport(
        replace(
            data,
            alpha=alpha,
            diffuse_texture="" if diffuse_texture is None else diffuse_texture.name,
            alpha_texture="" if alpha_texture is None else alpha_texture.name,
        ),
        textures,
    )


def _viewport_material(material):
    # Material > Viewport Display: what a material without nodes renders with.
    return _whitted_material(
        base_color=tuple(material.diffuse_color[:3]),
        metallic=material.metallic,
        roughness=material.roughness,
        f0=(0.08 * material.specular_intensity,) * 3,
        transmission=0.0,
        ior=1.45,
        emission=BLACK,
    )


def _whitted_material(base_color, metallic, roughness, f0, transmission, ior, emission):
    """Principled-style parameters -> Whitted parameters.

    `f0` is the dielectric reflectance at normal incidence (RGB, tint included).
    """
    metallic = _clamp(metallic, 0.0, 1.0)
    roughness = _clamp(roughness, 0.0, 1.0)
    transmission = _clamp(transmission, 0.0, 1.0)
    # A Whitted tracer cannot blur a reflection, so a metal's mirror fades out as
    # roughness goes from 0 to 0.25, and the Phong highlight takes its place.
    sharp = max(0.0, 1.0 - 4.0 * roughness)
    # Only what is neither metal nor glass scatters diffusely.
    diffuse_weight = (1.0 - metallic) * (1.0 - transmission)
    # Phong exponent of about the same lobe as a microfacet roughness: alpha =
    # roughness^2 and n = 2/alpha^2 - 2 (Walter et al. 2007, Beckmann <-> Phong).
    alpha = roughness * roughness
    shininess = MAX_SHININESS if alpha == 0.0 else 2.0 / (alpha * alpha) - 2.0
    return MaterialData(
        diffuse=tuple(diffuse_weight * c for c in base_color),
        # Highlight weight: the dielectric part reflects F0; a metal reflects its
        # base colour, of which the sharp part already went to the mirror.
        specular=tuple(
            (1.0 - metallic) * max(0.0, f) + metallic * (1.0 - sharp) * c
            for f, c in zip(f0, base_color, strict=True)
        ),
        shininess=_clamp(shininess, 1.0, MAX_SHININESS),
        ambient=1.0,
        reflectivity=tuple(metallic * sharp * c for c in base_color),
        transmissivity=tuple(transmission * (1.0 - metallic) * c for c in base_color),
        ior=ior,
        emission=tuple(emission),
    )


def _fresnel_f0(ior):
    # Reflectance at normal incidence of a dielectric: ((n - 1) / (n + 1))^2.
    return ((ior - 1.0) / (ior + 1.0)) ** 2 if math.isfinite(ior) and ior > 0.0 else 0.0


def _clamp(value, low, high):
    return min(max(value, low), high)
