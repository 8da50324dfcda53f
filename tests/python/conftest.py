"""Fixtures of the Python module's tests: the C++ reference run, the seeded generator, the maps and a room."""
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


# A 4 x 2.6 x 4 room of quads (corner, edge_u, edge_v); its +z wall has a 1.4 x 1.1 window at x in
# [-0.7, 0.7], y in [0.9, 2.0] (WINDOW_QUAD fills it), and a camera inside that sees it.
ROOM_QUADS = [([-2, 0, -2], [4, 0, 0], [0, 0, 4]), ([-2, 2.6, -2], [4, 0, 0], [0, 0, 4]),
              ([-2, 0, -2], [4, 0, 0], [0, 2.6, 0]), ([-2, 0, -2], [0, 0, 4], [0, 2.6, 0]),
              ([2, 0, -2], [0, 0, 4], [0, 2.6, 0]), ([-2, 0, 2], [1.3, 0, 0], [0, 2.6, 0]),
              ([0.7, 0, 2], [1.3, 0, 0], [0, 2.6, 0]), ([-0.7, 0, 2], [1.4, 0, 0], [0, 0.9, 0]),
              ([-0.7, 2.0, 2], [1.4, 0, 0], [0, 0.6, 0])]
WINDOW_QUAD = ([-0.7, 0.9, 2], [1.4, 0, 0], [0, 1.1, 0])
ROOM_CAMERA = dict(eye=[-1.5, 1.5, 1.5], target=[0.5, 0.8, -1.2], up=[0, 1, 0], fov=62, width=64, height=48)


def assert_portal_covers_window(portal):
    """An opening found in the room covers its window to 3 % of the wall and faces into the room."""
    corner, u, v = (np.asarray(portal[key], dtype=np.float64) for key in ("corner", "edge_u", "edge_v"))
    assert np.cross(u, v)[2] < 0  # into the room (z < 2)
    xs, ys = sorted([corner[0], corner[0] + u[0] + v[0]]), sorted([corner[1], corner[1] + u[1] + v[1]])
    np.testing.assert_allclose([*xs, *ys], [-0.7, 0.7, 0.9, 2.0], atol=0.03 * 4)
    assert abs(corner[2] - 2.0) < 0.03 * 4
