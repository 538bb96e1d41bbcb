"""Node trees as Blender evaluates them: groups inlined, reroutes followed, muted
nodes passed through, frames ignored.

`source(socket, scope)` follows the link into an input socket until it reaches the
output of a node that computes something, which it returns as an `Output` (the
node, its socket and the chain of group nodes it lives in). A socket nothing
feeds (unlinked, a muted link, a muted node without an internal link for that
output, a group input left unlinked on the group node) gives None and the socket
whose `default_value` Blender uses instead.
"""

from dataclasses import dataclass

# Node types that only route a value.
REROUTE = "NodeReroute"
GROUP_INPUT = "NodeGroupInput"
GROUP_OUTPUT = "NodeGroupOutput"

# Enough for any real tree; stops a malformed one from looping.
_MAX_STEPS = 10000


@dataclass(frozen=True)
class Output:
    """An output socket of a node that computes its value."""

    node: object
    socket: object
    scope: tuple  # the group nodes it is inside, outermost first

    @property
    def key(self):
        """Identity of this output of this instance of the node."""
        return (
            tuple(_pointer(g) for g in self.scope),
            _pointer(self.node),
            socket_id(self.socket),
        )


def _pointer(block):
    as_pointer = getattr(block, "as_pointer", None)
    return as_pointer() if as_pointer is not None else id(block)


def socket_id(socket):
    return getattr(socket, "identifier", None) or socket.name


def is_group(node):
    return node.bl_idname in ("ShaderNodeGroup", "ShaderNodeCustomGroup") or (
        node.bl_idname.endswith("Group") and hasattr(node, "node_tree")
    )


def source(socket, scope=()):
    """(Output or None, the socket whose value is used when None) for input `socket`."""
    for _ in range(_MAX_STEPS):
        if not socket.is_linked:
            return None, socket
        link = socket.links[0]
        if link.is_muted or not getattr(link, "is_valid", True):
            return None, socket
        node = link.from_node
        output = link.from_socket
        if node.bl_idname == REROUTE:
            socket = node.inputs[0]
            continue
        if getattr(node, "mute", False) and node.bl_idname != GROUP_INPUT:
            passed = internal_input(node, output)
            if passed is None:
                return None, socket
            socket = passed
            continue
        if node.bl_idname == GROUP_INPUT:
            if not scope:
                return None, socket
            group = scope[-1]
            passed = _by_identifier(group.inputs, output)
            if passed is None:
                return None, socket
            socket, scope = passed, scope[:-1]
            continue
        if is_group(node):
            tree = node.node_tree
            group_output = None if tree is None else active_group_output(tree)
            passed = None if group_output is None else _by_identifier(group_output.inputs, output)
            if passed is None:
                return None, socket
            socket, scope = passed, (*scope, node)
            continue
        return Output(node, output, scope), socket
    return None, socket


def active_group_output(tree):
    outputs = [n for n in tree.nodes if n.bl_idname == GROUP_OUTPUT]
    return next((n for n in outputs if n.is_active_output), outputs[0] if outputs else None)


def _by_identifier(sockets, wanted):
    identifier = socket_id(wanted)
    for socket in sockets:
        if socket_id(socket) == identifier:
            return socket
    return None


_CONVERTIBLE = {"VALUE", "INT", "BOOLEAN", "RGBA", "VECTOR"}


def internal_input(node, output):
    """The input a muted `node` passes to `output` (Blender's internal links), or None.

    Blender fills `internal_links` when it updates the tree; before that (a tree
    made by a script and not evaluated yet), the same rule is applied here: the
    first input of the output's type, else the first of a type it converts from.
    """
    links = list(getattr(node, "internal_links", ()))
    for link in links:
        if socket_id(link.to_socket) == socket_id(output):
            return None if link.is_muted else link.from_socket
    if links:
        return None
    kind = socket_type(output)
    inputs = [s for s in node.inputs if getattr(s, "enabled", True)]
    same = next((s for s in inputs if socket_type(s) == kind), None)
    if same is not None:
        return same
    if kind in _CONVERTIBLE:
        return next((s for s in inputs if socket_type(s) in _CONVERTIBLE), None)
    return None


def socket_type(socket):
    """VALUE, INT, BOOLEAN, RGBA, VECTOR, SHADER, ...; guessed from the value for
    sockets that do not say (tests' stand-ins)."""
    kind = getattr(socket, "type", None)
    if kind is not None:
        return kind
    value = getattr(socket, "default_value", None)
    if value is None:
        return "SHADER"
    if isinstance(value, (int, float)):
        return "VALUE"
    return "RGBA" if len(value) == 4 else "VECTOR"
