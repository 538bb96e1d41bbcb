"""Cryptomatte (Psyop's specification 1.1.0) names, ids and metadata: plain Python
(no bpy), tested without Blender (tests/python/test_cryptomatte.py).

An id is MurmurHash3_x86_32 (seed 0) of a name's UTF-8 bytes, stored in the pixels
as the float32 with the same bits, its exponent clamped to 1..254 so that no id is
a NaN, an infinity or a denormal. Blender hashes an object's or a material's name
(ID name without its two-letter code) and an asset's: the object's topmost parent.

A layer (one kind of id in one view layer) is named "<view layer>.CryptoObject"
(or CryptoMaterial, CryptoAsset); its passes are CryptoObject00, 01, ..., each RGBA =
(id, coverage, id, coverage) of two ranks, ranks sorted by coverage; its metadata
key is the first 7 hex digits of the hash of the layer's name:
cryptomatte/<key>/name, hash, conversion, manifest (a JSON object from name to
the 8 hex digits of the id's float bits).
"""

import json
import struct

KINDS = ("CryptoObject", "CryptoMaterial", "CryptoAsset")
HASH = "MurmurHash3_32"
CONVERSION = "uint32_to_float32"

_MASK = 0xFFFFFFFF


def murmur3_32(data, seed=0):
    """MurmurHash3_x86_32 of `data` (bytes, or str as UTF-8): an unsigned 32-bit int."""
    if isinstance(data, str):
        data = data.encode("utf-8")
    c1, c2 = 0xCC9E2D51, 0x1B873593
    h = seed & _MASK
    whole = len(data) // 4 * 4
    for (k,) in struct.iter_unpack("<I", data[:whole]):
        h ^= _mix(k, c1, c2)
        h = _rotl(h, 13)
        h = (h * 5 + 0xE6546B64) & _MASK
    tail = data[whole:]
    if tail:
        h ^= _mix(int.from_bytes(tail, "little"), c1, c2)
    h ^= len(data)
    h ^= h >> 16
    h = (h * 0x85EBCA6B) & _MASK
    h ^= h >> 13
    h = (h * 0xC2B2AE35) & _MASK
    return h ^ (h >> 16)


def _mix(k, c1, c2):
    k = (k * c1) & _MASK
    return (_rotl(k, 15) * c2) & _MASK


def _rotl(x, r):
    return ((x << r) | (x >> (32 - r))) & _MASK


def id_bits(name):
    """The bits of the float32 id of `name`: its hash with the exponent clamped."""
    h = murmur3_32(name)
    exponent = min(max((h >> 23) & 0xFF, 1), 254)
    return (h & 0x807FFFFF) | (exponent << 23)


def id_float(name):
    """The id of `name` as the float32 a pixel holds (a Python float of that value)."""
    return struct.unpack("<f", struct.pack("<I", id_bits(name)))[0]


def layer_name(view_layer, kind):
    """The layer's name, as Blender and Cycles write it: "ViewLayer.CryptoObject"."""
    return f"{view_layer}.{kind}"


def pass_names(kind, depth):
    """The passes of a layer of `depth` ranks: two ranks a pass, "CryptoObject00", ..."""
    return [f"{kind}{i:02d}" for i in range((depth + 1) // 2)]


def metadata(view_layer, kind, names):
    """{EXR header field: value} of one layer whose ids come from `names`."""
    layer = layer_name(view_layer, kind)
    key = f"{murmur3_32(layer):08x}"[:7]
    prefix = f"cryptomatte/{key}/"
    manifest = {name: f"{id_bits(name):08x}" for name in sorted(set(names))}
    return {
        prefix + "name": layer,
        prefix + "hash": HASH,
        prefix + "conversion": CONVERSION,
        prefix + "manifest": json.dumps(manifest, separators=(",", ":")),
    }
