"""Models: the generated compile-time HOAP-3 models against their URDF-loaded run-time twins (attributes and every
algorithm, ~1e-12), model attributes and name look-ups, loader options, and the fixed- and floating-base models
against the C++ command-line tool's model description (joint order)."""

import os

import numpy as np
import pytest

import spatial
from conftest import LOCKS, REFERENCES, assert_close, hoap3_path, states

# generated model -> how load_urdf gives the same model (src/models/CMakeLists.txt)
TWINS = {
    "hoap3_stance_right": ("hoap3.urdf", dict(root="R_SOLE", lock=LOCKS)),
    "hoap3_stance_left": ("hoap3.urdf", dict(root="L_SOLE", lock=LOCKS)),
    "hoap3_torso": ("hoap3.urdf", dict(subtree="CHEST", lock=LOCKS)),
    "hoap3_double_pendulum": ("double_pendulum.urdf", {}),
    "hoap3_floating": ("hoap3.urdf", dict(floating=True, lock=LOCKS)),
}
EXPECTED_DOF = {"hoap3_stance_right": 21, "hoap3_stance_left": 21, "hoap3_torso": 8, "hoap3_double_pendulum": 2,
                "hoap3_floating": 21}


def twins(name):
    gen = getattr(spatial, name)()
    file, opts = TWINS[name]
    run = spatial.load_urdf(spatial.urdf_path(file), **{k: (dict(v) if isinstance(v, dict) else v)
                                                         for k, v in opts.items()})
    return gen, run


@pytest.fixture(scope="module", params=sorted(TWINS))
def twin(request):
    return (request.param,) + twins(request.param)


# ---------------------------------------------------------------------------------------------------------------
# Generated == loaded


def test_twin_attributes(twin):
    name, gen, run = twin
    assert gen.compile_time is True, name
    assert run.compile_time is False, name
    n = EXPECTED_DOF[name]
    assert gen.njoints == run.njoints == n
    fl = name == "hoap3_floating"
    assert gen.floating is fl and run.floating is fl
    assert gen.nq == run.nq == n + (7 if fl else 0)
    assert gen.nv == run.nv == n + (6 if fl else 0)
    assert gen.joint_names == run.joint_names
    assert gen.body_names == run.body_names
    assert gen.frame_names == run.frame_names
    assert gen.root == run.root
    for attr in ("lower", "upper", "effort", "velocity", "gravity"):
        a, b = getattr(gen, attr), getattr(run, attr)
        assert isinstance(a, np.ndarray) and a.dtype == np.float64, (name, attr, type(a))
        assert a.shape == b.shape == ((3,) if attr == "gravity" else (n,)), (name, attr, a.shape, b.shape)
        assert np.array_equal(a, b), (name, attr, a, b)
    assert gen.total_mass == pytest.approx(run.total_mass, rel=1e-14)
    assert all(isinstance(s, str) for s in gen.joint_names + gen.body_names + gen.frame_names + list(gen.warnings))


def test_twin_algorithms(twin):
    """Every algorithm gives the same numbers on the compile-time model and its run-time twin (README: the numbers
    agree to 1e-14; here 1e-12)."""
    name, gen, run = twin
    s = states(run, 3, seed=11)
    checks = {
        "rnea": lambda m: spatial.rnea(m, s.Q, s.V, s.A),
        "gravity": lambda m: spatial.gravity(m, s.Q),
        "bias": lambda m: spatial.bias(m, s.Q, s.V),
        "crba": lambda m: spatial.crba(m, s.Q),
        "aba": lambda m: spatial.aba(m, s.Q, s.V, s.T),
        "forward_dynamics": lambda m: spatial.forward_dynamics(m, s.Q, s.V, s.T),
        "kinetic_energy": lambda m: spatial.kinetic_energy(m, s.Q, s.V),
        "potential_energy": lambda m: spatial.potential_energy(m, s.Q),
        "center_of_mass": lambda m: spatial.center_of_mass(m, s.Q),
        "com_jacobian": lambda m: spatial.com_jacobian(m, s.Q),
        "centroidal_momentum_matrix": lambda m: spatial.centroidal_momentum_matrix(m, s.Q),
        "centroidal_momentum": lambda m: spatial.centroidal_momentum(m, s.Q, s.V),
        "centroidal_momentum_time_variation": lambda m: spatial.centroidal_momentum_time_variation(m, s.Q, s.V, s.A),
        "integrate": lambda m: spatial.integrate(m, s.Q, s.V, 0.1),
        "difference": lambda m: spatial.difference(m, s.Q, s.Q[::-1]),
        "rnea_derivatives": lambda m: spatial.rnea_derivatives(m, s.Q, s.V, s.A),
        "aba_derivatives": lambda m: spatial.aba_derivatives(m, s.Q, s.V, s.T),
        "inverse_inertia": lambda m: spatial.inverse_inertia(m, s.Q),
        "neutral": lambda m: spatial.neutral(m),
    }
    for frame in gen.frame_names[:: max(1, len(gen.frame_names) // 4)] + gen.body_names[-1:]:
        checks[f"frame_placement {frame}"] = lambda m, f=frame: spatial.frame_placement(m, s.Q, f)
        for ref in REFERENCES:
            checks[f"frame_jacobian {frame} {ref}"] = (
                lambda m, f=frame, r=ref: spatial.frame_jacobian(m, s.Q, f, reference=r))
            checks[f"frame_velocity {frame} {ref}"] = (
                lambda m, f=frame, r=ref: spatial.frame_velocity(m, s.Q, s.V, f, reference=r))
            checks[f"frame_acceleration {frame} {ref}"] = (
                lambda m, f=frame, r=ref: spatial.frame_acceleration(m, s.Q, s.V, s.A, f, reference=r))
            checks[f"frame_classical_acceleration {frame} {ref}"] = (
                lambda m, f=frame, r=ref: spatial.frame_classical_acceleration(m, s.Q, s.V, s.A, f, reference=r))
            checks[f"frame_jacobian_time_variation {frame} {ref}"] = (
                lambda m, f=frame, r=ref: spatial.frame_jacobian_time_variation(m, s.Q, s.V, f, reference=r))
    for what, f in checks.items():
        a, b = f(gen), f(run)
        if isinstance(a, tuple):
            assert isinstance(b, tuple) and len(a) == len(b), what
            for k, (x, y) in enumerate(zip(a, b)):
                assert_close(x, y, 1e-12, err_msg=f"{name} {what}[{k}]")
        else:
            assert_close(a, b, 1e-12, err_msg=f"{name} {what}")


def test_twin_indices(twin):
    name, gen, run = twin
    for m in (gen, run):
        for i, j in enumerate(m.joint_names):
            assert m.joint_index(j) == i
        for i, b in enumerate(m.body_names):
            assert m.body_index(b) == i
        for i, f in enumerate(m.frame_names):
            assert m.frame_index(f) == i
    # frame given by index == by name
    s = states(run, 1, seed=3)
    k = len(gen.frame_names) - 1
    f = gen.frame_names[k]
    assert np.array_equal(spatial.frame_placement(gen, s.Q[0], k), spatial.frame_placement(gen, s.Q[0], f))
    assert np.array_equal(spatial.frame_jacobian(gen, s.Q[0], k, reference="local"),
                          spatial.frame_jacobian(gen, s.Q[0], f, reference="local"))


# ---------------------------------------------------------------------------------------------------------------
# What the models are


def test_stance_model_description(stance_gen, stance_urdf):
    for m in (stance_gen, stance_urdf):
        assert (m.nq, m.nv, m.njoints) == (21, 21, 21)
        assert m.floating is False
        assert m.root == "R_SOLE"
        assert np.array_equal(m.gravity, [0.0, 0.0, -9.81])
        # the stance leg first, from the sole up (spatial-dyn info, README)
        assert m.joint_names[0] == "R_AFE_R_AAA_joint"
        assert m.joint_names[5] == "WAIST_R_LR_joint"
        assert "L_SOLE" in m.frame_names and "R_SOLE" in m.frame_names
        assert not set(LOCKS) & set(m.joint_names)
        assert np.all(np.isfinite(m.lower)) and np.all(m.lower < m.upper)
        assert m.lower[m.joint_index("R_LFE_R_KN_joint")] == pytest.approx(0.0873)
        assert m.upper[m.joint_index("R_LFE_R_KN_joint")] == pytest.approx(2.2689)
        assert m.effort[m.joint_index("R_LFE_R_KN_joint")] == pytest.approx(4.5)
        # total_mass: the whole robot, base included (module.cpp's docstring; the moving bodies are 8.6484 kg)
        assert m.total_mass == pytest.approx(8.8024, abs=1e-9)


def test_floating_model_description(floating_gen, floating_urdf):
    for m in (floating_gen, floating_urdf):
        assert (m.nq, m.nv, m.njoints) == (28, 27, 21)
        assert m.floating is True
        assert m.root == "base_link"
        assert np.array_equal(m.gravity, [0.0, 0.0, -9.81])
        assert m.joint_names[0] == "WAIST_CHEST_joint"
        assert len(m.lower) == len(m.upper) == 21
        assert "base_link" in m.frame_names and "R_SOLE" in m.frame_names
        # total_mass: the whole robot, root body included (it flies with the rest)
        assert m.total_mass == pytest.approx(8.8024, abs=1e-9)
        q0 = spatial.neutral(m)
        # The whole robot flies: m = 8.8024 kg, seen in A_G's linear block at the identity pose (h_lin = m R v_lin).
        A = spatial.centroidal_momentum_matrix(m, q0)
        assert_close(A[:3, :3], 8.8024 * np.eye(3), 1e-12)


def test_double_pendulum_and_torso():
    dp = spatial.hoap3_double_pendulum()
    assert dp.joint_names == ["ankle_pitch", "hip_pitch"]
    assert dp.nq == 2 and not dp.floating
    assert np.all(np.isinf(dp.lower)) and np.all(np.isinf(dp.upper))  # continuous joints: no limits
    torso = spatial.hoap3_torso()
    assert torso.nq == 8 and torso.root == "CHEST"
    assert torso.total_mass == pytest.approx(5.456, abs=1e-9)  # chest, head and the two arms (README, footnote 1)
    assert dp.total_mass == pytest.approx(8.8024, abs=1e-9)


def test_neutral_and_random_configuration(any_model):
    key, m = any_model
    q0 = spatial.neutral(m)
    assert q0.shape == (m.nq,) and q0.dtype == np.float64
    expected = np.zeros(m.nq)
    if m.floating:
        expected[6] = 1.0
    assert np.array_equal(q0, expected)
    q1 = spatial.random_configuration(m, seed=1)
    q1b = spatial.random_configuration(m, seed=1)
    q2 = spatial.random_configuration(m, seed=2)
    assert q1.shape == (m.nq,) and q1.dtype == np.float64
    assert np.array_equal(q1, q1b), "same seed, different configurations"
    assert not np.array_equal(q1, q2), "different seeds, same configuration"
    joints = q1[7:] if m.floating else q1
    assert np.all(joints >= m.lower) and np.all(joints <= m.upper)
    assert np.ptp(joints) > 0.1  # not all at one value
    if m.floating:
        assert np.linalg.norm(q1[3:7]) == pytest.approx(1.0, abs=1e-14)
    # the default seed is None (fresh randomness, numpy's convention; API.md said seed=0): valid, and not stuck
    d1, d2 = spatial.random_configuration(m), spatial.random_configuration(m)
    assert d1.shape == (m.nq,) and not np.array_equal(d1, d2)
    # batch=B: B configurations, the first of which is not special
    Qb = spatial.random_configuration(m, seed=3, batch=4)
    assert Qb.shape == (4, m.nq) and Qb.dtype == np.float64 and Qb.flags.c_contiguous
    jb = Qb[:, 7:] if m.floating else Qb
    assert np.all(jb >= m.lower) and np.all(jb <= m.upper)
    assert not np.array_equal(Qb[0], Qb[1])
    if m.floating:
        assert_close(np.linalg.norm(Qb[:, 3:7], axis=1), np.ones(4), 1e-14)


def test_random_configuration_infinite_limits():
    dp = spatial.hoap3_double_pendulum()
    qs = np.array([spatial.random_configuration(dp, seed=s) for s in range(20)])
    assert np.all(np.abs(qs) <= np.pi)
    assert np.max(np.abs(qs)) > 1.0  # spread over [-pi, pi], not stuck near 0


def test_data_workspace(stance_gen, floating_urdf):
    for m in (stance_gen, floating_urdf):
        d = m.data()
        s = states(m, 2, seed=5)
        for k in range(2):
            assert np.array_equal(spatial.rnea(m, s.Q[k], s.V[k], s.A[k], data=d),
                                  spatial.rnea(m, s.Q[k], s.V[k], s.A[k]))
            assert np.array_equal(spatial.crba(m, s.Q[k], data=d), spatial.crba(m, s.Q[k]))
            assert np.array_equal(spatial.aba(m, s.Q[k], s.V[k], s.T[k], data=d),
                                  spatial.aba(m, s.Q[k], s.V[k], s.T[k]))
        # a batch with a private workspace
        assert np.array_equal(spatial.rnea(m, s.Q, s.V, s.A, data=d), spatial.rnea(m, s.Q, s.V, s.A))


# ---------------------------------------------------------------------------------------------------------------
# Loader options


def test_urdf_path():
    for name in ("hoap3.urdf", "double_pendulum.urdf"):
        p = spatial.urdf_path(name)
        assert isinstance(p, str) and os.path.isfile(p), p
        with open(p) as f:
            assert "<robot" in f.read()


def test_load_urdf_string_equals_file(stance_urdf):
    with open(hoap3_path()) as f:
        xml = f.read()
    m = spatial.load_urdf_string(xml, root="R_SOLE", lock=dict(LOCKS))
    assert m.joint_names == stance_urdf.joint_names and m.frame_names == stance_urdf.frame_names
    s = states(m, 2, seed=8)
    assert np.array_equal(spatial.rnea(m, s.Q, s.V, s.A), spatial.rnea(stance_urdf, s.Q, s.V, s.A))
    assert np.array_equal(spatial.crba(m, s.Q), spatial.crba(stance_urdf, s.Q))


def test_lock_changes_the_model():
    path = hoap3_path()
    full = spatial.load_urdf(path)
    assert full.njoints == 26  # head (3) and wrists (2) move
    locked = spatial.load_urdf(path, lock={"R_EB_R_WR_joint": 0.0})
    assert locked.njoints == 25 and "R_EB_R_WR_joint" not in locked.joint_names
    # locking a joint at another angle moves the mass it carries: the CoM changes
    bent = spatial.load_urdf(path, lock={**LOCKS, "CHEST_H_PAN_joint": 0.5, "H_PAN_H_TILT_joint": 0.4})
    straight = spatial.load_urdf(path, lock=dict(LOCKS))
    q = np.zeros(21)
    c0, c1 = spatial.center_of_mass(straight, q), spatial.center_of_mass(bent, q)
    assert np.linalg.norm(c0 - c1) > 1e-5


def test_gravity_option(stance_urdf):
    m = spatial.load_urdf(hoap3_path(), root="R_SOLE", lock=dict(LOCKS), gravity=[0.0, 0.0, -1.0])
    assert np.array_equal(m.gravity, [0.0, 0.0, -1.0])
    s = states(m, 2, seed=4)
    assert_close(spatial.gravity(m, s.Q) * 9.81, spatial.gravity(stance_urdf, s.Q), 1e-12)
    # no gravity: rnea = H a + C, gravity = 0
    z = spatial.load_urdf(hoap3_path(), root="R_SOLE", lock=dict(LOCKS), gravity=(0, 0, 0))
    assert np.array_equal(spatial.gravity(z, s.Q), np.zeros((2, 21)))


def test_axis_aligned_option_same_physics(stance_urdf):
    """axis_aligned=False keeps the body frames (RevoluteAxis joints): the same q gives the same dynamics."""
    m = spatial.load_urdf(hoap3_path(), root="R_SOLE", lock=dict(LOCKS), axis_aligned=False)
    assert m.joint_names == stance_urdf.joint_names
    s = states(m, 3, seed=6)
    assert_close(spatial.rnea(m, s.Q, s.V, s.A), spatial.rnea(stance_urdf, s.Q, s.V, s.A), 1e-11)
    assert_close(spatial.crba(m, s.Q), spatial.crba(stance_urdf, s.Q), 1e-11)
    assert_close(spatial.aba(m, s.Q, s.V, s.T), spatial.aba(stance_urdf, s.Q, s.V, s.T), 1e-10)
    for f in ("L_SOLE", "HEAD"):
        assert_close(spatial.frame_placement(m, s.Q, f), spatial.frame_placement(stance_urdf, s.Q, f), 1e-12)


def test_floating_urdf_equals_fixed_at_identity(floating_urdf, pelvis_urdf):
    """The floating model with the free-flyer at the identity and at rest has the pelvis-rooted fixed model's joint
    dynamics (README: to 1e-15): the lower-right blocks of H and tau."""
    s = states(pelvis_urdf, 2, seed=9)
    ff0 = np.tile([0, 0, 0, 0, 0, 0, 1.0], (2, 1))
    # the pelvis model's joints in the floating model's order
    perm = [pelvis_urdf.joint_index(j) for j in floating_urdf.joint_names]
    Qf = np.hstack([ff0, s.Q[:, perm]])
    Vf = np.hstack([np.zeros((2, 6)), s.V[:, perm]])
    Af = np.hstack([np.zeros((2, 6)), s.A[:, perm]])
    tau_fixed = spatial.rnea(pelvis_urdf, s.Q, s.V, s.A)[:, perm]
    # root at rest and not accelerating: the joints' torques are the fixed model's
    tau_float = spatial.rnea(floating_urdf, Qf, Vf, Af)
    assert_close(tau_float[:, 6:], tau_fixed, 1e-12)
    H_fixed = spatial.crba(pelvis_urdf, s.Q)[:, perm][:, :, perm]
    assert_close(spatial.crba(floating_urdf, Qf)[:, 6:, 6:], H_fixed, 1e-12)
    # the free-flyer's block of H is the composite inertia of the whole robot: m = 8.8024 kg
    Hf = spatial.crba(floating_urdf, Qf)
    assert_close(Hf[:, 0:3, 0:3], np.broadcast_to(8.8024 * np.eye(3), (2, 3, 3)), 1e-12)


# ---------------------------------------------------------------------------------------------------------------
# Against the command-line tool's description


def test_joint_order_matches_cli(dyn, any_model):
    """The CLI's output columns (model order) name the Python model's coordinates, in the same order."""
    key, m = any_model
    s = states(m, 1, seed=1)
    out = dyn.run(["id"], key, m, s.Q, s.V, s.A)
    names = [h[len("tau:"):] for h in out.header if h.startswith("tau:")]
    expected = ([f"floating_base:{c}" for c in ("vx", "vy", "vz", "wx", "wy", "wz")] if m.floating else []) + \
        list(m.joint_names)
    assert names == expected
