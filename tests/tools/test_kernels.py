"""compare_kernels.py's results as a table (whitted_tools.kernels), on hand-made results."""

from whitted_tools.kernels import kernel_table


def result(name, ratio, preset=None, passes=(), equal=True, worst=0.0):
    return {
        "file": name,
        "preset": preset,
        "passes": list(passes),
        "rays_equal": equal,
        "max_relative": worst,
        "pixels_over_1e-4": 0,
        "speed_ratio": ratio,
    }


def test_one_row_per_configuration_with_the_spread_of_the_ratios():
    lines = kernel_table(
        [
            result("a.blend", 0.9, "PREVIEW", ["depth"], worst=1e-7),
            result("b.blend", 1.2, "PREVIEW", ["depth"], equal=False),
            result("c.blend", 1.1, "PREVIEW", ["depth"]),
            result("a.blend", 1.05),
        ]
    )
    assert lines[2] == (
        "| PREVIEW, passes: depth | 3 | 2 of 3 | 1e-07 (a.blend) | 0 | "
        "0.900, 1.100, 1.200 | 2 of 3 |"
    )
    assert lines[3].startswith("| the file's own controls, passes: none | 1 | 1 of 1 |")
    assert len(lines) == 5 and lines[-1] == ""
