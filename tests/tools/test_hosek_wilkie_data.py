"""`python -m whitted_tools hosek-wilkie-data`: Mitsuba's tensor file read, the C++
table and the licence notice written from a wheel; without the network (a wheel made
here holding a tensor file of the dataset's fields and shapes)."""

import re
import struct
import zipfile

import pytest
from whitted_tools.generate import hosek_wilkie

LICENCE = "Copyright (c) 2012 - 2013, Lukas Hosek and Alexander Wilkie\nAll rights reserved.\n"


def tensor_file(fields, extra_dtype=None):
    """Mitsuba's tensor_file format of {name: (shape, values)}, float64 fields (and one
    of dtype `extra_dtype`, which the reader skips)."""
    entries = dict(fields)
    if extra_dtype is not None:
        entries["other"] = ((2,), [1.0, 2.0])
    header = b"tensor_file\0" + struct.pack("<BBI", 1, 0, len(entries))
    index_size = sum(2 + len(n) + 11 + 8 * len(s) for n, (s, _) in entries.items())
    offset = len(header) + index_size
    index, payload = b"", b""
    for name, (shape, values) in entries.items():
        dtype = extra_dtype if name == "other" else hosek_wilkie.FLOAT64
        index += struct.pack("<H", len(name)) + name.encode()
        index += struct.pack("<HBQ", len(shape), dtype, offset + len(payload))
        index += struct.pack(f"<{len(shape)}Q", *shape)
        payload += struct.pack(f"<{len(values)}d", *values)
    return header + index + payload


def dataset_fields():
    fields = {}
    for name, shape in hosek_wilkie.FIELDS.items():
        size = 1
        for extent in shape:
            size *= extent
        fields[name] = (shape, [0.25 * i - 3.0 for i in range(size)])
    return fields


def wheel(tmp_path, data):
    path = tmp_path / "mitsuba-3.9.1-cp311-cp311-manylinux_2_28_x86_64.whl"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr(hosek_wilkie.DATASET, data)
        archive.writestr(hosek_wilkie.LICENCE, LICENCE)
    return path


def test_the_reader_returns_each_float64_field_and_skips_others():
    fields = dataset_fields()
    read = hosek_wilkie.read_tensor_file(tensor_file(fields, extra_dtype=9))
    assert set(read) == set(fields)
    for name, (shape, values) in fields.items():
        assert read[name] == (shape, values)


def test_the_table_holds_every_value_in_order_under_the_notice(tmp_path):
    fields = dataset_fields()
    files = hosek_wilkie.outputs(wheel(tmp_path, tensor_file(fields)))
    table = files[hosek_wilkie.TABLE]
    assert "do not edit" in table.splitlines()[1]
    assert "// Copyright (c) 2012 - 2013, Lukas Hosek and Alexander Wilkie" in table
    for name, (_, values) in fields.items():
        cpp = hosek_wilkie.NAMES[name]
        body = re.search(rf"std::array<double, (\d+)> {cpp} = {{(.*?)}};", table, re.S)
        assert int(body.group(1)) == len(values)
        assert [float(v) for v in body.group(2).replace(",", " ").split()] == values
    notice = files[hosek_wilkie.NOTICE]
    assert notice.endswith(LICENCE) and "hosek_wilkie_data.inc" in notice


def test_a_file_not_of_the_format_or_shape_is_refused(tmp_path):
    with pytest.raises(ValueError, match="not a Mitsuba tensor file"):
        hosek_wilkie.read_tensor_file(b"PK\3\4 something else")
    fields = dataset_fields()
    fields["sky_rad_rgb"] = ((10, 2, 6, 11), [0.0] * 1320)  # the spectral shape
    with pytest.raises(ValueError, match="sky_rad_rgb has shape"):
        hosek_wilkie.outputs(wheel(tmp_path, tensor_file(fields)))


def test_check_compares_without_writing(tmp_path, capsys):
    # A wheel of other values: both committed files differ, and stay as they are.
    before = {path: path.read_text() for path in (hosek_wilkie.TABLE, hosek_wilkie.NOTICE)}
    assert (
        hosek_wilkie.main(
            ["--wheel", str(wheel(tmp_path, tensor_file(dataset_fields()))), "--check"]
        )
        == 1
    )
    assert capsys.readouterr().out.count(": differs") == 2
    assert before == {path: path.read_text() for path in before}
