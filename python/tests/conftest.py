"""Shared fixtures of the `spatial` Python test suite.

Models (session-scoped, built once):
  stance_gen     spatial.hoap3_stance_right()                      compile-time, fixed base at the right sole
  stance_urdf    load_urdf(hoap3, root="R_SOLE", lock=LOCKS)       run-time twin of stance_gen
  floating_gen   spatial.hoap3_floating()                          compile-time, free-flyer at the pelvis
  floating_urdf  load_urdf(hoap3, floating=True, lock=LOCKS)       run-time twin of floating_gen
  pelvis_urdf    load_urdf(hoap3, lock=LOCKS)                      fixed base at base_link (Pinocchio's fixed model)

`states(model, count, seed)` draws random states (q within the joint limits; a random pose and unit quaternion for
the free-flyer). `dyn` runs the C++ command-line tool `spatial-dyn` (env var SPATIAL_DYN) on those states and maps its
CSV columns back to the Python model's coordinates by name. Test modules import the helpers with
`from conftest import ...` (pytest's default "prepend" import mode puts this directory on sys.path).
"""

import os
import shutil
import subprocess
import types

import numpy as np
import pytest

import spatial

# Head and wrists locked at 0: the generated HOAP-3 models' locks (the wrists move no mass).
LOCKS = {
    "CHEST_H_PAN_joint": 0.0,
    "H_PAN_H_TILT_joint": 0.0,
    "H_TILT_H_ROLL_joint": 0.0,
    "R_EB_R_WR_joint": 0.0,
    "L_EB_L_WR_joint": 0.0,
}
LOCK_ARG = ",".join(f"{k}={v:g}" for k, v in LOCKS.items())
FF_Q = ["x", "y", "z", "qx", "qy", "qz", "qw"]
FF_V = ["vx", "vy", "vz", "wx", "wy", "wz"]
REFERENCES = ["local", "world", "local_world_aligned"]

# The command-line options of spatial-dyn that load the same model as each fixture (None: not a URDF model).
CLI_OPTIONS = {
    "stance_gen": ["--root", "R_SOLE", "--lock", LOCK_ARG],
    "stance_urdf": ["--root", "R_SOLE", "--lock", LOCK_ARG],
    "floating_gen": ["--floating", "--lock", LOCK_ARG],
    "floating_urdf": ["--floating", "--lock", LOCK_ARG],
    "pelvis_urdf": ["--lock", LOCK_ARG],
}
# Frames used for Jacobians: frames of the model (links merged into bodies or into the base), whose frame is the
# URDF link's own frame in both the Python module and the command-line tool.
FRAMES = {
    "stance": ["L_SOLE", "R_HAND", "HEAD", "R_SOLE"],
    "floating": ["R_SOLE", "L_HAND", "HEAD", "base_link"],
    "pelvis": ["L_SOLE", "R_HAND", "HEAD"],
}


def hoap3_path():
    return spatial.urdf_path("hoap3.urdf")


_MODELS = {}


def get_model(key):
    """One of the session's models by fixture name (built on first use)."""
    if key not in _MODELS:
        path = hoap3_path()
        if key == "stance_gen":
            m = spatial.hoap3_stance_right()
        elif key == "stance_urdf":
            m = spatial.load_urdf(path, root="R_SOLE", lock=dict(LOCKS))
        elif key == "floating_gen":
            m = spatial.hoap3_floating()
        elif key == "floating_urdf":
            m = spatial.load_urdf(path, floating=True, lock=dict(LOCKS))
        elif key == "pelvis_urdf":
            m = spatial.load_urdf(path, lock=dict(LOCKS))
        else:
            raise KeyError(key)
        _MODELS[key] = m
    return _MODELS[key]


# Mass of the bodies that center_of_mass counts: a fixed base's moving bodies (the links merged into the base move
# nothing), a floating robot's every body. `Model.total_mass` is the whole robot's (base included) in both cases.
MOVING_MASS = {"stance": 8.6484, "floating": 8.8024, "pelvis": 8.3854}


def com_mass(key):
    return MOVING_MASS[key.split("_")[0]]


def frames_of(key):
    return FRAMES[key.split("_")[0]]


@pytest.fixture(scope="session")
def stance_gen():
    return get_model("stance_gen")


@pytest.fixture(scope="session")
def stance_urdf():
    return get_model("stance_urdf")


@pytest.fixture(scope="session")
def floating_gen():
    return get_model("floating_gen")


@pytest.fixture(scope="session")
def floating_urdf():
    return get_model("floating_urdf")


@pytest.fixture(scope="session")
def pelvis_urdf():
    return get_model("pelvis_urdf")


MODEL_KEYS = ["stance_gen", "stance_urdf", "floating_gen", "floating_urdf"]


@pytest.fixture(params=MODEL_KEYS)
def any_model(request):
    """(key, model) for each of the four HOAP-3 models: fixed/floating x compile-time/run-time."""
    return request.param, get_model(request.param)


# ---------------------------------------------------------------------------------------------------------------
# Random states


def random_q(model, rng, count):
    """`count` configurations: joints uniform within their limits ([-pi, pi] where a limit is infinite), and for a
    floating model a root position in [-1, 1]^3 and a random unit quaternion (x y z w)."""
    lower = np.asarray(model.lower, dtype=float)
    upper = np.asarray(model.upper, dtype=float)
    lo = np.where(np.isfinite(lower), lower, -np.pi)
    hi = np.where(np.isfinite(upper), upper, np.pi)
    joints = lo + (hi - lo) * rng.random((count, model.njoints))
    if not model.floating:
        return joints
    pos = rng.uniform(-1.0, 1.0, (count, 3))
    quat = rng.normal(size=(count, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return np.hstack([pos, quat, joints])


def states(model, count=3, seed=0):
    """Random states: Q (count, nq), V, A, T (count, nv) as a SimpleNamespace."""
    rng = np.random.default_rng(seed)
    Q = random_q(model, rng, count)
    V = rng.normal(size=(count, model.nv))
    A = rng.normal(size=(count, model.nv))
    T = rng.normal(size=(count, model.nv))
    return types.SimpleNamespace(Q=Q, V=V, A=A, T=T)


def tangent_names(model):
    """Names of the velocity coordinates as spatial-dyn writes them (free-flyer first)."""
    ff = [f"floating_base:{c}" for c in FF_V] if model.floating else []
    return ff + list(model.joint_names)


def config_names(model):
    ff = [f"floating_base:{c}" for c in FF_Q] if model.floating else []
    return ff + list(model.joint_names)


def assert_close(actual, expected, rtol=1e-12, atol_scale=None, err_msg=""):
    """|actual - expected| <= rtol * |expected| + rtol * max(1, max |expected|) (entries near zero)."""
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    assert actual.shape == expected.shape, f"{err_msg}: shape {actual.shape} != {expected.shape}"
    if atol_scale is not None:
        scale = atol_scale
    else:
        scale = max(1.0, float(np.max(np.abs(expected)))) if expected.size else 1.0
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=rtol * scale, err_msg=err_msg)


# ---------------------------------------------------------------------------------------------------------------
# The C++ command-line tool


class SpatialDyn:
    """Runs `spatial-dyn` on CSV files written with NumPy (17 significant digits: the doubles read back exactly)."""

    def __init__(self, exe, tmpdir):
        self.exe = exe
        self.tmpdir = tmpdir
        self.count = 0

    def run_raw(self, args, columns, values):
        """Writes `values` (rows x columns) under the header `columns`, runs `spatial-dyn ARGS --in FILE`, returns
        (header list, float array rows x outputs)."""
        self.count += 1
        path = os.path.join(self.tmpdir, f"in{self.count}.csv")
        np.savetxt(path, np.atleast_2d(values), delimiter=",", header=",".join(columns), comments="", fmt="%.17g")
        cmd = [self.exe] + list(args) + ["--in", path]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
        assert proc.returncode == 0, f"{' '.join(cmd)} failed ({proc.returncode}): {proc.stderr.strip()}"
        lines = proc.stdout.splitlines()
        header = lines[0].split(",")
        data = np.array([[float(x) for x in line.split(",")] for line in lines[1:] if line.strip()], dtype=float)
        return header, data

    def run(self, sub, key, model, Q, V=None, X=None, xkind="qdd", extra=()):
        """`spatial-dyn SUB` (a list, e.g. ["id"] or ["derivatives", "fd"]) with the model options of fixture `key`
        on states Q (and V, X: qd and qdd or tau columns). Returns a function out(prefix, rows=None) that gives
        the output columns PREFIX:<coordinate> (B, nv), PREFIX:<row>:<coordinate> (B, len(rows), nv) or
        PREFIX:<coordinate>:<coordinate> (rows="tangent": (B, nv, nv)), in the Python model's coordinate order."""
        qn, vn = config_names(model), tangent_names(model)
        cols = [f"q:{n}" for n in qn]
        vals = [np.atleast_2d(Q)]
        if V is not None:
            cols += [f"qd:{n}" for n in vn] + [f"{xkind}:{n}" for n in vn]
            vals += [np.atleast_2d(V), np.atleast_2d(X)]
        args = list(sub) + ["--urdf", hoap3_path()] + CLI_OPTIONS[key] + list(extra)
        header, data = self.run_raw(args, cols, np.hstack(vals))
        index = {name: k for k, name in enumerate(header)}
        assert data.shape == (np.atleast_2d(Q).shape[0], len(header)), (data.shape, len(header))

        def out(prefix, rows=None):
            if rows is None:
                names = [f"{prefix}:{n}" for n in vn]
                missing = [n for n in names if n not in index]
                assert not missing, f"spatial-dyn {' '.join(sub)}: no column {missing[0]} in {header[:8]}..."
                return data[:, [index[n] for n in names]]
            row_names = vn if rows == "tangent" else rows
            blocks = []
            for r in row_names:
                names = [f"{prefix}:{r}:{n}" for n in vn]
                missing = [n for n in names if n not in index]
                assert not missing, f"spatial-dyn {' '.join(sub)}: no column {missing[0]}"
                blocks.append(data[:, [index[n] for n in names]])
            return np.stack(blocks, axis=1)

        out.header = header
        out.data = data
        out.index = index
        return out


@pytest.fixture(scope="session")
def dyn(tmp_path_factory):
    exe = os.environ.get("SPATIAL_DYN")
    if not exe:
        pytest.skip("SPATIAL_DYN is not set: set it to the C++ command-line tool (e.g. build/bin/spatial-dyn) "
                    "to compare the bindings with the C++ results")
    if not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
        found = shutil.which(exe)
        if not found:
            pytest.skip(f"SPATIAL_DYN={exe!r} is not an executable file (build it: "
                        "cmake --build build --target spatial-dyn)")
        exe = found
    return SpatialDyn(exe, str(tmp_path_factory.mktemp("spatial_dyn")))
