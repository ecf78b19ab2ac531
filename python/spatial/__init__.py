"""spatial: rigid-body dynamics of kinematic trees from NumPy.

The C++ library (header-only, Featherstone's spatial vector algebra) behind NumPy functions::

    import numpy as np, spatial
    model = spatial.hoap3_stance_right()             # or spatial.load_urdf(path, root=..., lock={...})
    q = spatial.random_configuration(model)
    tau = spatial.rnea(model, q, np.zeros(model.nv), np.zeros(model.nv))
    Q = np.stack([spatial.random_configuration(model, seed=k) for k in range(1000)])
    G = spatial.gravity(model, Q, threads=0)          # (1000, nv), all cores, without the GIL
    G = spatial.Batch(model).gravity(Q)               # the same on SIMD lanes: ~2x the states per second

Every algorithm takes one state ((n,) arrays) or a batch ((B, n) arrays; an argument given as (n,) is shared by the
whole batch) and returns fresh float64 arrays. Conventions (frames, orders) are those of the C++ library and of
Pinocchio: Jacobian rows and 6-vectors linear first; a floating base's q = [x y z qx qy qz qw, joints] and
v = [linear, angular velocity of the root in root coordinates, joint rates].
"""

from __future__ import annotations

import os as _os
from dataclasses import dataclass, field
from typing import List, Mapping, Optional, Sequence, Tuple, Union

import numpy as _np

from ._spatial import (  # noqa: F401  (re-exported)
    Batch,
    Contact,
    Contact3D,
    Contact6D,
    Contacts,
    Data,
    Dyn,
    Model,
    ModelError,
    aba,
    aba_derivatives,
    bias,
    center_of_mass,
    centroidal_momentum,
    centroidal_momentum_matrix,
    centroidal_momentum_time_variation,
    center_of_pressure,
    com_jacobian,
    constrained_forward_dynamics,
    contact_inverse_dynamics,
    contact_jacobian,
    contact_wrench,
    crba,
    difference,
    forward_dynamics,
    frame_acceleration,
    frame_classical_acceleration,
    frame_jacobian,
    frame_jacobian_time_variation,
    frame_placement,
    frame_velocity,
    gravity,
    hoap3_double_pendulum,
    hoap3_floating,
    hoap3_stance_left,
    hoap3_stance_right,
    hoap3_torso,
    impulse_dynamics,
    integrate,
    inverse_inertia,
    keep_branches,
    keep_joints,
    kinetic_energy,
    lock_joints,
    multibody_zmp,
    normalize,
    potential_energy,
    rnea,
    rnea_derivatives,
    walk,
)
from . import _spatial

__all__ = [
    "Batch", "Data", "Dyn", "Model", "ModelError", "aba", "aba_derivatives", "bias", "center_of_mass", "centroidal_momentum",
    "centroidal_momentum_matrix", "centroidal_momentum_time_variation", "com_jacobian", "crba", "difference",
    "forward_dynamics", "frame_acceleration", "frame_classical_acceleration", "frame_jacobian",
    "frame_jacobian_time_variation", "frame_placement", "frame_velocity", "gravity", "hoap3_double_pendulum",
    "hoap3_floating", "hoap3_stance_left", "hoap3_stance_right", "hoap3_torso", "integrate", "inverse_inertia",
    "kinetic_energy", "load_urdf", "load_urdf_string", "neutral", "normalize", "potential_energy",
    "random_configuration", "rnea", "rnea_derivatives", "urdf_path", "IkTask", "IkStatus", "IkSolver",
    "ik_position", "ik_orientation", "ik_pose", "ik_center_of_mass", "Contact", "Contact3D", "Contact6D",
    "Contacts", "center_of_pressure", "constrained_forward_dynamics", "contact_inverse_dynamics",
    "contact_jacobian", "contact_wrench", "impulse_dynamics", "multibody_zmp", "lock_joints", "keep_joints",
    "keep_branches", "walk",
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


# ---- inverse kinematics -------------------------------------------------------------------------------------------

@dataclass
class IkTask:
    """One task of an IkSolver (build it with ik_position, ik_orientation, ik_pose or ik_center_of_mass).

    Errors are target minus current, in world coordinates (fixed base: base coordinates): position p* - p (3 rows),
    orientation log(R* R^T) (3 rows, a rotation vector in world axes), pose [p* - p; log(R* R^T)] (6 rows, linear
    first), centre of mass c* - c (3 rows; fixed base: of the moving bodies). `weight` multiplies every row, `axes`
    each row (e.g. axes=(0, 0, 1) on a position task constrains the height only)."""
    kind: str
    frame: Union[str, int] = -1
    position: _np.ndarray = field(default_factory=lambda: _np.zeros(3))
    rotation: _np.ndarray = field(default_factory=lambda: _np.eye(3))
    weight: float = 1.0
    axes: _np.ndarray = field(default_factory=lambda: _np.ones(6))


def _axes(axes, rows):
    a = _np.ones(6)
    if axes is not None:
        given = _np.asarray(axes, dtype=float).ravel()
        if given.size != rows:
            raise ValueError(f"ik task: 'axes' has {given.size} entries, the task has {rows} rows")
        a[:rows] = given
    return a


def ik_position(frame: Union[str, int], position, weight: float = 1.0, axes=None) -> IkTask:
    """Frame origin at `position` (3,), world coordinates."""
    return IkTask("position", frame, _np.asarray(position, float), _np.eye(3), float(weight), _axes(axes, 3))


def ik_orientation(frame: Union[str, int], rotation, weight: float = 1.0, axes=None) -> IkTask:
    """Frame axes at `rotation` (3, 3): frame axes -> world axes."""
    return IkTask("orientation", frame, _np.zeros(3), _np.asarray(rotation, float), float(weight), _axes(axes, 3))


def ik_pose(frame: Union[str, int], position, rotation, weight: float = 1.0, axes=None) -> IkTask:
    """Frame at `position` (3,) with axes `rotation` (3, 3); 6 rows, linear first."""
    return IkTask("pose", frame, _np.asarray(position, float), _np.asarray(rotation, float), float(weight),
                  _axes(axes, 6))


def ik_center_of_mass(position, weight: float = 1.0, axes=None) -> IkTask:
    """Centre of mass at `position` (3,), world coordinates (fixed base: of the moving bodies, base coordinates)."""
    return IkTask("center_of_mass", -1, _np.asarray(position, float), _np.eye(3), float(weight), _axes(axes, 3))


@dataclass
class IkStatus:
    """How a solve ended: converged (residual <= tolerance), reason ('converged', 'max_iterations', 'stalled',
    'non_finite'), iterations (linear solves), accepted (steps taken), residual (the weighted error's norm at the
    returned q), damping (the final Levenberg-Marquardt damping)."""
    converged: bool
    reason: str
    iterations: int
    accepted: int
    residual: float
    damping: float


class IkSolver:
    """Inverse kinematics: several weighted tasks at once, damped least squares with adaptive
    (Levenberg-Marquardt) damping, on the configuration manifold for a floating base, joint limits kept by
    projection. The C++ solver (ik.hpp) allocates its workspace here, once.

    lower, upper: joint limits (one per joint, not the free-flyer); default the model's (model.lower/upper; pass
    arrays of -inf/inf for none). active: velocity coordinates that may move (default all). Other options as in
    ik.hpp's IkOptions.
    """

    def __init__(self, model: Model, tasks: Sequence[IkTask], *, lower=None, upper=None,
                 active: Optional[Sequence[int]] = None, max_iterations: int = 200, tolerance: float = 1e-12,
                 step_tolerance: float = 1e-15, damping: float = 1e-6, adaptive: bool = True):
        self.model = model
        self._tasks = [self._resolve(t) for t in tasks]
        self._solver = _spatial._IkSolver(
            model, self._tasks, max_iterations, tolerance, step_tolerance, damping, adaptive,
            model.lower if lower is None else lower, model.upper if upper is None else upper,
            list(active) if active is not None else [])

    def _resolve(self, t: IkTask) -> IkTask:
        if t.kind != "center_of_mass" and isinstance(t.frame, str):
            t = IkTask(t.kind, self.model.frame_index(t.frame), t.position, t.rotation, t.weight, t.axes)
        return t

    @property
    def rows(self) -> int:
        """Rows of the stacked error."""
        return self._solver.rows

    @property
    def tasks(self) -> List[IkTask]:
        return list(self._tasks)

    def set_task(self, i: int, task: IkTask) -> None:
        """Replaces task i's target, weight and axes (its kind and frame are fixed at construction)."""
        t = self._resolve(task)
        if t.kind != self._tasks[i].kind or t.frame != self._tasks[i].frame:
            raise ValueError(f"IkSolver.set_task: task {i} is a {self._tasks[i].kind} task on frame "
                             f"{self._tasks[i].frame}; only its target, weight and axes can change")
        self._solver.set_task(i, t)
        self._tasks[i] = t

    def residual(self, q) -> Tuple[float, _np.ndarray]:
        """(||r||, r) at q: the weighted stacked error, tasks in order."""
        return self._solver.residual(q)

    def solve(self, q0, *, threads: int = 1):
        """From the start q0 (nq,), returns (q, IkStatus); from starts (B, nq), (Q (B, nq), [IkStatus] * B), the
        starts solved independently (on `threads` threads: 0 = all cores). q is the best configuration found (inside
        the limits), also when not converged."""
        q, status = self._solver.solve(q0, threads)
        st = [IkStatus(*s) for s in status]
        return (q, st) if q.ndim == 2 else (q, st[0])
