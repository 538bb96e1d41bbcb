"""The compiled core, `whitted_native`, which the build copies beside this file."""

import os

BUILD_COMMAND = "bash scripts/setup.sh  (or: cmake -S . -B build && cmake --build build)"


def load_native():
    """Import whitted_native, or raise ImportError that says how to build it."""
    try:
        from . import whitted_native
    except ImportError as error:
        folder = os.path.dirname(os.path.abspath(__file__))
        raise ImportError(
            f"Whitted: the native module whitted_native could not be imported from {folder} "
            f"({error}). Build it from the repository root with: {BUILD_COMMAND}; "
            "the build copies whitted_native*.so into addon/."
        ) from error
    return whitted_native
