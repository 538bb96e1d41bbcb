"""The table of scripts/compare_kernels.py's results, one row per configuration.

.venv/bin/python scripts/compare_kernels_table.py RESULT.json ...
"""

import argparse
import json
from pathlib import Path

from whitted_tools.kernels import kernel_table


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", nargs="+", type=Path)
    args = parser.parse_args()
    results = [json.loads(path.read_text()) for path in args.results]
    print("\n".join(kernel_table(results)))


if __name__ == "__main__":
    main()
