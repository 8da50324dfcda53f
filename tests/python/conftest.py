"""Fixtures of the Python module's tests: the C++ reference run and the seeded generator."""
import os
import subprocess

import numpy as np
import pytest


class Reference:
    """The arrays python_reference wrote: reference.f32("name"), reference.f64("name")."""

    def __init__(self, directory):
        self.directory = directory

    def path(self, name):
        return os.path.join(self.directory, name)

    def f32(self, name):
        return np.fromfile(self.path(name + ".f32"), dtype="<f4")

    def f64(self, name):
        return np.fromfile(self.path(name + ".f64"), dtype="<f8")


@pytest.fixture(scope="session")
def reference(tmp_path_factory):
    program = os.environ.get("ACDF_PYTHON_REFERENCE")
    if not program:
        pytest.fail("ACDF_PYTHON_REFERENCE is not set (run the tests through ctest)")
    directory = tmp_path_factory.mktemp("reference")
    subprocess.run([program, str(directory)], check=True)
    return Reference(str(directory))


@pytest.fixture
def rng():
    return np.random.default_rng(20261202)


@pytest.fixture
def shared_map():
    """The real sun-lit map of ../shared (ACDF_SHARED_DATA); the test skips, saying so, without it."""
    directory = os.environ.get("ACDF_SHARED_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "..",
                                                                "shared", "data"))
    path = os.path.join(directory, "envmaps", "sunset_1024x512.exr")
    if not os.path.exists(path):
        pytest.skip(f"{path} is absent (the shared data is not on this machine)")
    return path
