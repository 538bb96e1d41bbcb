"""Blender materials as Whitted parameters: a Phong local term, a mirror and glass.

Colours are linear RGB (Blender's scene linear), as the tracer uses them.

`map_material` is the node mapping: a pure function from a material's node data
to a MaterialExport (Whitted parameters plus the textures they name), reading
no pixels. `convert_material` applies the artist's Whitted override on top.

The node tree is read as Blender evaluates it (export/nodes: groups inlined,
reroutes and muted nodes passed through, Add and Mix Shader trees over the
BSDFs, every value node lowered to an expression with its constants folded).
Each field then is, in order of preference:

1. a constant (the whole graph folds: no cost at all);
2. what the fixed native material computes by itself: a diffuse colour times an
   Image or Checker texture, an alpha from an image's alpha (`diffuse_texture`,
   `alpha_texture`);
3. the output of the material's shader program (docs/notes/shader_program.md),
   which the integrator runs per hit.

The surface returns `alpha * shade + (1 - alpha) * (what lies behind)`, as the
tracer does; see export/nodes/shaders.py for how shaders combine.
"""

from dataclasses import dataclass, field, fields, make_dataclass, replace
from functools import cache

import bpy

from ..native import load_native
from .nodes import ops, uses_nodes
from .nodes import warn as _warn
from .nodes.graph import source
from .nodes.ir import evaluate
from .nodes.normals import displacement_bump, output_displacement
from .nodes.program import emit, material_fields
from .nodes.shader_fields import MAX_SHININESS, phong_exponent
from .nodes.shaders import default_surface, finish, fixed_texture, surface
from .nodes.values import UNBOUNDED_AO_DISTANCE, Lowering
from .texture import CheckerTextureSpec, ImageTextureSpec
from .unrendered import volume_warning
from .volume import Medium, NotRendered, default_volume, volume_medium

__all__ = [
    "MAX_SHININESS",
    "Displacement",
    "MaterialExport",
    "convert_material",
    "map_material",
    "material_data_type",
]


BLACK = (0.0, 0.0, 0.0)
WHITE = (1.0, 1.0, 1.0)


@dataclass(frozen=True)
class MaterialExport:
    data: object  # a material_data_type(): the Whitted parameters
    textures: tuple = ()  # ImageTextureSpec / CheckerTextureSpec named by `data` or the program
    program: object = None  # nodes.program.ProgramData, or None
    outputs: tuple = ()  # (field, register) pairs the program computes
    uv_maps: tuple = ()  # UV maps the program reads, by UV set index ("" = active render)
    attributes: tuple = ()  # corner attributes it reads: ("COLOR" | "ATTRIBUTE", name)
    tangents: tuple = ()  # UV set indices whose tangents its normal maps read
    object_info: bool = False  # it reads Object Info (per-instance data)
    # Its Object and Instancer attributes by index (per-instance data, export/instance.py
    # instance_attributes): ("OBJECT" | "INSTANCER", name).
    instance_attributes: tuple = ()
    # The View Layer attributes folded into it, ((name, the RGBA read), ...): it is
    # exported again when one reads otherwise (sync/scene.py).
    layer_attributes: tuple = ()
    pass_index: int = 0  # Material Properties > Settings > Pass Index (the IndexMA pass)
    # Displacement Only or Displacement and Bump with a linked Displacement: what moves
    # the vertices of the meshes that use it (a Displacement), else None.
    displacement: object = None

    @property
    def uv_map(self):
        """The UV map the fixed textures read ("" = the active render map), or None
        when none uses UV coordinates."""
        return next((t.uv_map for t in self.textures if t.coordinates == "UV"), None)


@dataclass(frozen=True)
class Displacement:
    """What moves a material's vertices (Cycles' true displacement without adaptive
    subdivision): a program run once per vertex (native displace) whose `output` register
    holds the world displacement, the output's Displacement lowered as the bump lowers it
    (nodes/normals.py output_displacement)."""

    method: str  # DISPLACEMENT (the normals follow the moved faces) | BOTH (they are kept)
    program: object  # nodes.program.ProgramData
    output: int  # the register of the world displacement


@cache
def material_data_type():
    """MaterialData, a material's Whitted parameters as the exporter gives them: a frozen
    dataclass of every parameter of whitted_native.Material (MATERIAL_PARAMS, defined by
    native/src/scene/material.h, whose comments say what each means) but those a
    MaterialExport carries itself, defaulting as the native material does, its enums by
    name ("LAMBERT"). Made once, the first time it is asked for: the add-on imports
    before the native module loads."""
    own = {f.name for f in fields(MaterialExport)}
    return make_dataclass(
        "MaterialData",
        [
            (name, object, field(default=default))
            for name, default in load_native().MATERIAL_PARAMS
            if name not in own
        ],
        frozen=True,
    )


@cache
def _program_fields():
    # The fields a program may drive that are MaterialData's too (all but the normals),
    # as (name, components).
    data_fields = {f.name for f in fields(material_data_type())}
    return tuple((name, n) for name, n in material_fields() if name in data_fields)


def _black():
    # What a material without a surface shader renders as in Cycles.
    return material_data_type()(
        diffuse=BLACK,
        specular=BLACK,
        shininess=1.0,
        ambient=1.0,
        reflectivity=BLACK,
        transmissivity=BLACK,
        ior=1.45,
        emission=BLACK,
    )


def convert_material(
    material,
    warnings,
    local_model="BLENDER",
    ao_distance=UNBOUNDED_AO_DISTANCE,
    view_layer=None,
):
    """Convert one material: the node mapping, or with the Whitted material
    panel's override on, its values (emission, alpha and textures still come
    from the nodes). `local_model`: scene.whitted.local_model, BLENDER (the BSDFs'
    own lobes: glossy reflection where they are rough) or LECTURE (the seed's mirror
    and Phong). `ao_distance`: the World's AO distance (world.ao_distance), which Ambient
    Occlusion nodes of Distance 0 read. `view_layer`: the evaluated view layer whose View
    Layer attributes Attribute nodes read (None: they read 0, warned)."""
    exported = map_material(material, warnings, local_model, ao_distance, view_layer)
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
        # The override is the seed's material: its reflection is a mirror and it has no
        # coat, whatever the nodes' roughness and specular layer.
        roughness=0.0,
        multiscatter=False,
        coat_specular=0.0,
        coat_reflectivity=0.0,
        coat_roughness=0.0,
        layer_reflectivity=(0.0, 0.0, 0.0),
    )
    overridden = (
        "diffuse",
        "specular",
        "shininess",
        "reflectivity",
        "transmissivity",
        "ior",
        "roughness",
        "coat_specular",
        "coat_reflectivity",
        "coat_shininess",
        "coat_ior",
        "coat_normal",
        "coat_roughness",
        "layer_reflectivity",
        "layer_ior",
    )
    outputs = tuple(
        (name, register) for name, register in exported.outputs if name not in overridden
    )
    if exported.program is not None and not outputs:
        return replace(exported, data=data, program=None, outputs=())
    return replace(exported, data=data, outputs=outputs)


def map_material(
    material,
    warnings,
    local_model="BLENDER",
    ao_distance=UNBOUNDED_AO_DISTANCE,
    view_layer=None,
):
    """The node mapping: a material's surface shader as Whitted parameters: the fixed
    native material where it shows the graph (constants, a texture on the diffuse
    colour, an image's alpha), else a shader program.

    Without nodes, the viewport display values are used. A material without a
    surface shader renders as in Cycles (Blender 3.4 and 5.0 seen, docs/SUPPORT.md):
    black and opaque, unless it has a volume shader: then it is no surface at all
    (MaterialData.surface False), which rays pass through and which casts no shadow. A
    volume shader fills the meshes with its medium (export/volume.py): a homogeneous one's
    constants, or a heterogeneous one's volume_* fields computed by the program.
    """
    if not uses_nodes(material):
        return MaterialExport(_viewport_material(material))
    owner = f"material '{material.name}'"
    output_node = material.node_tree.get_output_node("CYCLES")
    found = []
    lowering = Lowering(owner, found, ao_distance=ao_distance, view_layer=view_layer)
    medium = Medium()
    varying = {}  # a heterogeneous medium's volume_* fields (Exprs)
    volume = False
    if output_node is not None:
        try:
            found_medium = volume_medium(output_node, lowering)
        except NotRendered as why:
            _warn(warnings, volume_warning(owner, output_node, str(why)))
            volume = True
        else:
            volume = found_medium is not None
            if isinstance(found_medium, Medium):
                medium = found_medium
            elif found_medium is not None:
                varying = found_medium
    if output_node is None or source(output_node.inputs["Surface"])[0] is None:
        if not volume:
            _warn(
                warnings, f"Whitted: {owner} has no surface shader; it renders black, as in Cycles"
            )
            return MaterialExport(_black())
        # Cycles lets rays through a volume's bounds: no surface (docs/notes/no_surface.md).
        if not varying:
            return _with_layer_attributes(medium_material(medium), lowering)
        for message in found:
            _warn(warnings, message)
        exported = _programmed(varying, lowering, "NONE")
        data = replace(exported.data, surface=False, volume_step_rate=_volume_step_rate(material))
        return _with_layer_attributes(replace(exported, data=data), lowering)
    bumped, moved = _displacement(material, output_node, lowering)
    lowering.shading_normal = bumped
    closure = surface(lowering, output_node, local_model=local_model)
    fields = {**finish(lowering, closure), **varying}
    if bumped is not None:
        # Every closure whose Normal is unlinked takes the bumped one, as Cycles' bump
        # sets the shading normal they default to.
        fields.setdefault("normal", bumped)
        fields.setdefault("coat_normal", bumped)
    exported = _fixed(fields, lowering)
    if exported is None:
        exported = _programmed(fields, lowering, _bump_shadowing(material))
    for message in found:
        _warn(warnings, message)
    exported = _with_lobe_models(exported, closure)
    exported = _with_displacement(exported, moved, displacement_method(material), lowering)
    sampling = _emission_sampling(material)
    # A surface's volume fills what its refraction enters (glass with an absorbing volume).
    # A heterogeneous one's fields are the program's, its constants the stand-ins.
    volume_fields = (
        {"volume_step_rate": _volume_step_rate(material)} if varying else medium.fields()
    )
    exported = replace(
        exported, data=replace(exported.data, emission_sampling=sampling, **volume_fields)
    )
    return _with_layer_attributes(exported, lowering)


def _with_layer_attributes(exported, lowering):
    # What the View Layer attributes read, also where everything folded (no program).
    return replace(exported, layer_attributes=tuple(lowering.needs.layer_attributes.items()))


def grid_material(material, grids, warnings):
    """What a Volume object renders with (export/volume_object.py): `material` (its
    first, or None) read with the object's grids `grids` ({role: grid name}). No surface,
    whatever its Surface output: Cycles shades a Volume object by its volume alone. A
    material without a volume shader fills nothing; None is Cycles' default volume."""
    owner = "the default volume" if material is None else f"material '{material.name}'"
    found = []
    lowering = Lowering(owner, found, grids=grids)
    medium = None
    if material is None:
        medium = default_volume(lowering)
    elif uses_nodes(material):
        output_node = material.node_tree.get_output_node("CYCLES")
        try:
            medium = None if output_node is None else volume_medium(output_node, lowering)
        except NotRendered as why:
            _warn(warnings, volume_warning(owner, output_node, str(why)))
    if not isinstance(medium, dict):
        return medium_material(medium or Medium())
    for message in found:
        _warn(warnings, message)
    exported = _programmed(medium, lowering, "NONE")
    data = replace(exported.data, surface=False, volume_step_rate=_volume_step_rate(material))
    return replace(exported, data=data)


def medium_material(medium):
    """A material of no surface filled with `medium` (an export.volume.Medium): the
    bounds of a volume, or the world's volume (Scene.set_world_medium)."""
    return MaterialExport(material_data_type()(surface=False, **medium.fields()))


def default_material(local_model="BLENDER"):
    """What an object without a material, or an empty material slot, renders with, as
    Cycles renders it, set as the native scene's default material
    (instance.DEFAULT_MATERIAL): from Blender 5.0 its default surface, a Principled BSDF
    of a new material's inputs (nodes/principled.py's DEFAULT_SURFACE); before 5.0 Cycles'
    default
    (a Diffuse BSDF of 0.8): the native material's defaults, with the version's normal
    handling (_material_data: 3.x lifts and fades its normal as any material's)."""
    if bpy.app.version < (5, 0, 0):
        return MaterialExport(_material_data({}))
    lowering = Lowering("the default surface", [])
    closure = default_surface(lowering, local_model)
    fields = finish(lowering, closure)
    exported = _fixed(fields, lowering) or _programmed(fields, lowering, "NONE")
    return _with_lobe_models(exported, closure)


def displacement_method(material):
    """Cycles' Displacement method of `material` (Material > Settings > Surface:
    `material.displacement_method` from 4.1, `material.cycles.displacement_method`
    before): BUMP (the default, also where the Cycles add-on that holds it is off),
    DISPLACEMENT or BOTH. Read on the original material: Blender 3.4's evaluated copy
    keeps Cycles' property as it was when a script sets it (measured: BUMP on the copy,
    DISPLACEMENT on the original, after a depsgraph update for the same material's links)."""
    material = getattr(material, "original", material)
    method = getattr(material, "displacement_method", None)
    if method is None:
        method = getattr(getattr(material, "cycles", None), "displacement_method", "BUMP")
    return method


def _displacement(material, output_node, lowering):
    """(the shading normal the output's linked Displacement bumps or None, the world
    displacement vector that moves the vertices or None). Cycles' Displacement method
    (displacement_method): Bump Only shades it as a bump (nodes/normals.py
    displacement_bump); Displacement Only moves the vertices and keeps the shading normal
    they get; Displacement and Bump moves them and bumps too (Cycles without adaptive
    subdivision: the native displace, sync/displace.py)."""
    method = displacement_method(material)
    moved = None
    if method in ("DISPLACEMENT", "BOTH"):
        moved = output_displacement(lowering, output_node)
        if moved is not None and moved.is_const and not any(moved.value[:3]):
            moved = None  # it moves nothing
    bumped = None if method == "DISPLACEMENT" else displacement_bump(lowering, output_node)
    return bumped, moved


def _with_displacement(exported, moved, method, lowering):
    """`exported` with the program that computes the world displacement `moved` (an
    Expr) at a vertex, its textures and the mesh layers it reads (the same lowering as
    the surface's: one index space of UV sets and attributes)."""
    if moved is None:
        return exported
    program, outputs = emit({"displacement": moved}, keep_constant=True)
    needs = lowering.needs
    textures = {spec.name: spec for spec in exported.textures}
    textures.update({name: lowering.textures[name] for name in program.textures})
    return replace(
        exported,
        displacement=Displacement(method, program, outputs["displacement"]),
        textures=tuple(textures.values()),
        uv_maps=tuple(needs.uv_maps),
        attributes=tuple(needs.attributes),
        tangents=tuple(sorted(needs.tangents)),
    )


def _with_lobe_models(exported, closure):
    """`exported` with the diffuse model, multiple scattering and coat model its closure
    asks for."""
    if closure.diffuse_model is not None:
        model = closure.diffuse_model
        if model == "OREN_NAYAR" and bpy.app.version >= (4, 3, 0):
            # Cycles 4.3 added Oren-Nayar's multiple scattering (read in 5.0's source;
            # 4.0-4.2 were not rendered here).
            model = "OREN_NAYAR_ENERGY"
        exported = replace(exported, data=replace(exported.data, diffuse_model=model))
    if closure.multiscatter:
        exported = replace(exported, data=replace(exported.data, multiscatter=True))
    if closure.coat_model is not None:
        exported = replace(exported, data=replace(exported.data, coat_model=closure.coat_model))
    return exported


def _volume_step_rate(material):
    """Cycles' Material > Settings > Volume > Step Rate (material.cycles.volume_step_rate),
    1 where the Cycles add-on that holds it is off."""
    return getattr(getattr(material, "cycles", None), "volume_step_rate", 1.0)


def _emission_sampling(material):
    """Which sides of an emissive mesh feelers sample, from Cycles' setting: 4.0+'s
    Material > Settings > Emission Sampling (material.cycles.emission_sampling: None,
    Auto, Front, Back, Front and Back), 3.x's Multiple Importance
    (material.cycles.sample_as_light: both sides or none); both sides where the Cycles
    add-on that holds them is off. Auto samples both sides: Cycles then skips emission
    it estimates weak (at most 0.5) and lets its diffuse rays find it, which Whitted
    does not trace, so Whitted samples every emitter it has (docs/SUPPORT.md)."""
    settings = getattr(material, "cycles", None)
    sampling = getattr(settings, "emission_sampling", None)
    if sampling is not None:
        return {"NONE": "NONE", "FRONT": "FRONT", "BACK": "BACK"}.get(sampling, "BOTH")
    return "BOTH" if getattr(settings, "sample_as_light", True) else "NONE"


def _fixed(fields, lowering):
    """The MaterialExport of fields the fixed native material can show (constants,
    a texture on the diffuse colour, an image's alpha); None when it cannot."""
    if "normal" in fields or "coat_normal" in fields or "tangent" in fields:
        return None
    textures = []
    values = {}
    diffuse_texture = alpha_texture = ""
    for name, _ in _program_fields():
        expr = fields.get(name)
        if expr is None:  # a volume field of a material without a heterogeneous medium
            continue
        if expr.is_const:
            values[name] = expr.value
            continue
        if name == "diffuse":
            scale, texture = _scaled_texture(expr)
            if texture is not None:
                spec = _fixed_spec(texture, lowering)
                textures.append(spec)
                diffuse_texture = spec.name
                values[name] = scale
                continue
        alpha = expr.op == ops.SWIZZLE and ops.unpack("SWIZZLE", expr.mode)["component"] == 3
        if name == "alpha" and alpha:
            texture = fixed_texture(expr.args[0])
            if texture is not None and texture.op == ops.IMAGE:
                spec = _fixed_spec(texture, lowering)
                textures.append(spec)
                alpha_texture = spec.name
                values[name] = (1.0,) * 4
                continue
        return None
    data = _material_data(values, diffuse_texture=diffuse_texture, alpha_texture=alpha_texture)
    unique = tuple({spec.name: spec for spec in textures}.values())
    return MaterialExport(data, unique)


def _programmed(fields, lowering, bump_shadowing):
    program, outputs = emit(fields)
    values = {
        name: evaluate(fields[name], _stand_in) for name, _ in _program_fields() if name in fields
    }
    data = _material_data(values)
    if "normal" in outputs:
        data = replace(data, bump_shadowing=bump_shadowing)
    textures = tuple(lowering.textures[name] for name in program.textures)
    needs = lowering.needs
    return MaterialExport(
        data,
        textures,
        program=program,
        outputs=tuple(outputs.items()),
        uv_maps=tuple(needs.uv_maps),
        attributes=tuple(needs.attributes),
        tangents=tuple(sorted(needs.tangents)),
        object_info=needs.object_info,
        instance_attributes=tuple(needs.instance_attributes),
    )


def _bump_shadowing(material):
    """How Cycles fades a diffuse closure whose normal a graph changed, towards the
    smooth surface's horizon: Blender 3.x by Chiang et al.'s term; where the material
    has Cycles' Bump Map Correction (5.0 has it, default on) by Conty Estevez et al.'s
    GGX term when it is on, else it only cuts light under the smooth surface. A 4.x
    without that setting is taken as 3.x (4.1's Cycles source still has Chiang's term;
    no 4.x was rendered here); 5.0 with the Cycles add-on off, as the setting's default."""
    settings = getattr(material, "cycles", None)
    correction = getattr(settings, "use_bump_map_correction", None)
    if correction is None:
        return "CHIANG" if bpy.app.version < (5, 0, 0) else "MICROFACET"
    return "MICROFACET" if correction else "SMOOTH_SIDE"


def _material_data(values, **textures):
    """MaterialData from the evaluated fields (float4 values by field name: colours take
    .xyz, values .x; a field not given keeps its default) and the legacy texture names,
    if any."""
    driven = {
        name: values[name][0] if components == 1 else tuple(values[name][:components])
        for name, components in _program_fields()
        if name in values
    }
    return material_data_type()(
        **driven,
        ambient=1.0,
        # Cycles 4.0 on: height-correlated masking and shadowing; 3.x separable.
        masking="CORRELATED" if bpy.app.version >= (4, 0, 0) else "SEPARABLE",
        # Cycles 3.x adds every lobe of a closure on top of the others (the Principled's
        # specular and Clearcoat do not dim its diffuse); 4.0 on layers them.
        coat_layered=bpy.app.version >= (4, 0, 0),
        # Cycles 3.x lifts every BSDF's normal, the interpolated one too, where the view's
        # mirror would fall below the surface (ensure_valid_reflection); 4.x+ only its
        # specular lobes' (not modelled). A diffuse lobe whose normal the lift turned is
        # faded by Chiang et al.'s term, as for any normal that is not the interpolated
        # one (a graph's: _programmed sets its own).
        valid_reflection=bpy.app.version < (4, 0, 0),
        bump_shadowing="CHIANG" if bpy.app.version < (4, 0, 0) else "NONE",
        **textures,
    )


def _stand_in(expr):
    # The constant a program's varying value counts as in the material's own fields
    # (what the inspector and the statistics read): textures white, everything the
    # hit gives 0.
    if expr.op in (ops.IMAGE, ops.ENVIRONMENT, ops.CHECKER):
        return (1.0, 1.0, 1.0, 1.0)
    return (0.0, 0.0, 0.0, 0.0)


def _scaled_texture(expr):
    """(scale rgba, texture Expr) when `expr` is a fixed texture times a constant."""
    if fixed_texture(expr) is not None:
        return (1.0, 1.0, 1.0, 1.0), expr
    if expr.op == ops.VECTOR_MATH and expr.mode == ops.pack("VECTOR_MATH", operation="MULTIPLY"):
        a, b = expr.args[:2]
        for const, texture in ((a, b), (b, a)):
            if const.is_const and fixed_texture(texture) is not None:
                return const.value, texture
    return None, None


def _fixed_spec(texture, lowering):
    vector = texture.args[0]
    if vector.mode == ops.IN_GENERATED:
        coordinates, uv_map = "GENERATED", ""
    elif vector.mode == ops.IN_OBJECT:
        coordinates, uv_map = "OBJECT", ""
    else:
        coordinates, uv_map = "UV", lowering.needs.uv_maps[vector.mode - ops.IN_UV]
    if texture.op == ops.CHECKER:
        _, color1, color2, scale = texture.args
        return CheckerTextureSpec(
            color1=tuple(color1.value[:3]),
            color2=tuple(color2.value[:3]),
            scale=scale.value[0],
            coordinates=coordinates,
            uv_map=uv_map,
        )
    spec = lowering.textures[texture.e]
    return ImageTextureSpec(spec.image, spec.interpolation, spec.extension, coordinates, uv_map)


def _viewport_material(material):
    # Material > Viewport Display: what a material without nodes renders with.
    return _whitted_material(
        base_color=tuple(material.diffuse_color[:3]),
        metallic=material.metallic,
        roughness=material.roughness,
        f0=(0.08 * material.specular_intensity,) * 3,
    )


def _whitted_material(base_color, metallic, roughness, f0):
    """Principled-style parameters -> Whitted parameters (the formulas of
    nodes/shader_fields.py `whitted_fields`, on plain floats)."""
    metallic = _clamp(metallic, 0.0, 1.0)
    roughness = _clamp(roughness, 0.0, 1.0)
    sharp = max(0.0, 1.0 - 4.0 * roughness)
    return material_data_type()(
        diffuse=tuple((1.0 - metallic) * c for c in base_color),
        specular=tuple(
            (1.0 - metallic) * max(0.0, f) + metallic * (1.0 - sharp) * c
            for f, c in zip(f0, base_color, strict=True)
        ),
        shininess=phong_exponent(roughness),
        ambient=1.0,
        reflectivity=tuple(metallic * sharp * c for c in base_color),
        transmissivity=BLACK,
        ior=1.45,
        emission=BLACK,
    )


def _clamp(value, low, high):
    return min(max(value, low), high)
