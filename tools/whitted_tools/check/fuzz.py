"""A long run of the randomized ("fuzz") native tests under ASan and UBSan.

    .venv/bin/python -m whitted_tools fuzz [ITERATIONS]      (default 20000)

Configures and builds build-asan/ (the core and its tests only, -DWHITTED_SANITIZE=ON),
then runs the Fuzz.* gtest cases with WHITTED_FUZZ_ITERATIONS scenes. The test suite
runs the same tests briefly (60 scenes).
"""

import argparse
import os
import subprocess

from whitted_tools import REPO
from whitted_tools.verbs import prog


def main(argv):
    parser = argparse.ArgumentParser(prog=prog(__name__), description=__doc__.splitlines()[0])
    parser.add_argument("iterations", nargs="?", type=int, default=20000)
    args = parser.parse_args(argv)
    configure = ["cmake", "-S", ".", "-B", "build-asan", "-DCMAKE_BUILD_TYPE=RelWithDebInfo"]
    configure += ["-DWHITTED_SANITIZE=ON", "-DWHITTED_PYTHON=OFF", "-DWHITTED_TESTS=ON"]
    subprocess.run(configure, cwd=REPO, check=True, stdout=subprocess.DEVNULL)
    build = ["cmake", "--build", "build-asan", "--parallel", str(os.cpu_count())]
    subprocess.run(build, cwd=REPO, check=True)
    env = {**os.environ, "WHITTED_FUZZ_ITERATIONS": str(args.iterations)}
    tests = [str(REPO / "build-asan" / "whitted_tests"), "--gtest_filter=Fuzz.*"]
    return subprocess.run(tests, cwd=REPO, env=env, check=False).returncode or None
