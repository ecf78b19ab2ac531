"""spatial: rigid-body dynamics of kinematic trees from NumPy.

The C++ library (header-only, Featherstone's spatial vector algebra) behind NumPy functions::

    import numpy as np, spatial
    model = spatial.hoap3_stance_right()             # or spatial.load_urdf(path, root=..., lock={...})
    q = spatial.random_configuration(model)
    tau = spatial.rnea(model, q, np.zeros(model.nv), np.zeros(model.nv))
    Q = np.stack([spatial.random_configuration(model, seed=k) for k in range(1000)])
    G = spatial.gravity(model, Q, threads=0)          # (1000, nv), all cores, without the GIL

Every algorithm takes one state ((n,) arrays) or a batch ((B, n) arrays; an argument given as (n,) is shared by the
whole batch) and returns fresh float64 arrays. Conventions (frames, orders) are those of the C++ library and of
Pinocchio: Jacobian rows and 6-vectors linear first; a floating base's q = [x y z qx qy qz qw, joints] and
v = [linear, angular velocity of the root in root coordinates, joint rates].
"""

from __future__ import annotations

import os as _os
from typing import Mapping, Optional, Sequence

import numpy as _np

from ._spatial import (  # noqa: F401  (re-exported)
    Data,
    Model,
    ModelError,
    aba,
    aba_derivatives,
    bias,
    center_of_mass,
    centroidal_momentum,
    centroidal_momentum_matrix,
    com_jacobian,
    crba,
    difference,
    forward_dynamics,
    frame_jacobian,
    frame_placement,
    frame_velocity,
    gravity,
    hoap3_double_pendulum,
    hoap3_floating,
    hoap3_stance_left,
    hoap3_stance_right,
    hoap3_torso,
    integrate,
    inverse_inertia,
    kinetic_energy,
    normalize,
    potential_energy,
    rnea,
    rnea_derivatives,
)
from . import _spatial

__all__ = [
    "Data", "Model", "ModelError", "aba", "aba_derivatives", "bias", "center_of_mass", "centroidal_momentum",
    "centroidal_momentum_matrix", "com_jacobian", "crba", "difference", "forward_dynamics", "frame_jacobian",
    "frame_placement", "frame_velocity", "gravity", "hoap3_double_pendulum", "hoap3_floating", "hoap3_stance_left",
    "hoap3_stance_right", "hoap3_torso", "integrate", "inverse_inertia", "kinetic_energy", "load_urdf",
    "load_urdf_string", "neutral", "normalize", "potential_energy", "random_configuration", "rnea",
    "rnea_derivatives", "urdf_path",
]

_URDF_DIR = _os.path.join(_os.path.dirname(__file__), "urdf")


def urdf_path(name: str) -> str:
    """Path of a robot description shipped with the package ("hoap3.urdf", "double_pendulum.urdf")."""
    path = _os.path.join(_URDF_DIR, name)
    if not _os.path.isfile(path):
        have = sorted(f for f in _os.listdir(_URDF_DIR)) if _os.path.isdir(_URDF_DIR) else []
        raise FileNotFoundError(f"urdf_path: no robot description '{name}' in the package (it has: {', '.join(have)})")
    return path


def load_urdf(path: str, *, root: Optional[str] = None, floating: bool = False,
              lock: Optional[Mapping[str, float]] = None, subtree: Optional[str] = None,
              gravity: Optional[Sequence[float]] = None, strict_inertia: bool = False,
              axis_aligned: bool = True) -> Model:
    """Loads a URDF file into a run-time model.

    root: link to root the tree at (the fixed base, or the free-flying root with floating=True); default the URDF's
    root link. floating: the base link flies freely (free-flyer 'floating_base'). lock: {joint name: position} joints
    made rigid at that position. subtree: keep only this link and what hangs below it. gravity: 3 numbers in the
    root frame (default (0, 0, -9.81)). strict_inertia: refuse link inertias that break the triangle inequality
    (default: loaded, with a message in model.warnings). axis_aligned: turn body frames so that joints about -x, -y,
    -z use the cheaper axis-aligned joint types (same q, same physics).

    Raises ModelError (a ValueError) naming the file, link or joint and the reason (a file that cannot be read
    included).
    """
    path = _os.fspath(path)
    return _spatial._load_urdf(path, root, floating, dict(lock) if lock is not None else None, subtree, gravity,
                               strict_inertia, axis_aligned)


def load_urdf_string(xml: str, *, name: str = "<string>", root: Optional[str] = None, floating: bool = False,
                     lock: Optional[Mapping[str, float]] = None, subtree: Optional[str] = None,
                     gravity: Optional[Sequence[float]] = None, strict_inertia: bool = False,
                     axis_aligned: bool = True) -> Model:
    """Like load_urdf, from the URDF text itself; `name` stands for the file name in error messages."""
    return _spatial._load_urdf_string(xml, name, root, floating, dict(lock) if lock is not None else None, subtree,
                                      gravity, strict_inertia, axis_aligned)


def neutral(model: Model) -> _np.ndarray:
    """The neutral configuration (nq,): joints at 0; floating base at the origin with the identity orientation."""
    return _spatial._neutral(model)


def random_configuration(model: Model, seed: Optional[int] = None, *, batch: Optional[int] = None,
                         position_range: float = 1.0) -> _np.ndarray:
    """A random configuration (nq,), or (batch, nq): each joint uniform within its limits (an infinite limit is
    replaced by -pi or pi); a floating base uniform in the box [-position_range, position_range]^3 with a uniformly
    random orientation (unit quaternion, Shoemake's method)."""
    rng = _np.random.default_rng(seed)
    count = 1 if batch is None else int(batch)
    lo = _np.where(_np.isfinite(model.lower), model.lower, -_np.pi)
    hi = _np.where(_np.isfinite(model.upper), model.upper, _np.pi)
    joints = lo + rng.random((count, model.njoints)) * (hi - lo)
    if model.floating:
        pos = rng.uniform(-position_range, position_range, (count, 3))
        u1, u2, u3 = rng.random((3, count))
        a, b = _np.sqrt(1.0 - u1), _np.sqrt(u1)
        quat = _np.stack([a * _np.sin(2 * _np.pi * u2), a * _np.cos(2 * _np.pi * u2),
                          b * _np.sin(2 * _np.pi * u3), b * _np.cos(2 * _np.pi * u3)], axis=1)
        q = _np.concatenate([pos, quat, joints], axis=1)
    else:
        q = joints
    q = _np.ascontiguousarray(q)
    return q[0] if batch is None else q
