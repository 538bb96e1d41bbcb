"""The Blender versions the suite tests, each once: which CPython it embeds, how it
is installed, and how deeply it is tested. scripts/setup.sh (--test-blenders) makes
their environments from this table, tests/package runs the smoke tier on it and the
README's "Supported Blender versions" table is written from it and a run's results
(whitted_tools blender-versions).

    .venv/bin/python -m whitted_tools.blenders      one line per bpy environment:
                                                    LABEL PYTHON VENV REQUIREMENT

Tiers: "full" runs the whole in-Blender suite (tests/blender); "smoke" installs the
package zip into a fresh profile, renders the demo and a node-graph scene and runs
the sync property test and the passes test (tests/package/test_versions.py).
"""

from dataclasses import dataclass

from whitted_tools import REPO


@dataclass(frozen=True)
class Blender:
    label: str  # what Blender calls itself, major.minor ("5.2")
    python: str  # the CPython it embeds, major.minor
    tier: str  # "full" or "smoke"
    requirement: str = ""  # pip's requirement for the bpy module; "" for a Blender binary
    venv: str = ""  # its environment, relative to the repository

    @property
    def is_module(self):
        return bool(self.requirement)

    @property
    def venv_python(self):
        return REPO / self.venv / "bin" / "python"


BLENDERS = (
    # Debian 12's `blender` package: a real window under Xvfb, the system CPython.
    Blender("3.4", "3.11", "full"),
    # The bpy module from the package index. .venv (the tools' environment) keeps 5.0,
    # the newest bpy for CPython 3.11; the others each have their own.
    Blender("4.2", "3.11", "smoke", "bpy==4.2.*", ".venv-4.2"),
    Blender("4.5", "3.11", "smoke", "bpy==4.5.*", ".venv-4.5"),
    Blender("5.0", "3.11", "smoke", "bpy==5.0.*", ".venv"),
    Blender("5.2", "3.13", "full", "bpy==5.2.*", ".venv-5.2"),
    Blender("5.3", "3.13", "smoke", "bpy==5.3.*", ".venv-5.3"),
)

# CPythons the package's module is built for: every one a supported Blender embeds
# (official 3.x and 4.0 builds: 3.10), and 3.12 because it costs one more compile.
MODULE_PYTHONS = ("3.10", "3.11", "3.12", "3.13")


def blender(label):
    """The BLENDERS entry called `label`."""
    for entry in BLENDERS:
        if entry.label == label:
            return entry
    raise KeyError(f"no Blender {label} in whitted_tools.blenders.BLENDERS")


def main():
    for entry in BLENDERS:
        if entry.is_module:
            print(entry.label, entry.python, entry.venv, entry.requirement)


if __name__ == "__main__":
    main()
