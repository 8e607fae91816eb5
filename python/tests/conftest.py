"""What the tests of the Python module nrsfm (python/) share."""
import os
import subprocess

import numpy as np
import pytest

import nrsfm


def rotating_w(frames, points, seed=7):
    """W (2F, P) of a rigid object turning about the vertical axis, seen by
    orthographic cameras (as tests/tools/bad_input_test.cc makes it)."""
    rng = np.random.default_rng(seed)
    shape = rng.uniform(-1.0, 1.0, size=(3, points))
    w = np.empty((2 * frames, points))
    for t in range(frames):
        a = 0.1 * t
        w[2 * t] = np.cos(a) * shape[0] + np.sin(a) * shape[2]
        w[2 * t + 1] = shape[1] + 0.5 * a
    return w


def reprojection(result):
    """W as the result reprojects it: points_camera[:, :, :2] + translations."""
    x = result.points_camera[:, :, :2, :] + result.translations[:, :, :, None]
    f, m, _, p = x.shape
    return x.reshape(f * m * 2, p)


@pytest.fixture(scope="module")
def random_sequence():
    """Noise-free random-basis data with 10 % missing, K = 3."""
    return nrsfm.synth(dataset="random", frames=80, points=30, K=3, missing=0.1, seed=4)


def cli():
    """The nrsfm binary of this build (NRSFM_CLI), or None."""
    path = os.environ.get("NRSFM_CLI")
    return path if path and os.path.exists(path) else None


def cli_error(args, cwd):
    """The error line of a failing `nrsfm` run, without its "nrsfm <command>:
    error: " prefix."""
    run = subprocess.run([cli()] + args, cwd=cwd, capture_output=True, text=True)
    assert run.returncode == 1, run.stdout + run.stderr
    line = run.stderr.strip().splitlines()[-1]
    prefix = "nrsfm %s: error: " % args[0]
    assert line.startswith(prefix), line
    return line[len(prefix):]
