"""Imports whitted_native from the build directory (WHITTED_BUILD_DIR, default build/)."""

import os
import sys
from pathlib import Path

BUILD_DIR = Path(os.environ.get("WHITTED_BUILD_DIR", Path(__file__).parents[2] / "build"))
sys.path.insert(0, str(BUILD_DIR))
