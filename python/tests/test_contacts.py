"""Contact dynamics from Python (contact.hpp, zmp.hpp through bind_contacts.cpp): Contact6D / Contact3D, Contacts,
constrained_forward_dynamics, impulse_dynamics, contact_inverse_dynamics, contact_jacobian, contact_wrench,
center_of_pressure, multibody_zmp.

Checked against independent parts of the module (rnea, crba, frame_jacobian, frame_velocity, frame_placement,
kinetic_energy, integrate): the equations of motion RNEA(q, v, a) = tau + J^T lambda with J built from frame_jacobian
in each contact's rows; the contact frames' accelerations (zero, or the Baumgarte terms) by central differences of
frame_velocity along the motion; impacts J v+ = -e J v-, H (v+ - v-) = J^T impulses and no energy gain; whole-body
inverse dynamics on both soles of the standing HOAP-3 and its round trip through constrained forward dynamics; the
multibody ZMP against RNEA's root wrench and against the CoP of the contact forces; batches against single calls and
threads against one thread (bit for bit); errors; optionally Pinocchio's constraintDynamics."""

import threading

import numpy as np
import pytest

import spatial
from conftest import get_model, states

# The contact API is registered in spatial._spatial; spatial/__init__.py re-exports it.
sp = spatial

SOLE = (-0.054, 0.054, -0.0365, 0.0365)  # the HOAP-3's sole rectangle about the sole frame (README)
FLOATING = ["floating_gen", "floating_urdf"]
G = 9.81


def contact_list(kind):
    if kind == "left":
        return [sp.Contact6D("L_SOLE", sole=SOLE)]
    if kind == "both":
        return [sp.Contact6D("L_SOLE", sole=SOLE), sp.Contact6D("R_SOLE", sole=SOLE)]
    if kind == "mixed":  # every row kind in both reference axes
        return [sp.Contact6D("L_SOLE", reference="local_world_aligned", sole=SOLE), sp.Contact3D("R_SOLE"),
                sp.Contact3D("R_HAND", reference="local")]
    if kind == "point":
        return [sp.Contact3D("L_SOLE")]
    raise KeyError(kind)


# (model fixture, contact kind): floating models with one and two soles and mixed contacts; the fixed-base stance
# model (rooted at the right sole) with its left sole held.
CASES = [(k, c) for k in FLOATING for c in ["left", "both", "mixed"]] + [("stance_gen", "left"),
                                                                         ("stance_urdf", "point")]
_SETS = {}


def contacts_for(key, kind):
    if (key, kind) not in _SETS:
        _SETS[key, kind] = sp.Contacts(get_model(key), contact_list(kind))
    return _SETS[key, kind]


def rows_and_lambda(model, contacts, q, lam):
    """The stacked constraint rows J (m, nv), built from frame_jacobian (6D: the Local rows; 3D: the linear
    LocalWorldAligned rows), and lam turned from each contact's reference axes into its rows' axes."""
    Js, ls = [], []
    for desc, name, size, off in zip(contacts.contacts, contacts.names, contacts.sizes, contacts.offsets):
        R = spatial.frame_placement(model, q, name)[:3, :3]
        lk = np.asarray(lam[off:off + size], dtype=float)
        if size == 6:
            Js.append(spatial.frame_jacobian(model, q, name, "local"))
            if desc.reference == "local_world_aligned":
                lk = np.concatenate([R.T @ lk[:3], R.T @ lk[3:]])
        else:
            Js.append(spatial.frame_jacobian(model, q, name, "local_world_aligned")[:3])
            if desc.reference == "local":
                lk = R @ lk
        ls.append(lk)
    return np.vstack(Js), np.concatenate(ls)


def frame_velocities(model, contacts, q, v):
    """Each contact's constrained velocity: 6D the frame's spatial velocity (Local), 3D its origin's (world)."""
    out = []
    for name, size in zip(contacts.names, contacts.sizes):
        if size == 6:
            out.append(spatial.frame_velocity(model, q, v, name, "local"))
        else:
            out.append(spatial.frame_velocity(model, q, v, name, "local_world_aligned")[:3])
    return np.concatenate(out)


def rate_along(model, contacts, q, v, a, h=1e-5):
    """d/dt of frame_velocities along the motion q(t) = q (+) (v t + a t^2 / 2), v(t) = v + a t (central
    differences; the body velocity of that curve differs from v + a t by an even O(t^2) term, which cancels)."""
    qp = spatial.integrate(model, q, h * v + 0.5 * h * h * a)
    qm = spatial.integrate(model, q, -h * v + 0.5 * h * h * a)
    return (frame_velocities(model, contacts, qp, v + h * a) - frame_velocities(model, contacts, qm, v - h * a)) / (2 * h)


def standing(model, bend=0.3):
    """The HOAP-3 standing: hips -bend, knees 2 bend, ankles -bend (the soles stay parallel to the pelvis), the
    pelvis at the height that puts both soles on the ground z = 0."""
    q = spatial.neutral(model)
    off = model.nq - model.njoints
    for s in "RL":
        q[off + model.joint_index(f"{s}_LAA_{s}_LFE_joint")] = -bend
        q[off + model.joint_index(f"{s}_LFE_{s}_KN_joint")] = 2 * bend
        q[off + model.joint_index(f"{s}_KN_{s}_AFE_joint")] = -bend
    q[2] -= spatial.frame_placement(model, q, "L_SOLE")[2, 3]
    for s in ("L_SOLE", "R_SOLE"):
        X = spatial.frame_placement(model, q, s)
        assert abs(X[2, 3]) < 1e-12 and np.allclose(X[:3, :3], np.eye(3), atol=1e-12), (s, X)
    return q


def null_space(J):
    _, s, Vt = np.linalg.svd(J)
    r = int(np.sum(s > 1e-10 * s[0]))
    return Vt[r:].T


def close(actual, expected, rtol, err_msg=""):
    expected = np.asarray(expected, dtype=float)
    scale = max(1.0, float(np.max(np.abs(expected)))) if expected.size else 1.0
    np.testing.assert_allclose(actual, expected, rtol=0, atol=rtol * scale, err_msg=err_msg)


# ---- forward dynamics ------------------------------------------------------------------------------------------


@pytest.mark.parametrize("key,kind", CASES)
def test_equations_of_motion(key, kind):
    """RNEA(q, v, a) = tau + J^T lambda, J from frame_jacobian; contact_jacobian is that J."""
    m, c = get_model(key), contacts_for(key, kind)
    s = states(m, 4, seed=1)
    for q, v, tau in zip(s.Q, s.V, s.T):
        a, lam = sp.constrained_forward_dynamics(c, q, v, tau)
        assert a.shape == (m.nv,) and lam.shape == (c.rows,)
        J, lrows = rows_and_lambda(m, c, q, lam)
        close(sp.contact_jacobian(c, q), J, 1e-13)
        close(spatial.rnea(m, q, v, a), tau + J.T @ lrows, 1e-10)


@pytest.mark.parametrize("key,kind", CASES)
def test_acceleration_constraint(key, kind):
    """At zero gains the contact frames do not accelerate: d/dt (J v) = J a + Jdot v = 0 along the motion."""
    m, c = get_model(key), contacts_for(key, kind)
    s = states(m, 3, seed=2)
    for q, v, tau in zip(s.Q, s.V, s.T):
        a, _ = sp.constrained_forward_dynamics(c, q, v, tau)
        rate = rate_along(m, c, q, v, a)
        scale = max(1.0, np.max(np.abs(a)), np.max(np.abs(v)) ** 2)
        assert np.max(np.abs(rate)) < 1e-6 * scale, rate


@pytest.mark.parametrize("key", FLOATING)
def test_baumgarte_terms(key):
    """With gains: J a + Jdot v = -kd J v - kp e. 3D: e = p - p* (world), the target taken at another q; 6D with
    its target at the current pose (e = 0): the spatial acceleration is -kd times the spatial velocity."""
    m = get_model(key)
    kp, kd = 25.0, 7.0
    c = sp.Contacts(m, [sp.Contact3D("R_SOLE", kp=kp, kd=kd), sp.Contact6D("L_SOLE", kp=kp, kd=kd)])
    s = states(m, 3, seed=3)
    for k, (q, v, tau) in enumerate(zip(s.Q, s.V, s.T)):
        c.set_targets(q)
        targets = c.targets
        for j, name in enumerate(c.names):
            np.testing.assert_array_equal(targets[j], spatial.frame_placement(m, q, name))
        p_star = targets[0][:3, 3]
        # A pose error for the point: the targets stay at q, the state moves away from it.
        q_now = q if k == 0 else spatial.integrate(m, q, 0.05 * s.V[(k + 1) % 3])
        a, _ = sp.constrained_forward_dynamics(c, q_now, v, tau)
        rate = rate_along(m, c, q_now, v, a)
        vel = frame_velocities(m, c, q_now, v)
        p = spatial.frame_placement(m, q_now, "R_SOLE")[:3, 3]
        expected_point = -kd * vel[:3] - kp * (p - p_star)
        scale = max(1.0, np.max(np.abs(a)), np.max(np.abs(v)) ** 2)
        assert np.max(np.abs(rate[:3] - expected_point)) < 1e-6 * scale, (rate[:3], expected_point)
        if k == 0:  # the 6D target is the current pose only at q itself
            assert np.max(np.abs(rate[3:] + kd * vel[3:])) < 1e-6 * scale
    # Back to the model's frames' own poses: targets are per set and survive calls.
    c.set_targets(spatial.neutral(m))
    np.testing.assert_array_equal(c.targets[1], spatial.frame_placement(m, spatial.neutral(m), "L_SOLE"))


def test_compile_time_equals_runtime():
    gen, urdf = contacts_for("floating_gen", "mixed"), contacts_for("floating_urdf", "mixed")
    m = get_model("floating_gen")
    s = states(m, 4, seed=4)
    a1, l1 = sp.constrained_forward_dynamics(gen, s.Q, s.V, s.T)
    a2, l2 = sp.constrained_forward_dynamics(urdf, s.Q, s.V, s.T)
    close(a1, a2, 1e-10)
    close(l1, l2, 1e-10)


def test_redundant_contacts_need_damping():
    """Two welds on one sole: J H^-1 J^T is singular (NaN results); damping splits the load equally."""
    m = get_model("floating_gen")
    q = standing(m)
    v = np.zeros(m.nv)
    tau = np.zeros(m.nv)
    twice = [sp.Contact6D("L_SOLE"), sp.Contact6D("L_SOLE")]
    a, lam = sp.constrained_forward_dynamics(sp.Contacts(m, twice), q, v, tau)
    assert np.all(np.isnan(a)) and np.all(np.isnan(lam))
    v_after, imp = sp.impulse_dynamics(sp.Contacts(m, twice), q, v)
    assert np.all(np.isnan(v_after)) and np.all(np.isnan(imp))
    damped = sp.Contacts(m, twice, damping=1e-7)
    assert damped.damping == 1e-7
    a2, lam2 = sp.constrained_forward_dynamics(damped, q, v, tau)
    a1, lam1 = sp.constrained_forward_dynamics(sp.Contacts(m, twice[:1]), q, v, tau)
    # (the residual grows with the damping, the round-off of the split shrinks with it)
    close(lam2[:6], lam2[6:], 1e-7)
    close(lam2[:6] + lam2[6:], lam1, 1e-5)
    close(a2, a1, 1e-4)


# ---- impulses --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("restitution", [0.0, 0.4, 1.0])
@pytest.mark.parametrize("key,kind", CASES)
def test_impulses(key, kind, restitution):
    """J v+ = -e J v-, H (v+ - v-) = J^T impulses, the kinetic energy does not grow (kept for e = 1)."""
    m, c = get_model(key), contacts_for(key, kind)
    s = states(m, 3, seed=5)
    for q, v in zip(s.Q, s.V):
        v_after, imp = sp.impulse_dynamics(c, q, v, restitution)
        J, irows = rows_and_lambda(m, c, q, imp)
        close(J @ v_after, -restitution * (J @ v), 1e-11)
        close(spatial.crba(m, q) @ (v_after - v), J.T @ irows, 1e-11)
        e0, e1 = spatial.kinetic_energy(m, q, v), spatial.kinetic_energy(m, q, v_after)
        assert e1 <= e0 * (1 + 1e-12)
        if restitution == 1.0:
            assert abs(e1 - e0) <= 1e-10 * e0
        else:
            assert e1 < e0


# ---- whole-body inverse dynamics, ZMP, CoP ------------------------------------------------------------------------


def expect_physical(c, lam, tol):
    """Every 6D contact's wrench (Local axes) in its cone: fz >= 0, |fx|, |fy| <= mu fz, CoP inside the sole."""
    for desc, off in zip(c.contacts, c.offsets):
        w = lam[off:off + 6]
        assert w[2] >= -tol
        assert abs(w[0]) <= desc.friction * w[2] + tol and abs(w[1]) <= desc.friction * w[2] + tol
        x0, x1, y0, y1 = desc.sole
        assert x0 - 1e-9 <= -w[4] / w[2] <= x1 + 1e-9 and y0 - 1e-9 <= w[3] / w[2] <= y1 + 1e-9


@pytest.mark.parametrize("key", FLOATING)
def test_inverse_dynamics_round_trip(key):
    """Standing on both soles at rest, accelerations that keep the soles still: contact_inverse_dynamics supplies the
    root wrench exactly with a physical split; constrained_forward_dynamics with the torques found gives back a and
    the same forces (the solution is unique); RNEA = tau + J^T lambda; the multibody ZMP is the forces' CoP."""
    m, c = get_model(key), contacts_for(key, "both")
    q, v = standing(m), np.zeros(m.nv)
    J = sp.contact_jacobian(c, q)
    N = null_space(J)
    rng = np.random.default_rng(6)
    weight = m.total_mass * G
    solved = 0
    for k in range(20):
        a = N @ (N.T @ rng.normal(scale=0.0 if k == 0 else 0.3, size=m.nv))
        tau, lam, ok = sp.contact_inverse_dynamics(c, q, v, a)
        assert isinstance(ok, bool)
        if k == 0:  # at rest: the weight on the soles, nothing missing
            assert ok
            close(lam[2] + lam[8], weight, 1e-12)
        if not ok:
            continue
        solved += 1
        assert np.linalg.norm(tau[:6]) < 1e-10 * weight
        expect_physical(c, lam, 1e-9 * weight)
        close(spatial.rnea(m, q, v, a), tau + J.T @ lam, 1e-12)
        a2, lam2 = sp.constrained_forward_dynamics(c, q, v, tau)
        close(a2, a, 1e-9)
        close(lam2, lam, 1e-9)
        close(sp.multibody_zmp(m, q, v, a), sp.center_of_pressure(c, q, lam), 1e-12)
    assert solved >= 10


@pytest.mark.parametrize("key", FLOATING)
def test_inverse_dynamics_without_a_physical_split(key):
    """The pelvis accelerating sideways at 2 g: the ZMP leaves the soles, ok is False and tau[:6] is what the
    contacts leave missing; a point contact (3D) and a 6D sole, in world axes, at rest: ok."""
    m, c = get_model(key), contacts_for(key, "both")
    q, v = standing(m), np.zeros(m.nv)
    a = np.zeros(m.nv)
    a[1] = 2 * G
    tau, lam, ok = sp.contact_inverse_dynamics(c, q, v, a)
    assert not ok and np.linalg.norm(tau[:6]) > 1e-3
    mixed = sp.Contacts(m, [sp.Contact6D("L_SOLE", reference="local_world_aligned", sole=SOLE),
                            sp.Contact3D("R_SOLE", friction=0.8)])
    tau, lam, ok = sp.contact_inverse_dynamics(mixed, q, v, np.zeros(m.nv))
    assert ok and np.linalg.norm(tau[:6]) < 1e-9
    J, lrows = rows_and_lambda(m, mixed, q, lam)
    close(spatial.rnea(m, q, v, np.zeros(m.nv)), tau + J.T @ lrows, 1e-12)
    assert lam[8] >= 0 and abs(lam[6]) <= 0.8 * lam[8] + 1e-9 and abs(lam[7]) <= 0.8 * lam[8] + 1e-9
    close(lam[2] + lam[8], m.total_mass * G, 1e-12)


def root_wrench_world(m, q, v, a):
    """The ground wrench the motion needs, from RNEA's root entries: [f; n about the world origin], world axes."""
    tau = spatial.rnea(m, q, v, a)
    X = spatial.frame_placement(m, q, "base_link")  # the root's pose (its frame is the root body's)
    R, p = X[:3, :3], X[:3, 3]
    f = R @ tau[:3]
    return np.concatenate([f, R @ tau[3:6] + np.cross(p, f)])


def zmp_of(w, h):
    f, n = w[:3], w[3:]
    return np.array([(h * f[0] - n[1]) / f[2], (n[0] + h * f[1]) / f[2], h])


@pytest.mark.parametrize("height", [0.0, 0.1])
@pytest.mark.parametrize("kind", ["left", "both", "mixed"])
@pytest.mark.parametrize("key", FLOATING)
def test_zmp_equals_cop(key, kind, height):
    """Near the standing pose, with torques around gravity compensation and no wrench on the root: the contacts are
    the only external forces, so the contact wrench is RNEA's root wrench and the multibody ZMP is their CoP, in
    single and double support; both against the formula on RNEA's root wrench."""
    m, c = get_model(key), contacts_for(key, kind)
    base = standing(m)
    tau0, _, _ = sp.contact_inverse_dynamics(contacts_for(key, "both"), base, np.zeros(m.nv), np.zeros(m.nv))
    rng = np.random.default_rng(7)
    for _ in range(4):
        q = base.copy()
        q[7:] += rng.normal(scale=0.05, size=m.njoints)
        v = rng.normal(scale=0.3, size=m.nv)
        tau = tau0 + rng.normal(scale=0.3, size=m.nv)
        tau[:6] = 0.0
        a, lam = sp.constrained_forward_dynamics(c, q, v, tau)
        w = root_wrench_world(m, q, v, a)
        close(sp.contact_wrench(c, q, lam), w, 1e-10)
        assert w[2] > 1.0
        zmp, cop = sp.multibody_zmp(m, q, v, a, height), sp.center_of_pressure(c, q, lam, height)
        close(zmp, zmp_of(w, height), 1e-10)
        close(cop, zmp, 1e-10)
        assert zmp[2] == height


def test_zmp_is_nan_without_support():
    """Free fall: nothing pushes the robot up, no ZMP."""
    m = get_model("floating_gen")
    q = standing(m)
    a = spatial.aba(m, q, np.zeros(m.nv), np.zeros(m.nv))
    assert np.all(np.isnan(sp.multibody_zmp(m, q, np.zeros(m.nv), a)))


def test_fixed_base_zmp_and_contacts():
    """A fixed base: the ZMP of the base's reaction (base frame); contact_inverse_dynamics is refused."""
    m = get_model("stance_gen")
    s = states(m, 3, seed=8)
    z = sp.multibody_zmp(m, s.Q, s.V, s.A, 0.02)
    assert z.shape == (3, 3) and np.all(z[:, 2] == 0.02)
    with pytest.raises(ValueError, match="contact_inverse_dynamics: the model 'hoap3_stance_right' has a fixed base"):
        sp.contact_inverse_dynamics(contacts_for("stance_gen", "left"), s.Q[0], s.V[0], s.A[0])


# ---- batches, threads, concurrency ---------------------------------------------------------------------------------


def all_calls(m, c):
    return {
        "constrained_forward_dynamics": lambda S, **kw: sp.constrained_forward_dynamics(c, S.Q, S.V, S.T, **kw),
        "impulse_dynamics": lambda S, **kw: sp.impulse_dynamics(c, S.Q, S.V, 0.3, **kw),
        "contact_jacobian": lambda S, **kw: sp.contact_jacobian(c, S.Q, **kw),
        "contact_wrench": lambda S, **kw: sp.contact_wrench(c, S.Q, S.L, **kw),
        "center_of_pressure": lambda S, **kw: sp.center_of_pressure(c, S.Q, S.L, 0.05, **kw),
        "multibody_zmp": lambda S, **kw: sp.multibody_zmp(m, S.Q, S.V, S.A, 0.05, **kw),
        **({"contact_inverse_dynamics": lambda S, **kw: sp.contact_inverse_dynamics(c, S.Q, S.V, S.A, **kw)}
           if m.floating else {}),
    }


def as_tuple(r):
    return r if isinstance(r, tuple) else (r,)


@pytest.mark.parametrize("key,kind", CASES)
def test_batches_equal_single_calls_and_threads(key, kind):
    m, c = get_model(key), contacts_for(key, kind)
    B = 7
    S = states(m, B, seed=9)
    S.L = np.random.default_rng(10).normal(size=(B, c.rows))
    S.L[:, 2] += 50.0
    for name, f in all_calls(m, c).items():
        batch = as_tuple(f(S))
        for b in range(B):
            one = types_one(S, b)
            single = as_tuple(f(one))
            for x, y in zip(batch, single):
                np.testing.assert_array_equal(np.asarray(x[b]), np.asarray(y), err_msg=f"{name} state {b}")
    # Threads: a batch large enough for three of them (each gets at least 256 states).
    B = 800
    S = states(m, B, seed=11)
    S.L = np.random.default_rng(12).normal(size=(B, c.rows))
    S.L[:, 2] += 50.0
    for name, f in all_calls(m, c).items():
        batch = as_tuple(f(S))
        for t in (2, 3, 0):
            for x, y in zip(as_tuple(f(S, threads=t)), batch):
                np.testing.assert_array_equal(x, y, err_msg=f"{name} threads={t}")
        for x in batch:
            assert x.shape[0] == B and x.flags.c_contiguous
            assert x.dtype == (np.bool_ if x.ndim == 1 and name == "contact_inverse_dynamics" else np.float64)


class _State:
    pass


def types_one(S, b):
    one = _State()
    for k in ("Q", "V", "A", "T", "L"):
        setattr(one, k, getattr(S, k)[b])
    return one


def test_shared_arguments_broadcast():
    """An argument given as (n,) is shared by the whole batch; (1, n) is a batch of one."""
    m, c = get_model("floating_gen"), contacts_for("floating_gen", "both")
    S = states(m, 4, seed=11)
    a, lam = sp.constrained_forward_dynamics(c, S.Q, S.V, S.T[0])
    a2, lam2 = sp.constrained_forward_dynamics(c, S.Q, S.V, np.tile(S.T[0], (4, 1)))
    np.testing.assert_array_equal(a, a2)
    np.testing.assert_array_equal(lam, lam2)
    a1, lam1 = sp.constrained_forward_dynamics(c, S.Q[:1], S.V[0], S.T[0])
    assert a1.shape == (1, m.nv) and lam1.shape == (1, 12)
    np.testing.assert_array_equal(a1[0], a[0])
    # lists, integers and float32 are converted
    tau, lam, ok = sp.contact_inverse_dynamics(c, list(standing(m)), [0] * m.nv, np.zeros(m.nv, np.float32))
    assert ok and tau.dtype == np.float64


def test_contact_set_used_from_two_python_threads():
    """Batches release the GIL; two Python threads on one contact set get the right results (the second uses
    fresh buffers)."""
    m, c = get_model("floating_gen"), contacts_for("floating_gen", "both")
    S = states(m, 300, seed=12)
    expected = sp.constrained_forward_dynamics(c, S.Q, S.V, S.T)
    errors = []
    barrier = threading.Barrier(3)

    def work():
        try:
            barrier.wait()
            for _ in range(5):
                a, lam = sp.constrained_forward_dynamics(c, S.Q, S.V, S.T)
                np.testing.assert_array_equal(a, expected[0])
                np.testing.assert_array_equal(lam, expected[1])
        except Exception as e:  # noqa: BLE001
            errors.append(e)

    threads = [threading.Thread(target=work) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors


# ---- the contact set, descriptions and errors -------------------------------------------------------------------


def test_contact_set_description():
    m = get_model("floating_gen")
    c = sp.Contacts(m, [sp.Contact6D("L_SOLE", sole=SOLE), sp.Contact3D(m.frame_names.index("R_HAND"), kp=4.0)])
    assert c.rows == 9 and len(c) == 2
    assert c.names == ["L_SOLE", "R_HAND"] and c.sizes == [6, 3] and c.offsets == [0, 6]
    assert c.frames == [m.frame_index("L_SOLE"), m.frame_index("R_HAND")]
    assert c.model is not None and c.model.name == m.name and c.damping == 0.0
    np.testing.assert_array_equal(c.targets, np.broadcast_to(np.eye(4), (2, 4, 4)))
    assert "L_SOLE (6D), R_HAND (3D); rows = 9" in repr(c)
    d = c.contacts[1]
    assert isinstance(d, sp.Contact3D) and isinstance(d, sp.Contact) and d.type == "3d" and d.kp == 4.0
    assert d.reference == "local_world_aligned" and d.sole is None and d.friction == 0.6
    assert c.contacts[0].sole == SOLE and c.contacts[0].reference == "local"
    assert repr(c.contacts[0]).startswith("Contact6D('L_SOLE', reference='local'")
    single = sp.Contacts(m, sp.Contact3D("L_HAND"))  # one description instead of a list
    assert single.rows == 3


def test_errors():
    m = get_model("floating_gen")
    c = contacts_for("floating_gen", "both")
    q, v = standing(m), np.zeros(m.nv)
    with pytest.raises(KeyError, match="unknown frame 'L_SOL'.*did you mean 'L_SOLE'"):
        sp.Contacts(m, [sp.Contact6D("L_SOL")])
    with pytest.raises(KeyError, match="'R_KN' is a body"):
        sp.Contacts(m, [sp.Contact3D("R_KN")])
    with pytest.raises(spatial.ModelError, match="frame index 99 is not one of the model's 17 frames"):
        sp.Contacts(m, [sp.Contact6D(99)])
    with pytest.raises(TypeError, match=r"contacts\[1\] is a str"):
        sp.Contacts(m, [sp.Contact6D("L_SOLE"), "R_SOLE"])
    with pytest.raises(ValueError, match="reference 'world' is not offered"):
        sp.Contact6D("L_SOLE", reference="world")
    with pytest.raises(ValueError, match="reference 'lwa' is not one of"):
        sp.Contact3D("L_SOLE", reference="lwa")
    with pytest.raises(ValueError, match="'sole' must be 4 finite numbers"):
        sp.Contact6D("L_SOLE", sole=(0.1, 0.2))
    with pytest.raises(ValueError, match="x_min <= x_max"):
        sp.Contact6D("L_SOLE", sole=(0.1, -0.1, -0.02, 0.02))
    with pytest.raises(ValueError, match="'friction' must be finite and >= 0"):
        sp.Contact3D("L_SOLE", friction=-1.0)
    with pytest.raises(TypeError, match="'frame' must be a frame name"):
        sp.Contact3D(1.5)
    with pytest.raises(ValueError, match="'damping' must be finite and >= 0"):
        sp.Contacts(m, [sp.Contact6D("L_SOLE")], damping=-1.0)
    with pytest.raises(ValueError, match=r"constrained_forward_dynamics: argument 'tau' has shape \(26,\); the model "
                                         r"'hoap3_floating' has nv = 27, so expected \(27,\) or \(B, 27\)"):
        sp.constrained_forward_dynamics(c, q, v, np.zeros(26))
    with pytest.raises(ValueError, match=r"impulse_dynamics: argument 'q' has shape \(27,\)"):
        sp.impulse_dynamics(c, np.zeros(27), v)
    with pytest.raises(ValueError, match=r"center_of_pressure: argument 'lam' has shape \(6,\); the contact set has "
                                         r"12 rows \(contacts.rows\), so expected \(12,\) or \(B, 12\)"):
        sp.center_of_pressure(c, q, np.zeros(6))
    with pytest.raises(ValueError, match="contact_wrench: argument 'lam' has 3 states, an earlier argument 2"):
        sp.contact_wrench(c, np.tile(q, (2, 1)), np.zeros((3, 12)))
    with pytest.raises(ValueError, match="restitution' must be in \\[0, 1\\]"):
        sp.impulse_dynamics(c, q, v, 1.5)
    bad = v.copy()
    bad[4] = np.nan
    with pytest.raises(ValueError, match="contact_inverse_dynamics: argument 'a' has a non-finite entry \\(nan\\) at "
                                         "index 4"):
        sp.contact_inverse_dynamics(c, q, v, bad, check=True)
    with pytest.raises(ValueError, match="state 1, at index 4"):
        sp.contact_jacobian(c, np.stack([q, np.where(np.arange(m.nq) == 4, np.inf, q)]), check=True)
    with pytest.raises(TypeError, match="multibody_zmp: argument 'v' must be an array of real numbers"):
        sp.multibody_zmp(m, q, v.astype(complex), v)
    with pytest.raises(ValueError, match="threads must be >= 0"):
        sp.contact_jacobian(c, q, threads=-1)
    with pytest.raises(ValueError, match="Contacts.set_targets: 'q' must be one configuration"):
        c.set_targets(np.tile(q, (2, 1)))


# ---- Pinocchio (optional) ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("kind", ["left", "both"])
def test_against_pinocchio_constraint_dynamics(kind):
    """Pinocchio's constraintDynamics and impulseDynamics (CONTACT_6D, LOCAL) on the same floating HOAP-3: the same
    a and lambda, v+ and impulses (measured ~1e-14)."""
    pin = pytest.importorskip("pinocchio")
    from test_pinocchio import Pair

    m = get_model("floating_urdf")
    c = contacts_for("floating_urdf", kind)
    pair = Pair(m, True)
    pm, pd = pair.pm, pair.pd
    models = []
    for name in c.names:
        fr = pm.frames[pair.frame(name)]
        models.append(pin.RigidConstraintModel(pin.ContactType.CONTACT_6D, pm, fr.parentJoint, fr.placement,
                                               pin.ReferenceFrame.LOCAL))
    models = pin.StdVec_RigidConstraintModel(models)
    datas = pin.StdVec_RigidConstraintData([cm.createData() for cm in models])
    pin.initConstraintDynamics(pm, pd, models, datas)
    settings = pin.ProximalSettings(1e-14, 0.0, 1)
    s = states(m, 3, seed=13)
    for q, v, tau in zip(s.Q, s.V, s.T):
        a_pin = pin.constraintDynamics(pm, pd, pair.q(q), pair.v(v), pair.v(tau), models, datas, settings)
        a, lam = sp.constrained_forward_dynamics(c, q, v, tau)
        close(a, pair.vec(a_pin), 1e-11)
        close(lam, np.asarray(pd.lambda_c), 1e-11)
        v_pin = pin.impulseDynamics(pm, pd, pair.q(q), pair.v(v), models, datas, 0.4, settings)
        v_after, imp = sp.impulse_dynamics(c, q, v, 0.4)
        close(v_after, pair.vec(v_pin), 1e-11)
        close(imp, np.asarray(pd.impulse_c), 1e-11)
