"""The add-on's preferences (Edit > Preferences > Add-ons > Whitted), keyed by the
package name, which is `whitted` as a legacy add-on and `bl_ext.<repo>.whitted` as
an extension."""

import bpy
from bpy.props import IntProperty

ADDON = __package__


class WhittedPreferences(bpy.types.AddonPreferences):
    bl_idname = ADDON

    memory_budget_mib: IntProperty(
        name="Memory Budget (MiB)",
        description="The most memory a Whitted render may need beyond Blender's own; a "
        "render estimated to need more is refused before it allocates. 0: the memory "
        "the system has available (the environment variable WHITTED_MEMORY_BUDGET, in "
        "MiB, overrides this, for farms that share machines)",
        default=0,
        min=0,
    )

    def draw(self, context):
        self.layout.prop(self, "memory_budget_mib")


def memory_budget_mib():
    """The budget set in the preferences, MiB; 0 when unset (or not registered)."""
    addon = bpy.context.preferences.addons.get(ADDON)
    return addon.preferences.memory_budget_mib if addon is not None else 0
