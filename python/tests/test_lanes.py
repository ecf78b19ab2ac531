"""spatial.Batch: many states per call on SIMD lanes. Its results agree with the functions' (the single-state code)
to a few units in the last place; a state's result does not depend on the batch size, on the threads or on the
other states, bit for bit; shapes, broadcasting and errors as the functions'."""

import numpy as np
import pytest

import spatial
from conftest import assert_close, get_model, states

# Every kind of engine in the module: the generated (compile-time) HOAP-3 trees and run-time URDF trees, fixed and
# floating base.
KINDS = ["stance_gen", "stance_urdf", "pelvis_urdf", "torso", "double_pendulum", "floating_gen", "floating_urdf"]


def kind_model(key):
    if key == "torso":
        return spatial.hoap3_torso()
    if key == "double_pendulum":
        return spatial.hoap3_double_pendulum()
    return get_model(key)


def methods(b):
    """name -> (Batch call of (Q, V, X), the functions' call of the same). The frame methods on the model's last
    fixed frame (its Jacobian in 'local') and on its last body (in 'world')."""
    m = b.model
    frames = {}
    if m.frame_names:
        f = m.frame_names[-1]
        frames["frame_placement"] = (lambda Q, V, X: b.frame_placement(Q, f),
                                     lambda Q, V, X: spatial.frame_placement(m, Q, f))
        frames["frame_jacobian"] = (lambda Q, V, X: b.frame_jacobian(Q, f, "local"),
                                    lambda Q, V, X: spatial.frame_jacobian(m, Q, f, "local"))
    body = m.body_names[-1]
    frames["body_placement"] = (lambda Q, V, X: b.frame_placement(Q, body),
                                lambda Q, V, X: spatial.frame_placement(m, Q, body))
    frames["body_jacobian"] = (lambda Q, V, X: b.frame_jacobian(Q, body, reference="world"),
                               lambda Q, V, X: spatial.frame_jacobian(m, Q, body, reference="world"))
    return frames | {
        "rnea": (lambda Q, V, X: b.rnea(Q, V, X), lambda Q, V, X: spatial.rnea(m, Q, V, X)),
        "gravity": (lambda Q, V, X: b.gravity(Q), lambda Q, V, X: spatial.gravity(m, Q)),
        "bias": (lambda Q, V, X: b.bias(Q, V), lambda Q, V, X: spatial.bias(m, Q, V)),
        "aba": (lambda Q, V, X: b.aba(Q, V, X), lambda Q, V, X: spatial.aba(m, Q, V, X)),
        "forward_dynamics": (lambda Q, V, X: b.forward_dynamics(Q, V, X),
                             lambda Q, V, X: spatial.forward_dynamics(m, Q, V, X)),
        "crba": (lambda Q, V, X: b.crba(Q), lambda Q, V, X: spatial.crba(m, Q)),
    }


@pytest.fixture(params=KINDS)
def batch_states(request):
    m = kind_model(request.param)
    b = spatial.Batch(m)
    # more than three registers of states and a tail: every lane position, full and partial groups
    return request.param, b, states(m, 3 * b.lanes + 3, seed=707)


def test_agrees_with_the_functions(batch_states):
    key, b, s = batch_states
    assert b.lanes >= 1 and b.threads == 1 and b.model is not None
    for name, (lanes, single) in methods(b).items():
        got, ref = lanes(s.Q, s.V, s.T), single(s.Q, s.V, s.T)
        assert got.shape == ref.shape and got.dtype == np.float64, f"{key} {name}: {got.shape} {got.dtype}"
        for k in range(len(ref)):  # each state at its own scale (q'' of ABA spans orders of magnitude)
            assert_close(got[k], ref[k], rtol=1e-12, err_msg=f"{key} {name} state {k}")
        if name == "crba":
            assert np.array_equal(got, np.swapaxes(got, 1, 2)), f"{key}: Batch.crba not exactly symmetric"


def test_rnea_round_trip_through_aba(batch_states):
    key, b, s = batch_states
    tau = b.rnea(s.Q, s.V, s.A)
    for name, qdd in (("aba", b.aba(s.Q, s.V, tau)), ("forward_dynamics", b.forward_dynamics(s.Q, s.V, tau))):
        for k in range(len(qdd)):
            assert_close(qdd[k], s.A[k], rtol=1e-8, err_msg=f"{key} {name}(rnea(a)) != a, state {k}")


def test_a_state_does_not_depend_on_the_batch_or_the_threads(batch_states):
    key, b, s = batch_states
    two = spatial.Batch(b.model, threads=2)
    assert two.threads == 2
    for name, (lanes, _) in methods(b).items():
        full = lanes(s.Q, s.V, s.T)
        for n in range(1, 2 * b.lanes + 2):
            part = lanes(s.Q[:n], s.V[:n], s.T[:n])
            assert np.array_equal(part, full[:n]), f"{key} {name}: first {n} states differ from the whole batch's"
        shifted = lanes(s.Q[1:], s.V[1:], s.T[1:])  # every state in another lane
        assert np.array_equal(shifted, full[1:]), f"{key} {name}: a state's result depends on its lane"
        one = lanes(s.Q[2], s.V[2], s.T[2])
        assert np.array_equal(one, full[2]), f"{key} {name}: (n,) input != its row in the batch"
        assert np.array_equal(methods(two)[name][0](s.Q, s.V, s.T), full), f"{key} {name}: threads=2 != threads=1"


def test_nan_stays_in_its_state(batch_states):
    key, b, s = batch_states
    k = b.lanes + 1  # inside the second register, with clean states beside it
    Q, V, T = s.Q.copy(), s.V.copy(), s.T.copy()
    Q[k, -1] = np.nan
    V[k, -1] = np.inf
    for name, (lanes, _) in methods(b).items():
        clean, dirty = lanes(s.Q, s.V, s.T), lanes(Q, V, T)
        others = np.arange(len(Q)) != k
        assert np.array_equal(dirty[others], clean[others]), f"{key} {name}: a NaN reached another state"
        if name in ("rnea", "bias", "aba", "forward_dynamics"):  # the others read q only, where the NaN may reach
            # no entry
            assert not np.all(np.isfinite(dirty[k])), f"{key} {name}: the NaN state came out finite"


def test_shapes_and_broadcasting(stance_gen):
    m = stance_gen
    b = spatial.Batch(m)
    s = states(m, 6, seed=9)
    assert b.rnea(s.Q[0], s.V[0], s.A[0]).shape == (m.nv,)
    assert b.crba(s.Q[0]).shape == (m.nv, m.nv)
    assert b.crba(s.Q).shape == (6, m.nv, m.nv)
    assert b.frame_placement(s.Q[0], 0).shape == (4, 4)
    assert b.frame_placement(s.Q, 0).shape == (6, 4, 4)
    assert b.frame_jacobian(s.Q, m.body_names[2]).shape == (6, 6, m.nv)
    assert np.array_equal(b.frame_placement(s.Q, 0)[:, 3], np.tile([0.0, 0.0, 0.0, 1.0], (6, 1)))
    assert b.rnea(s.Q[:0], s.V[:0], s.A[:0]).shape == (0, m.nv)
    # an (nv,) argument is shared by every state, as for the functions
    shared = b.rnea(s.Q, s.V[1], s.A)
    assert np.array_equal(shared, b.rnea(s.Q, np.tile(s.V[1], (6, 1)), s.A))
    # F-ordered, strided, float32 and list inputs are converted (float32: to the same float64 values)
    ref = b.gravity(s.Q)
    assert np.array_equal(b.gravity(np.asfortranarray(s.Q)), ref)
    assert np.array_equal(b.gravity(np.repeat(s.Q, 2, axis=0)[::2]), ref)
    assert np.array_equal(b.gravity(s.Q.astype(np.float32)), b.gravity(s.Q.astype(np.float32).astype(np.float64)))
    assert np.array_equal(b.gravity(s.Q.tolist()), ref)
    out = b.gravity(s.Q)
    assert out.flags.c_contiguous and out.flags.owndata


def test_errors(stance_gen):
    m = stance_gen
    b = spatial.Batch(m)
    s = states(m, 4, seed=3)
    with pytest.raises(ValueError, match=r"Batch\.rnea: argument 'v' has 3 states, an earlier argument 4"):
        b.rnea(s.Q, s.V[:3], s.A)
    with pytest.raises(ValueError, match=r"Batch\.crba: argument 'q' has shape \(4, 20\).*nq = 21"):
        b.crba(s.Q[:, :20])
    with pytest.raises(TypeError, match=r"Batch\.gravity: argument 'q' must be an array of real numbers"):
        b.gravity([["a"] * m.nv])
    fl = spatial.Batch(get_model("floating_gen"))
    with pytest.raises(ValueError, match=r"Batch\.rnea: argument 'q' has shape \(4, 27\).*nq = 28"):
        fl.rnea(np.zeros((4, 27)), np.zeros((4, 27)), np.zeros((4, 27)))
    with pytest.raises(KeyError, match=r"Batch\.frame_placement: .*'no_such_frame'"):
        b.frame_placement(s.Q, "no_such_frame")
    with pytest.raises(ValueError, match=r"Batch\.frame_jacobian: 'frame' must be a frame or body name"):
        b.frame_jacobian(s.Q, len(m.frame_names))
    with pytest.raises(ValueError, match=r"Batch\.frame_jacobian: reference 'body' is not one of"):
        b.frame_jacobian(s.Q, 0, "body")
    with pytest.raises(ValueError, match="threads"):
        spatial.Batch(m, threads=-1)
