"""`import yarnvox` in Debian's python3 with no PYTHONPATH, from a folder
that is not the project's, finds this build's module (tools/setup registers
the checkout's build with python3) and runs this build's yarnvox. Exits 1
naming what it found otherwise.

    python3 found_without_pythonpath.py BUILD_DIR
"""

import os
import sys


def main(build):
    if os.environ.get("PYTHONPATH"):
        return "PYTHONPATH is set: the test is of python3 finding the module without it"
    try:
        import yarnvox
    except ImportError as e:
        return f"python3 does not find yarnvox ({e}): tools/setup registers this checkout's build with it"
    found = os.path.realpath(os.path.dirname(yarnvox.__file__))
    wanted = os.path.realpath(os.path.join(build, "python", "yarnvox"))
    if found != wanted:
        return f"python3 finds yarnvox at {found}, not this build's {wanted}: run tools/setup, or remove the other copy"
    runs = os.path.realpath(yarnvox.executable())
    if runs != os.path.realpath(os.path.join(build, "yarnvox")):
        return f"the module runs {runs}, not this build's yarnvox"
    print(f"ok: python3 imports {found} and runs {runs}")
    return None


if __name__ == "__main__":
    why = main(sys.argv[1])
    if why:
        print("FAILED:", why)
        sys.exit(1)
