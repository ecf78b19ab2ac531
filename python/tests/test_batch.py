"""Shapes, dtypes and memory: (n,) vs (1, n) vs (B, n) inputs, F-ordered and non-contiguous inputs, int / float32 /
list inputs, fresh float64 C-contiguous outputs of the right shape; batches equal per-state calls exactly and the
thread count does not change a bit."""

import threading
import types

import numpy as np
import pytest

import spatial
from conftest import MODEL_KEYS, get_model, states

B = 5


def calls(m, frame):
    """name -> (function of (Q, V, X) , output shapes per state as a tuple of shapes)."""
    nv, nq = m.nv, m.nq
    return {
        "rnea": (lambda Q, V, X, **kw: spatial.rnea(m, Q, V, X, **kw), [(nv,)]),
        "gravity": (lambda Q, V, X, **kw: spatial.gravity(m, Q, **kw), [(nv,)]),
        "bias": (lambda Q, V, X, **kw: spatial.bias(m, Q, V, **kw), [(nv,)]),
        "crba": (lambda Q, V, X, **kw: spatial.crba(m, Q, **kw), [(nv, nv)]),
        "aba": (lambda Q, V, X, **kw: spatial.aba(m, Q, V, X, **kw), [(nv,)]),
        "forward_dynamics": (lambda Q, V, X, **kw: spatial.forward_dynamics(m, Q, V, X, **kw), [(nv,)]),
        "kinetic_energy": (lambda Q, V, X, **kw: spatial.kinetic_energy(m, Q, V, **kw), [()]),
        "potential_energy": (lambda Q, V, X, **kw: spatial.potential_energy(m, Q, **kw), [()]),
        "frame_placement": (lambda Q, V, X, **kw: spatial.frame_placement(m, Q, frame, **kw), [(4, 4)]),
        "frame_jacobian": (lambda Q, V, X, **kw: spatial.frame_jacobian(m, Q, frame, reference="local", **kw),
                           [(6, nv)]),
        "frame_velocity": (lambda Q, V, X, **kw: spatial.frame_velocity(m, Q, V, frame, reference="world", **kw),
                           [(6,)]),
        "frame_acceleration": (lambda Q, V, X, **kw: spatial.frame_acceleration(m, Q, V, X, frame, reference="local",
                                                                                **kw), [(6,)]),
        "frame_classical_acceleration": (
            lambda Q, V, X, **kw: spatial.frame_classical_acceleration(m, Q, V, X, frame, **kw), [(3,)]),
        "frame_jacobian_time_variation": (
            lambda Q, V, X, **kw: spatial.frame_jacobian_time_variation(m, Q, V, frame, reference="world", **kw),
            [(6, nv)]),
        "center_of_mass": (lambda Q, V, X, **kw: spatial.center_of_mass(m, Q, **kw), [(3,)]),
        "com_jacobian": (lambda Q, V, X, **kw: spatial.com_jacobian(m, Q, **kw), [(3, nv)]),
        "centroidal_momentum_matrix": (lambda Q, V, X, **kw: spatial.centroidal_momentum_matrix(m, Q, **kw),
                                       [(6, nv)]),
        "centroidal_momentum": (lambda Q, V, X, **kw: spatial.centroidal_momentum(m, Q, V, **kw), [(6,)]),
        "centroidal_momentum_time_variation": (
            lambda Q, V, X, **kw: spatial.centroidal_momentum_time_variation(m, Q, V, X, **kw), [(6,)] * 2),
        "integrate": (lambda Q, V, X, **kw: spatial.integrate(m, Q, V, 0.5, **kw), [(nq,)]),
        "normalize": (lambda Q, V, X, **kw: spatial.normalize(m, Q, **kw), [(nq,)]),
        "rnea_derivatives": (lambda Q, V, X, **kw: spatial.rnea_derivatives(m, Q, V, X, **kw), [(nv, nv)] * 2),
        "aba_derivatives": (lambda Q, V, X, **kw: spatial.aba_derivatives(m, Q, V, X, **kw), [(nv, nv)] * 3),
        "inverse_inertia": (lambda Q, V, X, **kw: spatial.inverse_inertia(m, Q, **kw), [(nv, nv)]),
    }


NAMES = list(calls(types.SimpleNamespace(nv=1, nq=1), "frame").keys())


def as_tuple(r):
    return r if isinstance(r, tuple) else (r,)


def frame_for(key):
    return "L_SOLE" if key.startswith("stance") else "R_SOLE"


@pytest.fixture(params=MODEL_KEYS)
def model_states(request):
    key = request.param
    m = get_model(key)
    return key, m, states(m, B, seed=301)


def check_output(r, shape, what):
    if shape == () and not isinstance(r, np.ndarray):
        assert isinstance(r, float), f"{what}: {type(r)}"
        return
    assert isinstance(r, np.ndarray), f"{what}: {type(r)}"
    assert r.dtype == np.float64, f"{what}: dtype {r.dtype}"
    assert r.shape == shape, f"{what}: shape {r.shape}, expected {shape}"
    assert r.flags.c_contiguous, f"{what}: not C-contiguous"
    assert r.flags.writeable, f"{what}: read-only"


@pytest.mark.parametrize("name", NAMES)
def test_shapes_single_one_batch(model_states, name):
    key, m, s = model_states
    f, shapes = calls(m, frame_for(key))[name]
    one = as_tuple(f(s.Q[0], s.V[0], s.T[0]))
    assert len(one) == len(shapes)
    for r, shp in zip(one, shapes):
        check_output(r, shp, f"{key} {name} (n,)")
    row = as_tuple(f(s.Q[:1], s.V[:1], s.T[:1]))
    for r, shp in zip(row, shapes):
        check_output(r, (1,) + shp, f"{key} {name} (1, n)")
    batch = as_tuple(f(s.Q, s.V, s.T))
    for r, shp in zip(batch, shapes):
        check_output(r, (B,) + shp, f"{key} {name} (B, n)")
    # batch rows == single calls, bit for bit
    for k in range(B):
        single = as_tuple(f(s.Q[k], s.V[k], s.T[k]))
        for i, (b, r) in enumerate(zip(batch, single)):
            assert np.array_equal(b[k], r), f"{key} {name}[{i}]: batch row {k} != single call"
    for i, (b, r) in enumerate(zip(row, one)):
        assert np.array_equal(b[0], r), f"{key} {name}[{i}]: (1, n) != (n,)"


@pytest.mark.parametrize("name", NAMES)
def test_threads_bit_identical(model_states, name):
    key, m, s = model_states
    f, _ = calls(m, frame_for(key))[name]
    # a batch large enough for two threads (the engine gives each thread at least 256 states)
    big = states(m, 600, seed=302)
    r1 = as_tuple(f(big.Q, big.V, big.T, threads=1))
    r2 = as_tuple(f(big.Q, big.V, big.T, threads=2))
    r0 = as_tuple(f(big.Q, big.V, big.T, threads=0))
    rd = as_tuple(f(big.Q, big.V, big.T))
    for i in range(len(r1)):
        assert np.array_equal(r1[i], r2[i]), f"{key} {name}[{i}]: threads=2 != threads=1"
        assert np.array_equal(r1[i], r0[i]), f"{key} {name}[{i}]: threads=0 != threads=1"
        assert np.array_equal(r1[i], rd[i]), f"{key} {name}[{i}]: default != threads=1"


def test_threads_more_than_states(stance_gen):
    s = states(stance_gen, 3, seed=303)
    assert np.array_equal(spatial.rnea(stance_gen, s.Q, s.V, s.A, threads=8), spatial.rnea(stance_gen, s.Q, s.V, s.A))
    assert np.array_equal(spatial.rnea(stance_gen, s.Q[0], s.V[0], s.A[0], threads=4),
                          spatial.rnea(stance_gen, s.Q[0], s.V[0], s.A[0]))


def test_layouts(any_model):
    """F-ordered, non-contiguous (column slice of a wider array, every second row) inputs give the same numbers."""
    key, m = any_model
    s = states(m, 2 * B, seed=304)
    ref_tau = spatial.rnea(m, s.Q, s.V, s.A)
    ref_H = spatial.crba(m, s.Q)
    # F order
    QF, VF, AF = (np.asfortranarray(x) for x in (s.Q, s.V, s.A))
    assert not QF.flags.c_contiguous
    assert np.array_equal(spatial.rnea(m, QF, VF, AF), ref_tau)
    assert np.array_equal(spatial.crba(m, QF), ref_H)
    # a column slice of a wider array: rows not contiguous
    wide = np.zeros((2 * B, m.nq + 5))
    wide[:, 2:2 + m.nq] = s.Q
    Qs = wide[:, 2:2 + m.nq][:, ::1]
    assert not Qs.flags.c_contiguous
    assert np.array_equal(spatial.rnea(m, Qs, s.V, s.A), ref_tau)
    assert np.array_equal(spatial.crba(m, Qs), ref_H)
    # every second row
    assert np.array_equal(spatial.rnea(m, s.Q[::2], s.V[::2], s.A[::2]), ref_tau[::2])
    assert np.array_equal(spatial.crba(m, s.Q[::2]), ref_H[::2])
    # a strided single state
    wide1 = np.zeros(2 * m.nq)
    wide1[::2] = s.Q[0]
    assert np.array_equal(spatial.rnea(m, wide1[::2], s.V[0], s.A[0]), ref_tau[0])
    # reversed rows (negative stride)
    assert np.array_equal(spatial.rnea(m, s.Q[::-1], s.V[::-1], s.A[::-1]), ref_tau[::-1])
    # inputs are not modified
    Q0 = s.Q.copy()
    spatial.normalize(m, s.Q)
    spatial.integrate(m, s.Q, s.V)
    assert np.array_equal(s.Q, Q0)


def test_dtypes_and_lists(stance_gen, floating_gen):
    for m in (stance_gen, floating_gen):
        s = states(m, 2, seed=305)
        # int input: converted to float64
        Qi = np.zeros((2, m.nq), dtype=np.int64)
        if m.floating:
            Qi[:, 6] = 1
        Vi = np.arange(2 * m.nv, dtype=np.int32).reshape(2, m.nv) % 3 - 1
        Ai = np.ones((2, m.nv), dtype=np.int16)
        assert np.array_equal(spatial.rnea(m, Qi, Vi, Ai),
                              spatial.rnea(m, Qi.astype(float), Vi.astype(float), Ai.astype(float)))
        # float32: converted (the float32 values, as doubles)
        Q32, V32, A32 = (x.astype(np.float32) for x in (s.Q, s.V, s.A))
        r32 = spatial.rnea(m, Q32, V32, A32)
        assert r32.dtype == np.float64
        assert np.array_equal(r32, spatial.rnea(m, Q32.astype(float), V32.astype(float), A32.astype(float)))
        assert not np.array_equal(r32, spatial.rnea(m, s.Q, s.V, s.A))  # it did not use hidden float64 data
        # lists, nested lists, tuples
        assert np.array_equal(spatial.rnea(m, s.Q[0].tolist(), s.V[0].tolist(), tuple(s.A[0])),
                              spatial.rnea(m, s.Q[0], s.V[0], s.A[0]))
        assert np.array_equal(spatial.crba(m, s.Q.tolist()), spatial.crba(m, s.Q))
        # bool? a real-valued array-like: ints from a list
        assert np.array_equal(spatial.gravity(m, [int(x) for x in spatial.neutral(m)]),
                              spatial.gravity(m, spatial.neutral(m)))
        # big-endian float64 is converted too
        Qbe = s.Q.astype(">f8")
        assert np.array_equal(spatial.crba(m, Qbe), spatial.crba(m, s.Q))


def test_outputs_are_fresh(any_model):
    key, m = any_model
    s = states(m, 3, seed=306)
    fns = calls(m, frame_for(key))
    for name, (f, _) in fns.items():
        first = as_tuple(f(s.Q[0], s.V[0], s.T[0]))
        kept = [np.array(x, copy=True) for x in first]
        second = as_tuple(f(s.Q[1], s.V[1], s.T[1]))
        for i, (a, k) in enumerate(zip(first, kept)):
            assert np.array_equal(a, k), f"{key} {name}[{i}]: a second call changed the first result"
            if isinstance(a, np.ndarray):
                assert not np.shares_memory(a, second[i]), f"{key} {name}[{i}]: results share memory"
                assert not np.shares_memory(a, s.Q) and not np.shares_memory(a, s.V) and not np.shares_memory(a, s.T)
        firstb = as_tuple(f(s.Q[:2], s.V[:2], s.T[:2]))
        keptb = [np.array(x, copy=True) for x in firstb]
        as_tuple(f(s.Q[1:], s.V[1:], s.T[1:]))
        for i, (a, k) in enumerate(zip(firstb, keptb)):
            assert np.array_equal(a, k), f"{key} {name}[{i}]: a second batch changed the first result"
        # writing into a result does not change the next one
        for a in first:
            if isinstance(a, np.ndarray):
                a[...] = 12345.0
        again = as_tuple(f(s.Q[0], s.V[0], s.T[0]))
        for i, (a, k) in enumerate(zip(again, kept)):
            assert np.array_equal(a, k), f"{key} {name}[{i}]: result depends on an earlier result's memory"
    # the tuple results' arrays are distinct
    dq, dv = spatial.rnea_derivatives(m, s.Q[0], s.V[0], s.T[0])
    assert not np.shares_memory(dq, dv)


def test_neutral_fresh(any_model):
    key, m = any_model
    a = spatial.neutral(m)
    a[:] = 7.0
    b = spatial.neutral(m)
    assert not np.any(b == 7.0)


def test_difference_batch(any_model):
    key, m = any_model
    s = states(m, B, seed=307)
    Q2 = states(m, B, seed=308).Q
    D = spatial.difference(m, s.Q, Q2)
    assert D.shape == (B, m.nv) and D.dtype == np.float64 and D.flags.c_contiguous
    for k in range(B):
        assert np.array_equal(D[k], spatial.difference(m, s.Q[k], Q2[k]))
    assert np.array_equal(spatial.difference(m, s.Q, Q2, threads=2), D)


def test_fext_batch(floating_gen, stance_gen):
    for m in (floating_gen, stance_gen):
        s = states(m, B, seed=309)
        nb = m.njoints + (1 if m.floating else 0)
        F = np.random.default_rng(1).normal(size=(B, nb, 6))
        tau = spatial.rnea(m, s.Q, s.V, s.A, fext=F)
        qdd = spatial.aba(m, s.Q, s.V, s.T, fext=F)
        assert tau.shape == (B, m.nv) and qdd.shape == (B, m.nv)
        for k in range(B):
            assert np.array_equal(tau[k], spatial.rnea(m, s.Q[k], s.V[k], s.A[k], fext=F[k]))
            assert np.array_equal(qdd[k], spatial.aba(m, s.Q[k], s.V[k], s.T[k], fext=F[k]))
        assert np.array_equal(spatial.rnea(m, s.Q, s.V, s.A, fext=F, threads=2), tau)
        # F-ordered fext
        assert np.array_equal(spatial.rnea(m, s.Q, s.V, s.A, fext=np.asfortranarray(F)), tau)


def test_empty_batch(stance_gen):
    """A batch of zero states is (0, n) in, (0, ...) out (or refused with ValueError, never a crash)."""
    m = stance_gen
    Q = np.zeros((0, m.nq))
    try:
        r = spatial.rnea(m, Q, Q, Q)
    except ValueError:
        return
    assert r.shape == (0, m.nv)
    assert spatial.crba(m, Q).shape == (0, m.nv, m.nv)


def test_concurrent_python_threads(stance_gen, floating_urdf):
    """Python threads calling into the same model at once (batches release the GIL and share the model's own
    workspace unless data= is given) get the results of sequential calls."""
    jobs = []
    for m in (stance_gen, floating_urdf):
        for seed in range(4):
            s = states(m, 64, seed=400 + seed)
            jobs.append((m, s, spatial.rnea(m, s.Q, s.V, s.A), spatial.crba(m, s.Q), spatial.aba(m, s.Q, s.V, s.T)))
    errors = []
    barrier = threading.Barrier(len(jobs))

    def work(job):
        m, s, tau, H, qdd = job
        try:
            barrier.wait()
            for _ in range(5):
                if not np.array_equal(spatial.rnea(m, s.Q, s.V, s.A), tau):
                    errors.append("rnea")
                if not np.array_equal(spatial.crba(m, s.Q), H):
                    errors.append("crba")
                if not np.array_equal(spatial.aba(m, s.Q, s.V, s.T, threads=2), qdd):
                    errors.append("aba")
                if not np.array_equal(spatial.rnea(m, s.Q[0], s.V[0], s.A[0]), tau[0]):
                    errors.append("rnea single")
        except Exception as e:  # pragma: no cover - reported below
            errors.append(repr(e))

    threads = [threading.Thread(target=work, args=(j,)) for j in jobs]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=60)
    assert not any(t.is_alive() for t in threads), "a thread hung"
    assert not errors, errors[:5]
