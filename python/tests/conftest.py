"""Fixtures of the module's tests: the yarnvox command line built beside the
module (--yarnvox), a scratch folder (--scratch), and small garments made by
`yarnvox gen` in it. Every test runs with the scratch folder as its working
directory, so the module and the command line are given the same relative
paths (a .vdb records its input's path)."""

import os
import shutil
import subprocess

import pytest


def pytest_addoption(parser):
    parser.addoption("--yarnvox", required=True, help="the yarnvox executable of the same build")
    parser.addoption("--scratch", required=True, help="a folder for the tests' files (emptied first)")


@pytest.fixture(scope="session")
def scratch_root(request):
    root = os.path.abspath(request.config.getoption("--scratch"))
    shutil.rmtree(root, ignore_errors=True)
    os.makedirs(root)
    return root


@pytest.fixture
def scratch(scratch_root, request, monkeypatch):
    folder = os.path.join(scratch_root, request.node.name.replace("[", "-").replace("]", ""))
    os.makedirs(folder)
    monkeypatch.chdir(folder)
    return folder


class Cli:
    """The yarnvox command line: run() returns the finished process."""

    def __init__(self, path):
        self.path = path

    def run(self, *words, check=True):
        p = subprocess.run([self.path, *map(str, words)], capture_output=True, text=True)
        if check and p.returncode != 0:
            raise AssertionError(f"yarnvox {' '.join(map(str, words))} failed:\n{p.stderr}")
        return p

    def error_line(self, *words):
        """The one line a refused command prints, without "yarnvox: error: " and " (see --help)"."""
        p = self.run(*words, check=False)
        assert p.returncode != 0, f"yarnvox {' '.join(map(str, words))} succeeded"
        line = p.stderr.strip().splitlines()[-1]
        assert line.startswith("yarnvox: error: "), line
        line = line[len("yarnvox: error: "):]
        return line[: -len(" (see --help)")] if line.endswith(" (see --help)") else line


@pytest.fixture(scope="session")
def cli(request):
    path = os.path.abspath(request.config.getoption("--yarnvox"))
    assert os.access(path, os.X_OK), f"{path}: no yarnvox executable"
    return Cli(path)


@pytest.fixture
def knit(scratch, cli):
    """A small knit cylinder, knit.bcc in the test's folder."""
    cli.run("gen", "--pattern", "knit", "--shape", "cylinder", "--crossings", 60, "--seed", 3, "-o", "knit.bcc")
    return "knit.bcc"
