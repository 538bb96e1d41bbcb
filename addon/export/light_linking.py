"""Light linking and shadow linking (Blender 4.0+, Object > Light Linking), resolved into
the light sets and shadow sets the tracer reads (native scene/light.h).

An emitter (a light, or an object whose material emits) may name a receiver collection
(the objects it lights) and a blocker collection (the objects that cast its shadows).
Each object or child collection in it is linked with a state, Include or Exclude; an
object reached through a child collection takes that child's state. Blender's depsgraph
resolves this for Cycles (depsgraph_light_linking.cc), and we follow its rules:
- each distinct collection is one bit; each object named by any collection gets the mask
  of the collections that include it and of those that exclude it (a later link of the
  same collection overrides an earlier one);
- objects with the same two masks share a set, numbered from 1 in the order met; set 0
  holds every object no collection names; at most 63 linked sets (Cycles' 64 bits);
- an emitter lights set s when its collection includes s, or, if it includes no set at
  all, when it does not exclude s. So an emitter that only excludes lights everything
  else, set 0 included, and one that includes something lights only what it includes;
- an instance is in its instancer's set when that is not 0, else in its object's.
Shadow linking is the same with the blocker collections.
"""

from dataclasses import dataclass, field

ALL_SETS = (1 << 64) - 1  # an emitter without linking: every set
MAX_SETS = 64  # set 0 and 63 linked ones

# (light set, shadow set, light sets it lights, shadow sets that block it): an object
# that no emitter names and that links nothing.
UNLINKED = (0, 0, ALL_SETS, ALL_SETS)


@dataclass(frozen=True)
class Linking:
    """One kind of linking (light or shadow) resolved: each named object's set, each
    emitter's mask, by original object name."""

    sets: dict = field(default_factory=dict)  # object name -> its set (1..63)
    masks: dict = field(default_factory=dict)  # emitter name -> the sets it reaches
    overflow: int = 0  # objects left in set 0 past the 63 linked sets


@dataclass(frozen=True)
class LightLinks:
    """Light linking and shadow linking of a scene."""

    light: Linking = field(default_factory=Linking)
    shadow: Linking = field(default_factory=Linking)

    @property
    def used(self):
        return bool(self.light.masks or self.shadow.masks)

    def of_object(self, obj, instancer=None):
        """UNLINKED's four fields for evaluated object `obj` (shown by `instancer`, if an
        instance): its sets as a receiver and a blocker, its masks as an emitter."""
        name = obj.original.name_full
        parent = instancer.original.name_full if instancer is not None else None
        return (
            self.light.sets.get(parent) or self.light.sets.get(name, 0),
            self.shadow.sets.get(parent) or self.shadow.sets.get(name, 0),
            self.light.masks.get(name, ALL_SETS),
            self.shadow.masks.get(name, ALL_SETS),
        )

    def warnings(self):
        """What could not be linked, as report lines."""
        return [
            f"Whitted: {linking.overflow} object(s) past the 63 {what} sets Cycles allows "
            "are left unlinked"
            for what, linking in (("light linking", self.light), ("shadow linking", self.shadow))
            if linking.overflow
        ]


# A scene without light linking (and every scene before Blender 4.0).
NO_LINKS = LightLinks()


def light_links(objects):
    """LightLinks of the evaluated `objects` (a depsgraph's `objects`): every emitter's
    receiver and blocker collections. Blender before 4.0 has no light linking."""
    emitters = []
    for obj in objects:
        linking = getattr(obj.original, "light_linking", None)
        if linking is not None:
            emitters.append((obj.original.name_full, linking))
    return LightLinks(
        light=_resolve([(n, link.receiver_collection) for n, link in emitters]),
        shadow=_resolve([(n, link.blocker_collection) for n, link in emitters]),
    )


def _resolve(emitters):
    """Linking of [(emitter name, collection or None)]."""
    collection_bit = {}  # collection name -> its bit
    emitter_bit = {}
    for name, collection in emitters:
        if collection is None:
            continue
        key = collection.name_full
        collection_bit.setdefault(key, 1 << len(collection_bit))
        emitter_bit[name] = collection_bit[key]
    if not emitter_bit:
        return Linking()
    # Each named object's (include mask, exclude mask), in the order objects are met.
    masks = {}
    seen = set()
    for _, collection in emitters:
        if collection is None or collection.name_full in seen:
            continue
        seen.add(collection.name_full)
        bit = collection_bit[collection.name_full]
        for obj, state in _linked_objects(collection):
            include, exclude = masks.get(obj, (0, 0))
            if state == "INCLUDE":
                include, exclude = include | bit, exclude & ~bit
            else:
                include, exclude = include & ~bit, exclude | bit
            masks[obj] = (include, exclude)
    # Objects with equal masks share a set.
    set_of_masks = {}
    sets = {}
    overflow = 0
    for obj, pair in masks.items():
        number = set_of_masks.setdefault(pair, len(set_of_masks) + 1)
        if number >= MAX_SETS:
            overflow += 1
            continue
        sets[obj] = number
    emitter_masks = {}
    for name, bit in emitter_bit.items():
        included = excluded = 0
        for (include, exclude), number in set_of_masks.items():
            if number >= MAX_SETS:
                continue
            if include & bit:
                included |= 1 << number
            if exclude & bit:
                excluded |= 1 << number
        emitter_masks[name] = (included or ALL_SETS) & ~excluded
    return Linking(sets=sets, masks=emitter_masks, overflow=overflow)


def _linked_objects(collection):
    """(object name, link state) of each object a light linking collection reaches: its
    own objects with their states, and every object under each child collection with that
    child's state. The entries that hold the states name no object or collection: they
    are in the order of `objects` and `children` (one list each in Blender)."""
    for child, entry in zip(collection.children, collection.collection_children, strict=True):
        state = entry.light_linking.link_state
        for obj in child.all_objects:
            yield obj.name_full, state
    for obj, entry in zip(collection.objects, collection.collection_objects, strict=True):
        yield obj.name_full, entry.light_linking.link_state
