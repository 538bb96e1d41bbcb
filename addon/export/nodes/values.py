"""Lowering the value nodes of a graph (textures, maths, colours, coordinates) to
Exprs (ir.py): `Lowering.value(socket, scope, kind)` is the value Blender would
feed `socket`, as an Expr of `kind`.

A node the program has no op for is warned once, by name, and the socket it
feeds takes its own unlinked value, as if the link were not there.
"""

from dataclasses import dataclass, field

from . import ops
from . import warn as _warn
from .converter_nodes import CONVERTER_NODES
from .graph import source
from .input_nodes import INPUT_NODES
from .ir import COLOR, FLOAT, VECTOR, Builder
from .normals import bump as _bump
from .normals import displacement as _displacement
from .sockets import find_socket, kind_of
from .texture_nodes import TEXTURE_NODES

# Textures the program does not compute (named in their warning).
PROCEDURALS = {
    "ShaderNodeTexPointDensity": "Point Density Texture",
}


# Cycles' AO distance in a scene without a world (its Integrator's default, FLT_MAX): an
# Ambient Occlusion node of unlinked Distance 0 reads the World's instead.
UNBOUNDED_AO_DISTANCE = 3.4028234663852886e38


@dataclass
class Needs:
    """What a material's program reads from the mesh and the instance."""

    uv_maps: list = field(default_factory=list)  # UV map names; "" = the active render map
    attributes: list = field(default_factory=list)  # ("COLOR" | "ATTRIBUTE", name)
    tangents: set = field(default_factory=set)  # UV set indices normal maps read
    object_info: bool = False
    # Per-instance attributes (the Attribute node's Object and Instancer types), by
    # index: ("OBJECT" | "INSTANCER", name).
    instance_attributes: list = field(default_factory=list)
    # The View Layer attributes folded into the program: {name: the RGBA read}.
    layer_attributes: dict = field(default_factory=dict)

    def uv_set(self, name):
        if name not in self.uv_maps:
            self.uv_maps.append(name)
        return self.uv_maps.index(name)

    def attribute(self, key):
        if key not in self.attributes:
            self.attributes.append(key)
        return self.attributes.index(key)

    def instance_attribute(self, key):
        """The index of per-instance attribute `key`; None past the OBJECT_ATTRIBUTES
        an instance carries."""
        if key not in self.instance_attributes:
            if len(self.instance_attributes) == ops.OBJECT_ATTRIBUTES:
                return None
            self.instance_attributes.append(key)
        return self.instance_attributes.index(key)


class Lowering:
    """One material's (or world's) lowering: the Builder, the warnings, the textures
    and the per-hit data its program reads."""

    def __init__(
        self,
        owner,
        warnings,
        world=False,
        grids=None,
        ao_distance=UNBOUNDED_AO_DISTANCE,
        view_layer=None,
        lamp_matrix=None,
    ):
        self.owner = owner  # "material 'Name'" or "world 'Name'"
        self.warnings = warnings
        self.world = world
        # A Volume object's grids its program may read, {role: grid name}
        # (export/volume_object.py ROLES); None for a mesh's material and the world.
        self.grids = grids
        self.b = Builder()
        self.needs = Needs()
        self.textures = {}  # name -> ImageTextureSpec
        # Each Sky Texture with a sun disc: (its Vector Expr, the sun in the node's space,
        # the disc's angular diameter), for the world's sun (export/world.py).
        self.suns = []
        self._outputs = {}  # Output.key -> Expr
        self._active = set()
        # The normal nodes read as the shading normal once a displacement bumps it
        # (normals.displacement_bump, set by export/material.py); None: the hit's.
        self.shading_normal = None
        # The World's AO distance (export/world.py ao_distance), which an Ambient Occlusion
        # node whose Distance is an unlinked 0 reads, as in Cycles.
        self.ao_distance = ao_distance
        # The evaluated view layer whose View Layer attributes a material reads (folded
        # into its program); None where they are not read (the world, lamps).
        self.view_layer = view_layer
        # A lamp's tree: its object-to-world matrix (a mathutils Matrix), whose space its
        # Texture Coordinate and IES Texture read; None for materials and the world.
        self.lamp_matrix = lamp_matrix

    def warn(self, node, message):
        _warn(self.warnings, f"Whitted: {self.owner}, node '{node.name}': {message}")

    # --- sockets ---------------------------------------------------------------

    def value(self, socket, scope, kind=None, consumer=None):
        """The Expr Blender feeds input `socket` (of a node inside `scope`)."""
        kind = kind or kind_of(socket)
        output, used = source(socket, scope)
        if output is not None:
            expr = self.output(output, consumer or (socket, scope))
            if expr is not None:
                return self.convert(expr, kind)
        return self.default(used, kind)

    def default(self, socket, kind):
        value = getattr(socket, "default_value", None)
        if value is None:
            return self.b.const(0.0, kind) if kind == FLOAT else self.b.const((0.0,) * 3, kind)
        if isinstance(value, (int, float, bool)):
            return self.convert(self.b.f(float(value)), kind)
        value = tuple(value)
        expr = self.b.const(value, COLOR if len(value) == 4 else VECTOR)
        return self.convert(expr, kind)

    def convert(self, expr, kind):
        """Blender's implicit conversions: colour -> float is its luminance, vector ->
        float the mean of its components; a float becomes all components."""
        if kind == FLOAT and expr.kind == COLOR:
            return self.b.luminance(expr)
        if kind == FLOAT and expr.kind == VECTOR:
            return self.b.average(expr)
        return expr

    def input(self, output, names, kind=None):
        """The value of the input of `output.node` with one of `names` (identifier
        or name, newest first); None when the node has no such input."""
        socket = find_socket(output.node.inputs, names)
        if socket is None:
            return None
        return self.value(socket, output.scope, kind)

    def inputs(self, output, kinds):
        """The node's enabled inputs in order, as Exprs of `kinds` (one per input)."""
        sockets = [s for s in output.node.inputs if getattr(s, "enabled", True)]
        return [self.value(s, output.scope, k) for s, k in zip(sockets, kinds, strict=False)]

    def output(self, output, consumer):
        """The Expr of a node output; None (with a warning) when not supported."""
        key = output.key
        if key in self._outputs:
            return self._outputs[key]
        if key in self._active:
            self.warn(output.node, "is part of a cycle; it is ignored")
            return None
        self._active.add(key)
        try:
            handler = _NODES.get(output.node.bl_idname)
            expr = self._unsupported(output, consumer) if handler is None else handler(self, output)
        finally:
            self._active.discard(key)
        self._outputs[key] = expr
        return expr

    def _unsupported(self, output, consumer):
        node = output.node
        socket, _ = consumer
        fed = getattr(socket, "node", None)
        where = f" of '{fed.name}'" if fed is not None and fed is not node else ""
        what = PROCEDURALS.get(node.bl_idname, node.bl_idname)
        self.warn(
            node,
            f"{what} is not supported; input '{socket.name}'{where} uses its unlinked value",
        )
        return None

    # --- per-hit inputs ----------------------------------------------------------

    def hit(self, mode, kind=VECTOR):
        if mode == ops.IN_NORMAL and self.shading_normal is not None:
            return self.shading_normal
        return self.b.op(ops.INPUT, mode, (), kind=kind)

    def in_lamp_space(self, direction):
        """World `direction` carried into the lamp's object space as a normal is (the
        transpose of the lamp's linear part: each component the direction dotted with one
        of its axes) and normalised, as Cycles' object_inverse_normal_transform."""
        b = self.b
        m = self.lamp_matrix
        components = [
            b.vmath("DOT_PRODUCT", direction, b.const((m[0][i], m[1][i], m[2][i]), VECTOR))
            for i in range(3)
        ]
        return b.vmath("NORMALIZE", b.pack(*components))

    def grid(self, role, name, kind=None):
        """The Volume object's grid `name` in `role` at the point (a colour for the colour
        role, else a scalar in every component), as `kind` when given; None where the
        program has no such grid: Cycles' attribute not found."""
        if self.grids is None or self.grids.get(role) != name:
            return None
        mode = getattr(ops, f"IN_GRID_{role.upper()}")
        expr = self.hit(mode, COLOR if role == "color" else FLOAT)
        return expr if kind is None else self.convert(expr, kind)

    def grid_voxels(self, role):
        """The eight voxels of the Volume object's grid in `role` around the point that its
        trilinear interpolation weighs, as (value, weight) scalar pairs: what a stochastic
        read (one voxel, picked with its weight) gives on average, through a non-linear
        function too (export/volume.py STOCHASTIC_GRID_READS). Only the temperature grid's
        voxels are offered (IN_GRID_TEMPERATURE_VOXEL)."""
        if role != "temperature":
            raise ValueError(f"only the temperature grid's voxels are read, not {role}'s")
        return [
            (
                self.hit(ops.IN_GRID_TEMPERATURE_VOXEL + k, FLOAT),
                self.hit(ops.IN_GRID_VOXEL_WEIGHT + k, FLOAT),
            )
            for k in range(ops.GRID_VOXELS)
        ]

    def uv(self, name=""):
        if self.world:
            return self.hit(ops.IN_GENERATED)
        return self.hit(ops.IN_UV + self.needs.uv_set(name))

    def texture(self, spec):
        self.textures[spec.name] = spec
        return spec.name


_NODES = {
    **INPUT_NODES,
    **TEXTURE_NODES,
    **CONVERTER_NODES,
    "ShaderNodeBump": _bump,
    "ShaderNodeDisplacement": _displacement,
}

SUPPORTED_NODES = frozenset(_NODES)
