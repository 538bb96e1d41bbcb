"""Sockets as the lowering reads them: their kind, and finding one by identifier or name."""

from .graph import socket_id, socket_type
from .ir import COLOR, FLOAT, VECTOR

_KINDS = {"VALUE": FLOAT, "INT": FLOAT, "BOOLEAN": FLOAT, "RGBA": COLOR, "VECTOR": VECTOR}


def kind_of(socket):
    return _KINDS.get(socket_type(socket), FLOAT)


def find_socket(sockets, names, enabled_only=True):
    """The first socket whose identifier or name is one of `names`, in order (only
    enabled ones unless `enabled_only` is False: Blender hides the operands an
    operation does not use)."""
    for name in names:
        for socket in sockets:
            if (not enabled_only or getattr(socket, "enabled", True)) and (
                socket_id(socket) == name or socket.name == name
            ):
                return socket
    return None


def output_name(output):
    return output.socket.name


def output_index(output):
    identifier = socket_id(output.socket)
    return next(i for i, s in enumerate(output.node.outputs) if socket_id(s) == identifier)
