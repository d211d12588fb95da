"""`cmake --install` (tools/install) puts the package where Debian's python3
looks when the prefix is /usr/local, and an installed package runs the
yarnvox installed beside it. Installs the build into a scratch prefix.

    python3 installed_where_python_looks.py BUILD_DIR INSTALL_DIR SCRATCH
"""

import os
import shutil
import site
import subprocess
import sys


def main(build, install_dir, scratch):
    looked_in = site.getsitepackages()[0]
    if looked_in != os.path.join("/usr/local", install_dir):
        return f"the package would go to /usr/local/{install_dir}, python3 looks in {looked_in}"
    shutil.rmtree(scratch, ignore_errors=True)
    subprocess.run(["cmake", "--install", build, "--prefix", scratch], check=True, stdout=subprocess.DEVNULL)
    env = dict(os.environ, PYTHONPATH=os.path.join(scratch, install_dir))
    env.pop("YARNVOX_EXECUTABLE", None)
    shown = subprocess.run([sys.executable, "-c", "import yarnvox; print(yarnvox.__file__); print(yarnvox.executable())"],
                           env=env, cwd=scratch, capture_output=True, text=True)
    if shown.returncode != 0:
        return "the installed package does not import: " + shown.stderr.strip().splitlines()[-1]
    module, runs = shown.stdout.split()
    if not module.startswith(os.path.join(scratch, install_dir)):
        return f"imported {module}, not the installed copy"
    if os.path.realpath(runs) != os.path.realpath(os.path.join(scratch, "bin", "yarnvox")):
        return f"the installed package runs {runs}, not the yarnvox installed beside it"
    print(f"ok: installed to {install_dir}, where python3 looks; it runs {runs}")
    shutil.rmtree(scratch)
    return None


if __name__ == "__main__":
    why = main(*sys.argv[1:4])
    if why:
        print("FAILED:", why)
        sys.exit(1)
