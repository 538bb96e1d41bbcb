"""Cryptomatte ids and metadata (addon/cryptomatte.py), without Blender: the hash
against MurmurHash3's published values and the specification's own examples."""

import importlib.util
import json
import math
import struct
from pathlib import Path

import pytest

PATH = Path(__file__).parents[2] / "addon" / "cryptomatte.py"
SPEC = importlib.util.spec_from_file_location("whitted_cryptomatte", PATH)
crypto = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(crypto)


@pytest.mark.parametrize(
    ("data", "seed", "expected"),
    [
        ("", 0, 0x00000000),
        ("hello", 0, 0x248BFA47),
        ("The quick brown fox jumps over the lazy dog", 0, 0x2E4FF723),
        ("Hello, world!", 1234, 0xFAF6CDB3),
    ],
)
def test_murmur3_gives_the_published_values(data, seed, expected):
    assert crypto.murmur3_32(data, seed) == expected


def test_ids_are_the_specifications_examples():
    # The manifest examples of the Cryptomatte specification 1.1.0.
    assert f"{crypto.id_bits('bunny'):08x}" == "13851a76"
    assert f"{crypto.id_bits('default'):08x}" == "42c9679f"
    assert f"{crypto.id_bits('bunny_porcelain_mat'):08x}" == "b24b26d4"


def test_every_id_is_a_normal_finite_float():
    for i in range(5000):
        value = crypto.id_float(f"Object.{i:03d}")
        assert math.isfinite(value) and value != 0.0
        bits = struct.unpack("<I", struct.pack("<f", value))[0]
        assert bits == crypto.id_bits(f"Object.{i:03d}")
        assert 1 <= (bits >> 23) & 0xFF <= 254


def test_layer_passes_and_metadata_are_named_as_blender_names_them():
    assert crypto.pass_names("CryptoObject", 6) == [
        "CryptoObject00",
        "CryptoObject01",
        "CryptoObject02",
    ]
    assert crypto.pass_names("CryptoAsset", 3) == ["CryptoAsset00", "CryptoAsset01"]
    fields = crypto.metadata("ViewLayer", "CryptoMaterial", ["Glass", "Floor", "Glass"])
    key = f"{crypto.murmur3_32('ViewLayer.CryptoMaterial'):08x}"[:7]
    assert set(fields) == {
        f"cryptomatte/{key}/{f}" for f in ("name", "hash", "conversion", "manifest")
    }
    assert fields[f"cryptomatte/{key}/name"] == "ViewLayer.CryptoMaterial"
    assert fields[f"cryptomatte/{key}/hash"] == "MurmurHash3_32"
    assert fields[f"cryptomatte/{key}/conversion"] == "uint32_to_float32"
    manifest = json.loads(fields[f"cryptomatte/{key}/manifest"])
    assert manifest == {
        "Floor": f"{crypto.id_bits('Floor'):08x}",
        "Glass": f"{crypto.id_bits('Glass'):08x}",
    }
