"""Errors: wrong sizes (ValueError naming the function, the argument and the expected size), non-real dtypes
(TypeError), check=True on NaN/inf (ValueError naming the argument, state and entry), bad URDF files and options
(spatial.ModelError, a ValueError, naming the file; "did you mean"), unknown frames and names, and a battery of bad
calls in a child process that must not crash the interpreter."""

import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import spatial
from conftest import LOCKS, MODEL_KEYS, get_model, hoap3_path, states


def names_argument(msg, arg):
    """The message names argument `arg`: quoted, or after the word "argument", or followed by has/must/:/=."""
    a = re.escape(arg)
    return re.search(rf"(['\"`]{a}['\"`]|argument {a}\b|\b{a}\s*(has|must|should|is|:|=|\[|\())", msg) is not None


def signature_calls(m, frame):
    """name -> (function(q, v, x, q1), [(argument, position in (q, v, x, q1), size)])."""
    nq, nv = m.nq, m.nv
    return {
        "rnea": (lambda q, v, x, q1: spatial.rnea(m, q, v, x), [("q", 0, nq), ("v", 1, nv), ("a", 2, nv)]),
        "gravity": (lambda q, v, x, q1: spatial.gravity(m, q), [("q", 0, nq)]),
        "bias": (lambda q, v, x, q1: spatial.bias(m, q, v), [("q", 0, nq), ("v", 1, nv)]),
        "crba": (lambda q, v, x, q1: spatial.crba(m, q), [("q", 0, nq)]),
        "aba": (lambda q, v, x, q1: spatial.aba(m, q, v, x), [("q", 0, nq), ("v", 1, nv), ("tau", 2, nv)]),
        "forward_dynamics": (lambda q, v, x, q1: spatial.forward_dynamics(m, q, v, x),
                             [("q", 0, nq), ("v", 1, nv), ("tau", 2, nv)]),
        "kinetic_energy": (lambda q, v, x, q1: spatial.kinetic_energy(m, q, v), [("q", 0, nq), ("v", 1, nv)]),
        "potential_energy": (lambda q, v, x, q1: spatial.potential_energy(m, q), [("q", 0, nq)]),
        "frame_placement": (lambda q, v, x, q1: spatial.frame_placement(m, q, frame), [("q", 0, nq)]),
        "frame_jacobian": (lambda q, v, x, q1: spatial.frame_jacobian(m, q, frame), [("q", 0, nq)]),
        "frame_velocity": (lambda q, v, x, q1: spatial.frame_velocity(m, q, v, frame), [("q", 0, nq), ("v", 1, nv)]),
        "frame_acceleration": (lambda q, v, x, q1: spatial.frame_acceleration(m, q, v, x, frame),
                               [("q", 0, nq), ("v", 1, nv), ("a", 2, nv)]),
        "frame_classical_acceleration": (lambda q, v, x, q1: spatial.frame_classical_acceleration(m, q, v, x, frame),
                                         [("q", 0, nq), ("v", 1, nv), ("a", 2, nv)]),
        "frame_jacobian_time_variation": (lambda q, v, x, q1: spatial.frame_jacobian_time_variation(m, q, v, frame),
                                          [("q", 0, nq), ("v", 1, nv)]),
        "center_of_mass": (lambda q, v, x, q1: spatial.center_of_mass(m, q), [("q", 0, nq)]),
        "com_jacobian": (lambda q, v, x, q1: spatial.com_jacobian(m, q), [("q", 0, nq)]),
        "centroidal_momentum_matrix": (lambda q, v, x, q1: spatial.centroidal_momentum_matrix(m, q), [("q", 0, nq)]),
        "centroidal_momentum": (lambda q, v, x, q1: spatial.centroidal_momentum(m, q, v), [("q", 0, nq), ("v", 1, nv)]),
        "centroidal_momentum_time_variation": (
            lambda q, v, x, q1: spatial.centroidal_momentum_time_variation(m, q, v, x),
            [("q", 0, nq), ("v", 1, nv), ("a", 2, nv)]),
        "integrate": (lambda q, v, x, q1: spatial.integrate(m, q, v), [("q", 0, nq), ("v", 1, nv)]),
        "difference": (lambda q, v, x, q1: spatial.difference(m, q, q1), [("q0", 0, nq), ("q1", 3, nq)]),
        "normalize": (lambda q, v, x, q1: spatial.normalize(m, q), [("q", 0, nq)]),
        "rnea_derivatives": (lambda q, v, x, q1: spatial.rnea_derivatives(m, q, v, x),
                             [("q", 0, nq), ("v", 1, nv), ("a", 2, nv)]),
        "aba_derivatives": (lambda q, v, x, q1: spatial.aba_derivatives(m, q, v, x),
                            [("q", 0, nq), ("v", 1, nv), ("tau", 2, nv)]),
        "inverse_inertia": (lambda q, v, x, q1: spatial.inverse_inertia(m, q), [("q", 0, nq)]),
    }


FUNCS = list(signature_calls(type("M", (), {"nq": 1, "nv": 1})(), "f").keys())


def frame_for(m):
    return "R_SOLE" if m.floating else "L_SOLE"


@pytest.fixture(params=["stance_gen", "floating_urdf"])
def model(request):
    return get_model(request.param)


@pytest.mark.parametrize("name", FUNCS)
def test_wrong_size(model, name):
    m = model
    s = states(m, 2, seed=401)
    good = [s.Q[0], s.V[0], s.T[0], s.Q[1]]
    f, args = signature_calls(m, frame_for(m))[name]
    f(*good)  # the good call works
    for arg, pos, size in args:
        for bad_size in (size - 1, size + 1):
            bad = list(good)
            bad[pos] = np.zeros(bad_size)
            with pytest.raises(ValueError) as e:
                f(*bad)
            msg = str(e.value)
            assert name in msg, f"{name}: message does not name the function: {msg!r}"
            assert names_argument(msg, arg), f"{name}: message does not name argument {arg!r}: {msg!r}"
            assert str(size) in msg, f"{name}: message does not give the expected size {size}: {msg!r}"
        # the same in a batch
        bad = [np.atleast_2d(x).repeat(2, axis=0) for x in good]
        bad[pos] = np.zeros((2, size + 2))
        with pytest.raises(ValueError) as e:
            f(*bad)
        assert name in str(e.value) and names_argument(str(e.value), arg), str(e.value)
        # too many dimensions
        bad = list(good)
        bad[pos] = np.zeros((2, 2, size))
        with pytest.raises(ValueError) as e:
            f(*bad)
        assert name in str(e.value), str(e.value)


def test_batch_size_mismatch(model):
    m = model
    s = states(m, 3, seed=402)
    with pytest.raises(ValueError) as e:
        spatial.rnea(m, s.Q, s.V[:2], s.A)
    assert "rnea" in str(e.value)
    with pytest.raises(ValueError):
        spatial.difference(m, s.Q, s.Q[:2])


def test_fext_wrong_shape(model):
    m = model
    s = states(m, 2, seed=403)
    nb = m.njoints + (1 if m.floating else 0)
    for shape in [(nb - 1, 6), (nb, 5), (nb * 6,), (2, nb + 1, 6)]:
        with pytest.raises(ValueError) as e:
            spatial.rnea(m, s.Q[0], s.V[0], s.A[0], fext=np.zeros(shape))
        assert "rnea" in str(e.value) and names_argument(str(e.value), "fext"), str(e.value)
    with pytest.raises(ValueError) as e:
        spatial.aba(m, s.Q, s.V, s.T, fext=np.zeros((3, nb, 6)))  # 3 force sets for 2 states
    assert "aba" in str(e.value)


@pytest.mark.parametrize("bad", ["complex", "complex_list", "str", "str_list", "object", "none"])
def test_non_real_dtype(model, bad):
    m = model
    s = states(m, 1, seed=404)
    q = s.Q[0]
    values = {
        "complex": q.astype(complex),
        "complex_list": [complex(x, 1) for x in q],
        "str": np.array(["0.1"] * m.nq),
        "str_list": ["a"] * m.nq,
        "object": np.array([object()] * m.nq, dtype=object),
        "none": None,
    }
    with pytest.raises(TypeError):
        spatial.rnea(m, values[bad], s.V[0], s.A[0])
    with pytest.raises(TypeError):
        spatial.crba(m, values[bad])
    with pytest.raises(TypeError):
        spatial.aba(m, q, s.V[0], values[bad] if bad != "str" and bad != "str_list" else ["x"] * m.nv)


def test_not_a_model():
    q = np.zeros(21)
    with pytest.raises(TypeError):
        spatial.rnea("hoap3", q, q, q)
    with pytest.raises(TypeError):
        spatial.crba(None, q)


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_check_nonfinite(model, value):
    m = model
    s = states(m, 3, seed=405)
    cases = [
        ("rnea", lambda Q, V, X: spatial.rnea(m, Q, V, X, check=True)),
        ("aba", lambda Q, V, X: spatial.aba(m, Q, V, X, check=True)),
        ("forward_dynamics", lambda Q, V, X: spatial.forward_dynamics(m, Q, V, X, check=True)),
    ]
    for name, f in cases:
        f(s.Q, s.V, s.T)  # good input passes
        for pos, arg in ((0, "q"), (1, "v"), (2, "a" if name == "rnea" else "tau")):
            X = [s.Q.copy(), s.V.copy(), s.T.copy()]
            entry = 8 if pos == 0 else 4
            X[pos][2, entry] = value  # state 2, entry 8 / 4
            with pytest.raises(ValueError) as e:
                f(*X)
            msg = str(e.value)
            assert names_argument(msg, arg), f"{name}: {msg!r} does not name {arg!r}"
            assert "2" in msg and str(entry) in msg, f"{name}: {msg!r} does not name state 2 / entry {entry}"
            # single state
            with pytest.raises(ValueError) as e:
                f(X[0][2], X[1][2], X[2][2])
            assert names_argument(str(e.value), arg), str(e.value)
    for name, f in [("crba", lambda Q: spatial.crba(m, Q, check=True)),
                    ("gravity", lambda Q: spatial.gravity(m, Q, check=True)),
                    ("frame_jacobian", lambda Q: spatial.frame_jacobian(m, Q, frame_for(m), check=True)),
                    ("center_of_mass", lambda Q: spatial.center_of_mass(m, Q, check=True))]:
        Q = s.Q.copy()
        Q[1, -1] = value
        with pytest.raises(ValueError) as e:
            f(Q)
        assert names_argument(str(e.value), "q"), f"{name}: {str(e.value)!r}"


def test_nonfinite_without_check_propagates(model):
    """Without check=True, NaN propagates by IEEE rules (no exception), and the next good call is unaffected."""
    m = model
    s = states(m, 2, seed=406)
    good = spatial.rnea(m, s.Q, s.V, s.A)
    Q = s.Q.copy()
    Q[0, -1] = np.nan
    r = spatial.rnea(m, Q, s.V, s.A)
    assert np.isnan(r[0]).any()
    assert np.array_equal(r[1], good[1])
    assert np.array_equal(spatial.rnea(m, s.Q, s.V, s.A), good)
    H = spatial.crba(m, Q)
    assert np.isnan(H[0]).any()
    assert np.array_equal(spatial.crba(m, s.Q[0]), spatial.crba(m, s.Q)[0])


# ---------------------------------------------------------------------------------------------------------------
# Models and names


def test_model_error_is_value_error():
    assert issubclass(spatial.ModelError, ValueError)


def test_bad_urdf_path(tmp_path):
    missing = str(tmp_path / "no_such_robot.urdf")
    with pytest.raises(spatial.ModelError) as e:
        spatial.load_urdf(missing)
    assert "no_such_robot.urdf" in str(e.value)
    with pytest.raises(ValueError):  # ModelError is a ValueError
        spatial.load_urdf(missing)


@pytest.mark.parametrize("content", [
    "this is not xml",
    "<robot name='r'><link name='a'/><joint name='j' type='revolute'><parent link='a'/><child link='b'/>"
    "<axis xyz='0 0 1'/><limit lower='0' upper='1' effort='1' velocity='1'/></joint></robot>",  # no link b
    "<robot name='r'><link name='a'><inertial><mass value='-1'/><inertia ixx='1' ixy='0' ixz='0' iyy='1' iyz='0' "
    "izz='1'/></inertial></link></robot>",  # negative mass
    "",
])
def test_bad_urdf_content(tmp_path, content):
    path = tmp_path / "broken_robot.urdf"
    path.write_text(content)
    with pytest.raises(spatial.ModelError) as e:
        spatial.load_urdf(str(path))
    assert "broken_robot.urdf" in str(e.value), str(e.value)
    with pytest.raises(spatial.ModelError) as e:
        spatial.load_urdf_string(content, name="my_string_robot")
    assert "my_string_robot" in str(e.value), str(e.value)


def test_unknown_lock_joint():
    with pytest.raises(spatial.ModelError) as e:
        spatial.load_urdf(hoap3_path(), lock={"R_EB_R_WR_jiont": 0.0})
    msg = str(e.value)
    assert "did you mean" in msg and "R_EB_R_WR_joint" in msg, msg
    assert "hoap3.urdf" in msg, msg


def test_unknown_root_and_subtree():
    with pytest.raises(spatial.ModelError) as e:
        spatial.load_urdf(hoap3_path(), root="R_SOEL")
    assert "R_SOEL" in str(e.value) and "R_SOLE" in str(e.value), str(e.value)
    with pytest.raises(spatial.ModelError) as e:
        spatial.load_urdf(hoap3_path(), subtree="CHESTT")
    assert "CHESTT" in str(e.value), str(e.value)


def test_bad_gravity_option():
    with pytest.raises((ValueError, TypeError)):
        spatial.load_urdf(hoap3_path(), gravity=[0, -9.81])
    with pytest.raises((ValueError, TypeError)):
        spatial.load_urdf(hoap3_path(), gravity=[0, 0, float("nan")])


BAD_INERTIA = """<robot name="tri">
  <link name="base"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="arm"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.01"/></inertial></link>
</robot>"""


def test_strict_inertia():
    m = spatial.load_urdf_string(BAD_INERTIA, name="tri.urdf")
    assert m.warnings and any("arm" in w for w in m.warnings), m.warnings
    with pytest.raises(spatial.ModelError) as e:
        spatial.load_urdf_string(BAD_INERTIA, name="tri.urdf", strict_inertia=True)
    assert "arm" in str(e.value)
    good = spatial.load_urdf(hoap3_path(), lock=dict(LOCKS))
    assert isinstance(good.warnings, list)


@pytest.mark.parametrize("key", MODEL_KEYS)
def test_unknown_names(key):
    m = get_model(key)
    q = spatial.neutral(m)
    for lookup in (m.frame_index, m.joint_index, m.body_index):
        with pytest.raises(KeyError):
            lookup("NO_SUCH_NAME")
    with pytest.raises(KeyError) as e:
        m.frame_index("L_SOLEE")
    assert "did you mean" in str(e.value) and "L_SOLE" in str(e.value), str(e.value)
    with pytest.raises(KeyError) as e:
        m.joint_index("WAIST_CHEST_jiont")
    assert "did you mean" in str(e.value) and "WAIST_CHEST_joint" in str(e.value), str(e.value)
    for f in (lambda: spatial.frame_placement(m, q, "L_SOLEE"),
              lambda: spatial.frame_jacobian(m, q, "L_SOLEE"),
              lambda: spatial.frame_velocity(m, q, np.zeros(m.nv), "L_SOLEE")):
        with pytest.raises((KeyError, ValueError)) as e:
            f()
        assert "L_SOLEE" in str(e.value)
    for index in (len(m.frame_names), 10_000, -10_000):
        with pytest.raises((IndexError, KeyError, ValueError)):
            spatial.frame_placement(m, q, index)
    with pytest.raises(ValueError) as e:
        spatial.frame_jacobian(m, q, "L_SOLE", reference="global")
    assert "global" in str(e.value)
    with pytest.raises(ValueError):
        spatial.frame_velocity(m, q, np.zeros(m.nv), "L_SOLE", reference="LOCAL_WORLD")


def test_bad_urdf_path_name():
    with pytest.raises((ValueError, KeyError, FileNotFoundError)):
        spatial.urdf_path("no_such_robot.urdf")


# ---------------------------------------------------------------------------------------------------------------
# Nothing crashes


CRASH_SCRIPT = textwrap.dedent(r"""
    import numpy as np, spatial
    locks = %(locks)r
    path = spatial.urdf_path("hoap3.urdf")
    models = [spatial.hoap3_stance_right(), spatial.hoap3_floating(),
              spatial.load_urdf(path, root="R_SOLE", lock=locks), spatial.load_urdf(path, floating=True, lock=locks),
              spatial.load_urdf(path)]  # the last one: wrists unlocked, massless joints (H singular)
    bad_arrays = [None, [], [[]], np.zeros(0), np.zeros(1000), np.zeros((3, 0)), np.full(28, np.nan),
                  np.full(28, np.inf), np.full(27, 1e308), np.zeros((2, 2, 2)), "abc", 3.0, np.zeros(21, dtype=complex),
                  np.array([object()] * 21), np.zeros((1, 28)), np.zeros((0, 27)), np.zeros(28, dtype=np.float16)]
    funcs = ["rnea", "gravity", "bias", "crba", "aba", "forward_dynamics", "kinetic_energy", "potential_energy",
             "center_of_mass", "com_jacobian", "centroidal_momentum_matrix", "centroidal_momentum", "integrate",
             "difference", "normalize", "rnea_derivatives", "aba_derivatives", "inverse_inertia"]
    count = 0
    for m in models:
        good = [spatial.neutral(m), np.ones(m.nv), np.ones(m.nv)]
        # massless joints: singular H, must not crash (inf/nan or an error)
        for f in ("aba", "forward_dynamics", "inverse_inertia", "aba_derivatives"):
            try:
                getattr(spatial, f)(m, *good[: {"inverse_inertia": 1}.get(f, 3)])
            except Exception:
                pass
        for name in funcs:
            f = getattr(spatial, name)
            for bad in bad_arrays:
                for pos in range(3):
                    args = list(good)
                    args[pos] = bad
                    for n in range(pos + 1, 4):
                        for kw in ({}, {"check": True}, {"threads": 2}):
                            try:
                                f(m, *args[:n], **kw)
                            except Exception:
                                pass
                            count += 1
        q = spatial.neutral(m)
        for frame in ["", "x" * 1000, -1, 10**9, 2**70, None, 1.5, "\0"]:
            for f in (spatial.frame_placement, spatial.frame_jacobian):
                try:
                    f(m, q, frame)
                except Exception:
                    pass
        for fext in [np.zeros((0, 6)), np.zeros((100, 6)), np.zeros(6), "x", np.full((m.njoints + 1, 6), np.nan)]:
            try:
                spatial.rnea(m, q, good[1], good[2], fext=fext)
            except Exception:
                pass
        for dyn in (spatial.Dyn(0), spatial.Dyn.Static, spatial.Dyn(8), spatial.Dyn(255), 7, -1, None, "x", 1.5):
            for f in (spatial.rnea, spatial.aba, spatial.forward_dynamics):
                for v in (good[1], None, np.full(m.nv, np.nan)):
                    for x in (good[2], None):
                        for fext in (None, np.zeros((m.njoints + (1 if m.floating else 0), 6))):
                            try:
                                if fext is None:
                                    f(m, q, v, x, dyn=dyn)
                                else:
                                    f(m, q, v, x, fext, dyn=dyn)
                            except Exception:
                                pass
        for t in (-1, 0, 1, 1000, 2**40):
            try:
                spatial.rnea(m, np.tile(q, (4, 1)), np.ones((4, m.nv)), np.ones((4, m.nv)), threads=t)
            except Exception:
                pass
        for s in (-1, 2**70, "x"):
            try:
                spatial.random_configuration(m, seed=s)
            except Exception:
                pass
    for xml in ["", "<robot/>", "<robot name='x'>", "\0" * 10,
                "<robot name='r'><link name='a'/><link name='a'/></robot>"]:
        try:
            spatial.load_urdf_string(xml)
        except Exception:
            pass
    for kw in ({"root": ""}, {"subtree": "R_SOLE", "root": "L_SOLE"}, {"lock": {"x": float("nan")}},
               {"lock": {"R_EB_R_WR_joint": float("inf")}}, {"lock": "abc"}, {"gravity": "abc"}):
        try:
            spatial.load_urdf(path, **kw)
        except Exception:
            pass
    for kw in ({"steps": -5}, {"steps": 2**40}, {"length": float("nan")}, {"width": float("inf")}, {"period": -1.0},
               {"double_support": float("nan")}, {"turn": 10.0}, {"swing_height": float("nan")}, {"zmp_model": ""},
               {"first_swing": None}, {"com_height": float("nan")}, {"second_stage": -3}, {"closed_loop": "x"}):
        try:
            spatial.walk(**kw)
        except Exception:
            pass
    print("survived", count)
""")


def test_nothing_crashes():
    script = CRASH_SCRIPT % {"locks": dict(LOCKS)}
    proc = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, f"child process died (status {proc.returncode}): {proc.stderr[-2000:]}"
    assert "survived" in proc.stdout
