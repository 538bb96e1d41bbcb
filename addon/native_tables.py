"""The native module's tables, which the add-on's controls and passes are built from at
import: the settings' defaults (whitted_native.Settings()) and ranges (LIMITS), the
film passes' channels (FILM_PASSES). Their one definition is the C++ one
(native/src/integrator/settings.h, passes.h).

Where whitted_native does not import (a Blender whose Python the add-on carries no
module for, a checkout not yet built), NATIVE is None and the controls register
without native defaults and bounds (Blender's own: 0, the first item, unbounded): the
add-on still registers, the engine cannot render, and every render says why and what to
do (native.load_native).
"""

from .native import load_native


def _native_or_none():
    try:
        return load_native()
    except ImportError:
        return None


NATIVE = _native_or_none()


def limit(name):
    """(min, max) of setting `name` (whitted_native.LIMITS), or None without the module."""
    return None if NATIVE is None else NATIVE.LIMITS[name]


def bounds(name, kind=int):
    """The min and max keywords of a control of `kind` (int or float) whose range is
    that of native setting `name`; none without the module."""
    limits = limit(name)
    return {} if limits is None else {"min": kind(limits[0]), "max": kind(limits[1])}


def setting(name, default=None):
    """The default, min and max keywords of the control for native Settings field
    `name` (an enum's default as its item's name); `default` is the add-on's own where
    it has one. None of them without the module."""
    if NATIVE is None:
        return {}
    value = getattr(NATIVE.Settings(), name) if default is None else default
    value = getattr(value, "name", value)  # a native enum's item
    if name in NATIVE.LIMITS:
        return {"default": value, **bounds(name, type(value))}
    return {"default": value}
