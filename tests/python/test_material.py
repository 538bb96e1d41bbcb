"""whitted_native.Material as its tables define it (native/src/scene/material.h): its
keywords and attributes are MATERIAL_PARAMS, the fields a program may drive
MATERIAL_FIELDS; the add-on builds its data class and program outputs on these."""

import pytest
import whitted_native as wn

PARAMS = dict(wn.MATERIAL_PARAMS)


def _as_given(value):
    # An attribute as the constructor takes it: an enum by its member's name.
    return value.name if hasattr(type(value), "__members__") else value


def test_every_parameter_is_a_keyword_and_an_attribute_defaulting_as_the_table_says():
    default = wn.Material()
    assert len(PARAMS) == len(wn.MATERIAL_PARAMS)  # no name twice
    for name, value in wn.MATERIAL_PARAMS:
        assert _as_given(getattr(default, name)) == value, name
        assert _as_given(getattr(wn.Material(**{name: value}), name)) == value, name


def test_given_values_come_back():
    material = wn.Material(
        diffuse=(0.1, 0.2, 0.3),
        coat_ior=1.3,
        priority=2,
        masking="SEPARABLE",
        diffuse_model=wn.DiffuseModel.BURLEY,
        coat_model="GTR1",
        diffuse_texture="wood",
    )
    assert material.diffuse == pytest.approx((0.1, 0.2, 0.3))
    assert material.coat_ior == pytest.approx(1.3)
    assert material.priority == 2
    assert material.masking == wn.Masking.SEPARABLE
    assert material.diffuse_model == wn.DiffuseModel.BURLEY
    assert material.coat_model == wn.CoatModel.GTR1
    assert wn.Material().coat_model == wn.CoatModel.GGX
    assert material.diffuse_texture == "wood"


def test_program_fields_are_named_and_sized_as_the_parameters():
    names = [name for name, _ in wn.MATERIAL_FIELDS]
    assert len(set(names)) == len(names)
    for name, components in wn.MATERIAL_FIELDS:
        assert components in (1, 3), name
        if name in PARAMS:
            value = PARAMS[name]
            assert components == (len(value) if isinstance(value, tuple) else 1), name
    # Every field a program may drive is accepted as an output.
    # One register, set before the first instruction (MATH ADD of unused operands).
    unused = wn.OP_NUMBERS["UNUSED"]
    code = [(wn.OPS.index(("MATH", 3, False)), 0, 0, unused, unused, unused, unused, unused)]
    program = wn.Program(code, [[0.0] * 4], [])
    outputs = dict.fromkeys(names, 0)
    assert wn.Material(program=program, outputs=outputs).outputs == outputs


def test_bad_parameters_name_themselves():
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        wn.Material(colour=(1, 1, 1))
    with pytest.raises(TypeError, match="diffuse: expected"):
        wn.Material(diffuse="red")
    with pytest.raises(TypeError, match="shininess: expected"):
        wn.Material(shininess=(1, 2))
    with pytest.raises(TypeError, match="program: expected a Program"):
        wn.Material(program="p")
    with pytest.raises(ValueError, match="masking: 'ROUGH' is not a Masking"):
        wn.Material(masking="ROUGH")
    with pytest.raises(ValueError, match="bump_shadowing: 3 is not a BumpShadowing"):
        wn.Material(bump_shadowing=3)
    # What Material's own constructor refuses.
    with pytest.raises(ValueError, match="coat_ior must be positive"):
        wn.Material(coat_ior=-1.0)
