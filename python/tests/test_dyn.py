"""The terms of the dynamics (spatial.Dyn, the C++ options.hpp flags) on rnea, aba and forward_dynamics.

Each flag set is checked against the full algorithms taken apart: G = gravity(q), C v = bias(q, v) - G, H a = crba(q) a
and the external forces' part rnea(q, v, a, fext) - rnea(q, v, a), so rnea(dyn) must be the sum of the terms dyn
names and aba(dyn) = forward_dynamics(dyn) = H^-1 (tau - the bias terms dyn names); with fext (Full only, the other
sets refused), rnea and aba must add the forces' part. An input that
dyn does not read must change nothing (bit for bit, NaN included) and may be None. Every engine is exercised: each
generated fixed-base model, the run-time twin and a reduced model (each compiles its own copies of the flag sets)."""

import itertools

import numpy as np
import pytest

import spatial
from conftest import assert_close, get_model, states

D = spatial.Dyn
G, V, A = D.Gravity, D.Velocity, D.Acceleration
# Every subset of the three terms, Dyn(0) (none) included.
RNEA_SETS = [D(sum(int(f) for f in c)) for r in range(4) for c in itertools.combinations([G, V, A], r)]
FD_SETS = [D(0), G, V, G | V]

FIXED = {
    "stance_gen": lambda: get_model("stance_gen"),
    "stance_urdf": lambda: get_model("stance_urdf"),
    "stance_left": spatial.hoap3_stance_left,
    "torso": spatial.hoap3_torso,
    "pendulum": spatial.hoap3_double_pendulum,
    # A reduced model (two joints locked): run-time, built by model reduction.
    "reduced": lambda: spatial.lock_joints(get_model("stance_urdf"), {get_model("stance_urdf").joint_names[3]: 0.3,
                                                                      get_model("stance_urdf").joint_names[10]: -0.2}),
}


@pytest.fixture(params=sorted(FIXED))
def fixed(request):
    return request.param, FIXED[request.param]()


def _parts(m, s, fext):
    """Per state: G, C v, H a, the external forces' part of rnea, and H."""
    g = spatial.gravity(m, s.Q)
    cv = spatial.bias(m, s.Q, s.V) - g
    H = spatial.crba(m, s.Q)
    ha = np.einsum("bij,bj->bi", H, s.A)
    f = spatial.rnea(m, s.Q, s.V, s.A, fext) - spatial.rnea(m, s.Q, s.V, s.A)
    return g, cv, ha, f, H


def _fext(m, count, seed):
    rng = np.random.default_rng(seed)
    return rng.uniform(-2.0, 2.0, size=(count, m.njoints, 6))


def _check_fext(name, call, dyn, full, expected, rtol, key):
    """fext with the set `dyn`: the forces' part added when the set is all of the function's terms (`full`), refused
    otherwise (external forces with Full only; the forces' part is linear: add it)."""
    if full:
        assert_close(call(), expected, rtol=rtol, err_msg=f"{key} {name} {dyn!r} with fext")
    else:
        with pytest.raises(ValueError, match=f"{name}: fext= works with dyn=Dyn.Full only"):
            call()


def test_flag_values():
    assert G | A == D.QuasiStatic and G == D.Static and V | A == D.NoGravity and G | V | A == D.Full
    assert len(set(RNEA_SETS)) == 8 and int(D(0)) == 0


def test_rnea_terms(fixed):
    key, m = fixed
    s = states(m, 4, seed=301)
    fe = _fext(m, 4, 302)
    g, cv, ha, f, _ = _parts(m, s, fe)
    for dyn in RNEA_SETS:
        expected = np.zeros_like(g) + (g if G in dyn else 0) + (cv if V in dyn else 0) + (ha if A in dyn else 0)
        assert_close(spatial.rnea(m, s.Q, s.V, s.A, dyn=dyn), expected, rtol=1e-11, err_msg=f"{key} rnea {dyn!r}")
        _check_fext("rnea", lambda: spatial.rnea(m, s.Q, s.V, s.A, fe, dyn=dyn), dyn, dyn == D.Full, expected + f,
                    1e-11, key)
    # Full is what the call without dyn computes, bit for bit.
    np.testing.assert_array_equal(spatial.rnea(m, s.Q, s.V, s.A, dyn=D.Full), spatial.rnea(m, s.Q, s.V, s.A))


def test_aba_and_forward_dynamics_terms(fixed):
    key, m = fixed
    s = states(m, 4, seed=303)
    fe = _fext(m, 4, 304)
    g, cv, _, f, H = _parts(m, s, fe)
    for dyn in FD_SETS:
        rhs = s.T - (g if G in dyn else 0) - (cv if V in dyn else 0)
        expected = np.linalg.solve(H, rhs[..., None])[..., 0]
        with_f = np.linalg.solve(H, (rhs - f)[..., None])[..., 0]
        assert_close(spatial.aba(m, s.Q, s.V, s.T, dyn=dyn), expected, rtol=1e-9, err_msg=f"{key} aba {dyn!r}")
        # G | V is all of aba's terms: Full
        _check_fext("aba", lambda: spatial.aba(m, s.Q, s.V, s.T, fe, dyn=dyn), dyn, dyn == G | V, with_f, 1e-9, key)
        assert_close(spatial.forward_dynamics(m, s.Q, s.V, s.T, dyn=dyn), expected, rtol=1e-9,
                     err_msg=f"{key} forward_dynamics {dyn!r}")
        # Acceleration does not apply to forward dynamics: with or without it, the same code and numbers.
        np.testing.assert_array_equal(spatial.aba(m, s.Q, s.V, s.T, dyn=dyn | A), spatial.aba(m, s.Q, s.V, s.T, dyn=dyn))
        np.testing.assert_array_equal(spatial.forward_dynamics(m, s.Q, s.V, s.T, dyn=dyn | A),
                                      spatial.forward_dynamics(m, s.Q, s.V, s.T, dyn=dyn))


def test_unread_inputs_are_not_read(fixed):
    key, m = fixed
    s = states(m, 3, seed=305)
    nan = np.full_like(s.V, np.nan)
    # rnea without Velocity: v is never read (NaN, None and the real v give the same bits); without Acceleration, a.
    for dyn in [D.Static, D.QuasiStatic, A, D(0)]:
        ref = spatial.rnea(m, s.Q, s.V, s.A, dyn=dyn)
        assert np.all(np.isfinite(ref)), f"{key} {dyn!r}"
        np.testing.assert_array_equal(spatial.rnea(m, s.Q, nan, s.A, dyn=dyn), ref)
        np.testing.assert_array_equal(spatial.rnea(m, s.Q, None, s.A, dyn=dyn), ref)
    for dyn in [D.Static, G | V, V, D(0)]:
        ref = spatial.rnea(m, s.Q, s.V, s.A, dyn=dyn)
        np.testing.assert_array_equal(spatial.rnea(m, s.Q, s.V, nan, dyn=dyn), ref)
        np.testing.assert_array_equal(spatial.rnea(m, s.Q, s.V, None, dyn=dyn), ref)
    # aba and forward_dynamics without Velocity: v is never read.
    for fn in (spatial.aba, spatial.forward_dynamics):
        for dyn in [D.Static, D(0)]:
            ref = fn(m, s.Q, s.V, s.T, dyn=dyn)
            assert np.all(np.isfinite(ref))
            np.testing.assert_array_equal(fn(m, s.Q, nan, s.T, dyn=dyn), ref)
            np.testing.assert_array_equal(fn(m, s.Q, None, s.T, dyn=dyn), ref)
    # And with the term on, the input is read: NaN comes through.
    assert np.all(np.isnan(spatial.rnea(m, s.Q, nan, s.A, dyn=V)))


def test_batches_and_threads(fixed):
    key, m = fixed
    s = states(m, 600, seed=306)
    for dyn in [D.QuasiStatic, V, D(0)]:
        batch = spatial.rnea(m, s.Q, None if V not in dyn else s.V, s.A, dyn=dyn, threads=2)
        one = np.stack([spatial.rnea(m, s.Q[k], s.V[k], s.A[k], dyn=dyn) for k in range(0, 600, 97)])
        np.testing.assert_array_equal(batch[::97], one)
        np.testing.assert_array_equal(batch, spatial.rnea(m, s.Q, s.V, s.A, dyn=dyn, threads=1))
        fd2 = spatial.aba(m, s.Q, s.V, s.T, dyn=dyn, threads=2)
        np.testing.assert_array_equal(fd2, spatial.aba(m, s.Q, s.V, s.T, dyn=dyn, threads=1))
    # One configuration shared by a batch of accelerations; None for the unread v.
    tau = spatial.rnea(m, s.Q[0], None, s.A, dyn=D.QuasiStatic)
    assert tau.shape == (600, m.nv)
    np.testing.assert_array_equal(tau[5], spatial.rnea(m, s.Q[0], s.V[0], s.A[5], dyn=D.QuasiStatic))


def test_floating_base_full_only():
    for m in (get_model("floating_gen"), get_model("floating_urdf")):
        s = states(m, 2, seed=307)
        np.testing.assert_array_equal(spatial.rnea(m, s.Q, s.V, s.A, dyn=D.Full), spatial.rnea(m, s.Q, s.V, s.A))
        np.testing.assert_array_equal(spatial.aba(m, s.Q, s.V, s.T, dyn=D.Full | A), spatial.aba(m, s.Q, s.V, s.T))
        for fn, x in ((spatial.rnea, s.A), (spatial.aba, s.T), (spatial.forward_dynamics, s.T)):
            with pytest.raises(ValueError, match="fixed-base models only.*floating base"):
                fn(m, s.Q, s.V, x, dyn=D.Static)
        # aba ignores Acceleration, so G | V is Full for it.
        np.testing.assert_array_equal(spatial.aba(m, s.Q, s.V, s.T, dyn=G | V), spatial.aba(m, s.Q, s.V, s.T))


def test_errors():
    m = get_model("stance_gen")
    s = states(m, 1, seed=308)
    with pytest.raises(TypeError, match="rnea: argument 'v' is None, but dyn includes"):
        spatial.rnea(m, s.Q[0], None, s.A[0])
    with pytest.raises(TypeError, match="rnea: argument 'a' is None, but dyn includes"):
        spatial.rnea(m, s.Q[0], s.V[0], None, dyn=D.QuasiStatic)
    with pytest.raises(TypeError, match="aba: argument 'v' is None, but dyn includes"):
        spatial.aba(m, s.Q[0], None, s.T[0], dyn=G | V)
    with pytest.raises(TypeError):
        spatial.aba(m, s.Q[0], s.V[0], None, dyn=D.Static)  # tau is always read
    with pytest.raises((TypeError, ValueError)):
        spatial.rnea(m, s.Q[0], s.V[0], s.A[0], dyn=8)  # C++'s BaseForces: not available from Python
    with pytest.raises(ValueError, match="argument 'v' has shape"):
        spatial.rnea(m, s.Q[0], np.zeros(3), s.A[0], dyn=D.Static)  # given, so checked even when not read
