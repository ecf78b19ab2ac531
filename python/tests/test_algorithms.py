"""Algorithms: every binding against the C++ command-line tool spatial-dyn on random states (rel 1e-12: the same
library code runs), then identities that hold only if the numbers are right (inverse/forward dynamics round trips,
H from RNEA's slope, H^-1 H = I, analytical derivatives and Jacobians against central finite differences on the
configuration manifold, kinetic and potential energy, centroidal momentum, integrate/difference)."""

import numpy as np
import pytest

import spatial
from conftest import FF_V, MODEL_KEYS, REFERENCES, assert_close, com_mass, frames_of, get_model, states

CLI_KEYS = MODEL_KEYS + ["pelvis_urdf"]
NSTATES = 3


@pytest.fixture(params=CLI_KEYS)
def cli_model(request):
    return request.param, get_model(request.param)


# ---------------------------------------------------------------------------------------------------------------
# Against spatial-dyn


def test_rnea_gravity_bias_vs_cli(dyn, cli_model):
    key, m = cli_model
    s = states(m, NSTATES, seed=101)
    out = dyn.run(["id"], key, m, s.Q, s.V, s.A)
    assert_close(spatial.rnea(m, s.Q, s.V, s.A), out("tau"), err_msg=f"{key} rnea")
    Z = np.zeros_like(s.V)
    out = dyn.run(["id"], key, m, s.Q, Z, Z)
    assert_close(spatial.gravity(m, s.Q), out("tau"), err_msg=f"{key} gravity")
    out = dyn.run(["id"], key, m, s.Q, s.V, Z)
    assert_close(spatial.bias(m, s.Q, s.V), out("tau"), err_msg=f"{key} bias")


def test_aba_and_forward_dynamics_vs_cli(dyn, cli_model):
    key, m = cli_model
    s = states(m, NSTATES, seed=102)
    out = dyn.run(["fd"], key, m, s.Q, s.V, s.T, xkind="tau")
    assert_close(spatial.aba(m, s.Q, s.V, s.T), out("qdd"), err_msg=f"{key} aba")
    out = dyn.run(["fd"], key, m, s.Q, s.V, s.T, xkind="tau", extra=["--method", "crba"])
    assert_close(spatial.forward_dynamics(m, s.Q, s.V, s.T), out("qdd"), err_msg=f"{key} forward_dynamics")


def test_crba_vs_cli(dyn, cli_model):
    key, m = cli_model
    s = states(m, NSTATES, seed=103)
    out = dyn.run(["crba"], key, m, s.Q)
    assert_close(spatial.crba(m, s.Q), out("H", rows="tangent"), err_msg=f"{key} crba")


@pytest.mark.parametrize("reference", REFERENCES)
def test_frame_jacobian_vs_cli(dyn, cli_model, reference):
    key, m = cli_model
    s = states(m, NSTATES, seed=104)
    for frame in frames_of(key):
        out = dyn.run(["jacobian"], key, m, s.Q, extra=["--frame", frame, "--reference", reference])
        assert_close(spatial.frame_jacobian(m, s.Q, frame, reference=reference), out("J", rows=FF_V),
                     err_msg=f"{key} frame_jacobian {frame} {reference}")


def test_com_vs_cli(dyn, cli_model):
    key, m = cli_model
    s = states(m, NSTATES, seed=105)
    out = dyn.run(["com"], key, m, s.Q)
    com = out.data[:, [out.index[f"com:{c}"] for c in "xyz"]]
    assert_close(spatial.center_of_mass(m, s.Q), com, err_msg=f"{key} center_of_mass")
    assert_close(spatial.com_jacobian(m, s.Q), out("Jcom", rows=list("xyz")), err_msg=f"{key} com_jacobian")


def test_derivatives_vs_cli(dyn, cli_model):
    key, m = cli_model
    s = states(m, 2, seed=106)
    out = dyn.run(["derivatives", "id"], key, m, s.Q, s.V, s.A)
    dq, dv = spatial.rnea_derivatives(m, s.Q, s.V, s.A)
    assert_close(dq, out("dtau_dq", rows="tangent"), err_msg=f"{key} dtau_dq")
    assert_close(dv, out("dtau_dv", rows="tangent"), err_msg=f"{key} dtau_dv")
    out = dyn.run(["derivatives", "fd"], key, m, s.Q, s.V, s.T, xkind="tau")
    dq, dv, dtau = spatial.aba_derivatives(m, s.Q, s.V, s.T)
    assert_close(dq, out("dqdd_dq", rows="tangent"), err_msg=f"{key} dqdd_dq")
    assert_close(dv, out("dqdd_dv", rows="tangent"), err_msg=f"{key} dqdd_dv")
    assert_close(dtau, out("dqdd_dtau", rows="tangent"), err_msg=f"{key} dqdd_dtau")
    assert_close(spatial.inverse_inertia(m, s.Q), out("dqdd_dtau", rows="tangent"), err_msg=f"{key} inverse_inertia")


# ---------------------------------------------------------------------------------------------------------------
# Identities


def scale(x):
    return max(1.0, float(np.max(np.abs(x))))


def test_rnea_aba_round_trip(any_model):
    key, m = any_model
    s = states(m, NSTATES, seed=201)
    qdd = spatial.aba(m, s.Q, s.V, s.T)
    tau = spatial.rnea(m, s.Q, s.V, qdd)
    H = spatial.crba(m, s.Q)
    # backward stable: residual ~ u (|H| |qdd| + |C| + |tau|)
    for k in range(NSTATES):
        size = np.abs(H[k]).max() * np.abs(qdd[k]).max() + np.abs(tau[k]).max() + 1.0
        np.testing.assert_allclose(tau[k], s.T[k], rtol=0, atol=1e-12 * size, err_msg=f"{key} rnea(aba(tau))")
    # and the other way round: aba(rnea(a)) = a (conditioned by H)
    a = spatial.aba(m, s.Q, s.V, spatial.rnea(m, s.Q, s.V, s.A))
    np.testing.assert_allclose(a, s.A, rtol=0, atol=1e-8, err_msg=f"{key} aba(rnea(a))")
    # not a tautology: another torque gives another acceleration
    assert not np.allclose(spatial.aba(m, s.Q, s.V, s.T + 0.1), qdd)


def test_crba_symmetric_positive_definite(any_model):
    key, m = any_model
    s = states(m, NSTATES, seed=202)
    H = spatial.crba(m, s.Q)
    assert H.shape == (NSTATES, m.nv, m.nv)
    assert np.array_equal(H, np.swapaxes(H, 1, 2)), f"{key}: crba not exactly symmetric"
    for k in range(NSTATES):
        assert np.linalg.eigvalsh(H[k]).min() > 0
    # H depends on q
    assert not np.allclose(H[0], H[1])


def test_rnea_linear_in_a_with_slope_crba(any_model):
    key, m = any_model
    s = states(m, NSTATES, seed=203)
    H = spatial.crba(m, s.Q)
    tau_a = spatial.rnea(m, s.Q, s.V, s.A)
    tau_0 = spatial.rnea(m, s.Q, s.V, np.zeros_like(s.A))
    Ha = np.einsum("bij,bj->bi", H, s.A)
    assert_close(tau_a - tau_0, Ha, 1e-11, atol_scale=scale(tau_a) + scale(Ha), err_msg=key)
    # columns of H one at a time, without velocity
    Z = np.zeros(m.nv)
    g = spatial.gravity(m, s.Q[0])
    for j in (0, m.nv // 2, m.nv - 1):
        e = np.zeros(m.nv)
        e[j] = 1.0
        assert_close(spatial.rnea(m, s.Q[0], Z, e) - g, H[0][:, j], 1e-11, atol_scale=scale(g), err_msg=key)
    # gravity = rnea(q, 0, 0), bias = rnea(q, v, 0)
    assert_close(spatial.gravity(m, s.Q), spatial.rnea(m, s.Q, np.zeros_like(s.V), np.zeros_like(s.A)), 1e-13)
    assert_close(spatial.bias(m, s.Q, s.V), tau_0, 1e-13)


def test_forward_dynamics_equals_aba(any_model):
    key, m = any_model
    s = states(m, NSTATES, seed=204)
    a1 = spatial.aba(m, s.Q, s.V, s.T)
    a2 = spatial.forward_dynamics(m, s.Q, s.V, s.T)
    assert_close(a2, a1, 1e-10, err_msg=key)


def test_inverse_inertia(any_model):
    key, m = any_model
    s = states(m, NSTATES, seed=205)
    Minv = spatial.inverse_inertia(m, s.Q)
    H = spatial.crba(m, s.Q)
    I = np.broadcast_to(np.eye(m.nv), H.shape)
    np.testing.assert_allclose(Minv @ H, I, rtol=0, atol=1e-9, err_msg=key)
    np.testing.assert_allclose(H @ Minv, I, rtol=0, atol=1e-9, err_msg=key)
    assert np.array_equal(Minv, np.swapaxes(Minv, 1, 2)), f"{key}: inverse_inertia not exactly symmetric"


def test_kinetic_energy(any_model):
    key, m = any_model
    s = states(m, NSTATES, seed=206)
    H = spatial.crba(m, s.Q)
    T = spatial.kinetic_energy(m, s.Q, s.V)
    assert T.shape == (NSTATES,)
    assert_close(T, 0.5 * np.einsum("bi,bij,bj->b", s.V, H, s.V), 1e-12, err_msg=key)
    t0 = spatial.kinetic_energy(m, s.Q[0], s.V[0])
    assert isinstance(t0, float)
    assert t0 == T[0]


# --- finite differences on the configuration manifold


def fd_tangent(m, f, q, eps=1e-6):
    """Central differences of f along the nv tangent directions at q (q ⊕ ±eps e_j through integrate): returns
    an array (..., nv), the last axis the direction."""
    Qs = np.tile(q, (m.nv, 1))
    E = eps * np.eye(m.nv)
    fp = np.asarray(f(spatial.integrate(m, Qs, E)))
    fm = np.asarray(f(spatial.integrate(m, Qs, -E)))
    return np.moveaxis((fp - fm) / (2 * eps), 0, -1)


def fd_vector(f, x, eps=1e-6):
    """Central differences of f (batched over rows) along the coordinates of the vector x."""
    n = x.shape[0]
    X = np.tile(x, (n, 1))
    E = eps * np.eye(n)
    return np.moveaxis((np.asarray(f(X + E)) - np.asarray(f(X - E))) / (2 * eps), 0, -1)


def test_rnea_derivatives_fd(any_model):
    key, m = any_model
    s = states(m, 2, seed=207)
    for k in range(2):
        q, v, a = s.Q[k], s.V[k], s.A[k]
        dq, dv = spatial.rnea_derivatives(m, q, v, a)
        assert dq.shape == dv.shape == (m.nv, m.nv)
        n = lambda Q: spatial.rnea(m, Q, np.tile(v, (len(Q), 1)), np.tile(a, (len(Q), 1)))
        fdq = fd_tangent(m, n, q)
        fdv = fd_vector(lambda V: spatial.rnea(m, np.tile(q, (len(V), 1)), V, np.tile(a, (len(V), 1))), v)
        assert_close(dq, fdq, 1e-6, atol_scale=scale(fdq), err_msg=f"{key} dtau_dq")
        assert_close(dv, fdv, 1e-6, atol_scale=scale(fdv), err_msg=f"{key} dtau_dv")


def test_aba_derivatives_fd(any_model):
    key, m = any_model
    s = states(m, 1, seed=208)
    q, v, t = s.Q[0], s.V[0], s.T[0]
    dq, dv, dtau = spatial.aba_derivatives(m, q, v, t)
    tile = lambda x, n: np.tile(x, (n, 1))
    fdq = fd_tangent(m, lambda Q: spatial.aba(m, Q, tile(v, len(Q)), tile(t, len(Q))), q)
    fdv = fd_vector(lambda V: spatial.aba(m, tile(q, len(V)), V, tile(t, len(V))), v)
    fdt = fd_vector(lambda T: spatial.aba(m, tile(q, len(T)), tile(v, len(T)), T), t)
    assert_close(dq, fdq, 1e-5, atol_scale=scale(fdq), err_msg=f"{key} dqdd_dq")
    assert_close(dv, fdv, 1e-5, atol_scale=scale(fdv), err_msg=f"{key} dqdd_dv")
    assert_close(dtau, fdt, 1e-5, atol_scale=scale(fdt), err_msg=f"{key} dqdd_dtau")
    assert_close(dtau, spatial.inverse_inertia(m, q), 1e-12, err_msg=f"{key} dqdd_dtau = H^-1")


def skew(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def jacobians_from_placements(T, dT):
    """The three Jacobians of a frame from its placement T (4, 4) and the derivative dT (4, 4, nv)."""
    R, p = T[:3, :3], T[:3, 3]
    dp = dT[:3, 3, :]
    W = np.einsum("ijk,lj->ilk", dT[:3, :3, :], R)  # dR R^T per column: skew(omega)
    w = np.stack([0.5 * (W[2, 1] - W[1, 2]), 0.5 * (W[0, 2] - W[2, 0]), 0.5 * (W[1, 0] - W[0, 1])])
    lwa = np.vstack([dp, w])
    world = np.vstack([dp - np.cross(w.T, p).T, w])
    local = np.vstack([R.T @ dp, R.T @ w])
    return {"local_world_aligned": lwa, "world": world, "local": local}


def test_frame_jacobian_fd(any_model):
    key, m = any_model
    s = states(m, 2, seed=209)
    frames = frames_of(key) + [m.body_names[-1]]
    for k in range(2):
        q = s.Q[k]
        for frame in frames:
            T = spatial.frame_placement(m, q, frame)
            assert T.shape == (4, 4)
            assert np.array_equal(T[3], [0, 0, 0, 1])
            assert_close(T[:3, :3] @ T[:3, :3].T, np.eye(3), 1e-14)
            dT = fd_tangent(m, lambda Q: spatial.frame_placement(m, Q, frame), q)
            expected = jacobians_from_placements(T, dT)
            for ref in REFERENCES:
                J = spatial.frame_jacobian(m, q, frame, reference=ref)
                assert J.shape == (6, m.nv)
                assert_close(J, expected[ref], 1e-7, atol_scale=scale(expected[ref]),
                             err_msg=f"{key} {frame} {ref}")
                # frame_velocity = J v
                assert_close(spatial.frame_velocity(m, q, s.V[k], frame, reference=ref), J @ s.V[k], 1e-12,
                             err_msg=f"{key} frame_velocity {frame} {ref}")
    # default reference: local_world_aligned
    assert np.array_equal(spatial.frame_jacobian(m, s.Q[0], frames[0]),
                          spatial.frame_jacobian(m, s.Q[0], frames[0], reference="local_world_aligned"))


def along(m, q, v, a, t):
    """The state at time t of the motion through (q, v) with acceleration a: q(t) = q (+) (v t + a t^2 / 2) through
    integrate (on a free-flyer its body velocity is v + a t + O(t^2) with an even O(t^2), which central differences
    cancel), v(t) = v + a t."""
    return spatial.integrate(m, q, v * t + 0.5 * a * t * t), v + a * t


def time_derivative(m, f, q, v, a, h=1e-5):
    """d/dt f(q(t), v(t)) at t = 0 by central differences along `along`."""
    return (f(*along(m, q, v, a, h)) - f(*along(m, q, v, a, -h))) / (2 * h)


def test_frame_accelerations_fd(any_model):
    """frame_acceleration is the time derivative of frame_velocity (local, world; local_world_aligned is the local
    vector in world axes), frame_classical_acceleration that of the origin's velocity (the linear part of the
    local_world_aligned velocity), frame_jacobian_time_variation that of frame_jacobian; J_dot v is the drift
    (a = 0) as kinematics.hpp states it."""
    key, m = any_model
    s = states(m, 2, seed=215)
    frames = frames_of(key) + [m.body_names[-1]]
    for k in range(2):
        q, v, a = s.Q[k], s.V[k], s.A[k]
        zero = np.zeros(m.nv)
        for frame in frames:
            what = f"{key} {frame}"
            R = spatial.frame_placement(m, q, frame)[:3, :3]
            acc = {}
            for ref in ("local", "world"):
                acc[ref] = spatial.frame_acceleration(m, q, v, a, frame, reference=ref)
                assert acc[ref].shape == (6,)
                fd = time_derivative(m, lambda Q, V: spatial.frame_velocity(m, Q, V, frame, reference=ref), q, v, a)
                assert_close(acc[ref], fd, 1e-7, err_msg=f"{what} frame_acceleration {ref}")
            lwa = spatial.frame_acceleration(m, q, v, a, frame, reference="local_world_aligned")
            assert_close(lwa, np.concatenate([R @ acc["local"][:3], R @ acc["local"][3:]]), 1e-12,
                         err_msg=f"{what} frame_acceleration local_world_aligned")
            # the classical acceleration of the origin: d/dt of its velocity in world axes, or in the frame's axes
            pdd = spatial.frame_classical_acceleration(m, q, v, a, frame, reference="world")
            assert pdd.shape == (3,)
            fd = time_derivative(
                m, lambda Q, V: spatial.frame_velocity(m, Q, V, frame, reference="local_world_aligned")[:3], q, v, a)
            assert_close(pdd, fd, 1e-7, err_msg=f"{what} frame_classical_acceleration")
            assert_close(spatial.frame_classical_acceleration(m, q, v, a, frame, reference="local_world_aligned"),
                         pdd, 1e-15, err_msg=f"{what} classical lwa = world")
            assert_close(spatial.frame_classical_acceleration(m, q, v, a, frame, reference="local"), R.T @ pdd,
                         1e-12, err_msg=f"{what} classical local")
            vl = spatial.frame_velocity(m, q, v, frame, reference="local")
            assert_close(pdd, R @ (acc["local"][:3] + np.cross(vl[3:], vl[:3])), 1e-12,
                         err_msg=f"{what} p_ddot = a_lin + w x v_lin")
            for ref in REFERENCES:
                dJ = spatial.frame_jacobian_time_variation(m, q, v, frame, reference=ref)
                assert dJ.shape == (6, m.nv)
                fd = time_derivative(m, lambda Q, V: spatial.frame_jacobian(m, Q, frame, reference=ref), q, v, zero)
                assert_close(dJ, fd, 1e-7, atol_scale=scale(fd), err_msg=f"{what} frame_jacobian_time_variation {ref}")
                # acceleration = J a + J_dot v
                J = spatial.frame_jacobian(m, q, frame, reference=ref)
                if ref == "local_world_aligned":
                    drift = np.concatenate([spatial.frame_classical_acceleration(m, q, v, zero, frame, reference=ref),
                                            spatial.frame_acceleration(m, q, v, zero, frame, reference=ref)[3:]])
                    full = np.concatenate([pdd, lwa[3:]])
                else:
                    drift = spatial.frame_acceleration(m, q, v, zero, frame, reference=ref)
                    full = acc[ref]
                assert_close(dJ @ v, drift, 1e-12, atol_scale=scale(drift), err_msg=f"{what} J_dot v {ref}")
                assert_close(J @ a + dJ @ v, full, 1e-11, atol_scale=scale(full), err_msg=f"{what} J a + J_dot v {ref}")


def test_centroidal_momentum_time_variation_fd(any_model):
    """dh_G = d/dt h_G(q(t), v(t)); its drift is dh_G at a = 0 and dh_G is linear in a with slope A_G; the linear rows
    are M times the CoM's acceleration."""
    key, m = any_model
    s = states(m, 2, seed=216)
    for k in range(2):
        q, v, a = s.Q[k], s.V[k], s.A[k]
        dh, drift = spatial.centroidal_momentum_time_variation(m, q, v, a)
        assert dh.shape == (6,) and drift.shape == (6,)
        fd = time_derivative(m, lambda Q, V: spatial.centroidal_momentum(m, Q, V), q, v, a)
        assert_close(dh, fd, 1e-7, err_msg=f"{key} dh_G")
        dh0, drift0 = spatial.centroidal_momentum_time_variation(m, q, v, np.zeros(m.nv))
        assert_close(dh0, drift, 1e-12, err_msg=f"{key} drift = dh_G(a = 0)")
        assert_close(drift0, drift, 1e-15, err_msg=f"{key} drift independent of a")
        assert_close(dh, drift + spatial.centroidal_momentum_matrix(m, q) @ a, 1e-11, err_msg=f"{key} A_G a + drift")
        cdd = time_derivative(m, lambda Q, V: spatial.com_jacobian(m, Q) @ V, q, v, a)
        assert_close(dh[:3], com_mass(key) * cdd, 1e-7, err_msg=f"{key} M c_ddot")


def test_frame_on_base(stance_gen, floating_gen):
    """A frame on the fixed base does not move (zero Jacobian); the floating root's frame moves with the
    free-flyer only: its local Jacobian is [I 0]."""
    q = states(stance_gen, 1, seed=3).Q[0]
    assert np.array_equal(spatial.frame_jacobian(stance_gen, q, "R_SOLE"), np.zeros((6, 21)))
    assert_close(spatial.frame_placement(stance_gen, q, "R_SOLE"), np.eye(4), 1e-15)
    qf = states(floating_gen, 1, seed=3).Q[0]
    J = spatial.frame_jacobian(floating_gen, qf, "base_link", reference="local")
    expected = np.zeros((6, 27))
    expected[:, :6] = np.eye(6)
    assert_close(J, expected, 1e-14)
    T = spatial.frame_placement(floating_gen, qf, "base_link")
    assert_close(T[:3, 3], qf[:3], 1e-15)


def quat_to_matrix(qx, qy, qz, qw):
    return np.array([
        [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
        [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
        [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)],
    ])


def test_com_jacobian_fd(any_model):
    key, m = any_model
    s = states(m, 2, seed=210)
    for k in range(2):
        q = s.Q[k]
        Jc = spatial.com_jacobian(m, q)
        assert Jc.shape == (3, m.nv)
        fd = fd_tangent(m, lambda Q: spatial.center_of_mass(m, Q), q)
        assert_close(Jc, fd, 1e-7, err_msg=key)


def test_gravity_is_weight_through_com_jacobian(any_model):
    """G(q) = -M J_c^T g: the gravity torques are the weight of the bodies center_of_mass counts (a fixed base's
    moving bodies, a floating robot's every body) pulled through the CoM Jacobian."""
    key, m = any_model
    s = states(m, NSTATES, seed=211)
    G = spatial.gravity(m, s.Q)
    Jc = spatial.com_jacobian(m, s.Q)
    assert_close(G, -com_mass(key) * np.einsum("bij,i->bj", Jc, m.gravity), 1e-11, err_msg=key)
    if m.floating:
        assert m.total_mass == pytest.approx(com_mass(key), rel=1e-14)


def test_potential_energy_gradient_is_gravity(any_model):
    key, m = any_model
    s = states(m, 2, seed=212)
    for k in range(2):
        U = spatial.potential_energy(m, s.Q[k])
        assert isinstance(U, float)
        dU = fd_tangent(m, lambda Q: spatial.potential_energy(m, Q), s.Q[k])
        assert_close(dU, spatial.gravity(m, s.Q[k]), 1e-7, err_msg=key)
    # U = -M g.c (+ a constant): compare differences between two states
    U = spatial.potential_energy(m, s.Q)
    c = spatial.center_of_mass(m, s.Q)
    assert_close(U[1] - U[0], -com_mass(key) * m.gravity @ (c[1] - c[0]), 1e-11, err_msg=key)


def test_centroidal(any_model):
    key, m = any_model
    s = states(m, NSTATES, seed=213)
    A = spatial.centroidal_momentum_matrix(m, s.Q)
    assert A.shape == (NSTATES, 6, m.nv)
    h = spatial.centroidal_momentum(m, s.Q, s.V)
    assert h.shape == (NSTATES, 6)
    assert_close(h, np.einsum("bij,bj->bi", A, s.V), 1e-12, err_msg=key)
    # linear rows first: the linear momentum M c_dot = M J_c v
    assert_close(A[:, :3, :], com_mass(key) * spatial.com_jacobian(m, s.Q), 1e-12, err_msg=key)


def test_centroidal_angular_momentum_from_bodies(floating_gen):
    """k_G of a floating robot moving as a rigid body (joints still, root twist only) is I_G(q) w in world axes,
    where the root's 6x6 block of H gives the whole robot's spatial inertia."""
    m = floating_gen
    s = states(m, 2, seed=214)
    for k in range(2):
        q = s.Q[k]
        v = np.zeros(m.nv)
        v[:6] = s.V[k, :6]
        h = spatial.centroidal_momentum(m, q, v)
        # world-frame momentum about the world origin from the composite inertia in root coordinates
        H = spatial.crba(m, q)
        R = quat_to_matrix(*q[3:7])
        p_root = q[:3]
        root_momentum = H[:6, :6] @ v[:6]  # [linear; angular about the root origin], root coordinates
        lin_w = R @ root_momentum[:3]
        ang_root_w = R @ root_momentum[3:]
        c = spatial.center_of_mass(m, q)
        # move the moment from the root origin to the CoM: k_G = k_O + (p_root - c) x l
        k_G = ang_root_w + np.cross(p_root - c, lin_w)
        assert_close(h[:3], lin_w, 1e-12)
        assert_close(h[3:], k_G, 1e-11)


def test_integrate_difference_round_trip(any_model):
    key, m = any_model
    s = states(m, NSTATES, seed=215)
    dt = 0.3
    Q1 = spatial.integrate(m, s.Q, s.V, dt)
    assert Q1.shape == s.Q.shape
    assert_close(spatial.difference(m, s.Q, Q1), s.V * dt, 1e-12, err_msg=f"{key} difference(q, q + v dt)")
    assert_close(spatial.integrate(m, s.Q, s.V * dt), Q1, 1e-14, err_msg=f"{key} dt")
    # default dt = 1
    assert np.array_equal(spatial.integrate(m, s.Q, s.V), spatial.integrate(m, s.Q, s.V, 1.0))
    # q1 = q0 + difference(q0, q1)
    Q2 = states(m, NSTATES, seed=216).Q
    D = spatial.difference(m, s.Q, Q2)
    assert D.shape == (NSTATES, m.nv)
    back = spatial.integrate(m, s.Q, D)
    if m.floating:
        # the same rotation: the quaternion up to its sign
        sign = np.sign(np.sum(back[:, 3:7] * Q2[:, 3:7], axis=1))[:, None]
        back[:, 3:7] *= sign
        assert_close(np.linalg.norm(Q1[:, 3:7], axis=1), np.ones(NSTATES), 1e-14)
    assert_close(back, Q2, 1e-12, err_msg=f"{key} integrate(q0, difference(q0, q1))")
    np.testing.assert_allclose(spatial.difference(m, s.Q, s.Q), np.zeros((NSTATES, m.nv)), rtol=0, atol=1e-15)
    if not m.floating:
        assert_close(Q1, s.Q + dt * s.V, 1e-15)
        assert_close(D, Q2 - s.Q, 1e-15)


def test_integrate_free_flyer_convention(floating_gen):
    """v[0:3] is the root's linear velocity and v[3:6] its angular velocity, both in root (body) coordinates."""
    m = floating_gen
    q = states(m, 1, seed=217).Q[0]
    R = quat_to_matrix(*q[3:7])
    v = np.zeros(m.nv)
    v[:3] = [0.1, -0.2, 0.3]
    q1 = spatial.integrate(m, q, v)
    assert_close(q1[:3], q[:3] + R @ v[:3], 1e-14)
    assert_close(q1[3:], q[3:], 1e-15)
    v = np.zeros(m.nv)
    v[3:6] = [0.0, 0.0, 0.2]  # about the root's own z: R1 = R Rz(0.2), the origin stays
    q1 = spatial.integrate(m, q, v)
    c, s_ = np.cos(0.2), np.sin(0.2)
    Rz = np.array([[c, -s_, 0], [s_, c, 0], [0, 0, 1]])
    assert_close(q1[:3], q[:3], 1e-15)
    assert_close(quat_to_matrix(*q1[3:7]), R @ Rz, 1e-14)
    # joint rates move the joints only
    v = np.zeros(m.nv)
    v[6:] = 0.01
    q1 = spatial.integrate(m, q, v)
    assert_close(q1[7:], q[7:] + 0.01, 1e-15)
    assert np.array_equal(q1[:7], q[:7])


def test_normalize(any_model):
    key, m = any_model
    s = states(m, 2, seed=218)
    Q = s.Q.copy()
    if m.floating:
        Q[:, 3:7] *= np.array([[2.5], [0.3]])
    N = spatial.normalize(m, Q)
    assert_close(N, s.Q, 1e-15, err_msg=key)
    assert not np.shares_memory(N, Q)
    if m.floating:
        assert not np.allclose(Q, s.Q)  # the input is left alone


def test_external_forces(any_model):
    """fext[i] (body coordinates, [f; n]) acting on body i: tau = rnea - J_i^T fext[i] with J_i the body's local
    Jacobian (floating: row 0 is the root, rows 1.. the bodies); aba with the same forces inverts it."""
    key, m = any_model
    s = states(m, 2, seed=219)
    nb = m.njoints + (1 if m.floating else 0)
    rng = np.random.default_rng(5)
    F = rng.normal(size=(2, nb, 6))
    tau0 = spatial.rnea(m, s.Q, s.V, s.A)
    tau = spatial.rnea(m, s.Q, s.V, s.A, fext=F)
    assert tau.shape == (2, m.nv)
    for k in range(2):
        expected = tau0[k].copy()
        for i in range(nb):
            if m.floating and i == 0:
                J = np.zeros((6, m.nv))
                J[:, :6] = np.eye(6)
            else:
                J = spatial.frame_jacobian(m, s.Q[k], m.body_names[i - (1 if m.floating else 0)], reference="local")
            expected -= J.T @ F[k, i]
        assert_close(tau[k], expected, 1e-11, err_msg=f"{key} rnea fext state {k}")
        # single-state call with a (nb, 6) fext
        assert np.array_equal(spatial.rnea(m, s.Q[k], s.V[k], s.A[k], fext=F[k]), tau[k])
    qdd = spatial.aba(m, s.Q, s.V, s.T, fext=F)
    assert_close(spatial.rnea(m, s.Q, s.V, qdd, fext=F), s.T, 1e-9, err_msg=f"{key} rnea(aba(tau, fext), fext)")
    assert not np.allclose(qdd, spatial.aba(m, s.Q, s.V, s.T))
    # zero forces = no forces (to rounding: the compile-time models' kernel without forces is another code path)
    assert_close(spatial.rnea(m, s.Q, s.V, s.A, fext=np.zeros((2, nb, 6))), tau0, 1e-14, err_msg=key)
