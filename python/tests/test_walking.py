"""The walking pattern generator from Python (spatial.walk): against `spatial-dyn walk` (the same C++ code, so the
same numbers up to the compilers' contractions), and on its own: the walk succeeds, the state stays on the manifold,
the feet carry the robot's weight while it stands, the open-loop inverse dynamics needs no root wrench, a run is
deterministic, the gait options act, and bad parameters raise ValueError naming them."""

import json
import os
import subprocess

import numpy as np
import pytest

import spatial

STEPS = 2


@pytest.fixture(scope="module")
def walk2():
    return spatial.walk(steps=STEPS)


def test_walk_vs_cli(dyn, walk2, tmp_path):
    out = tmp_path / "walk"
    proc = subprocess.run([dyn.exe, "walk", "--steps", str(STEPS), "--out", str(out)], capture_output=True, text=True,
                          timeout=120, env={**os.environ, "SPATIAL_PYTHON": "true"})  # no plots
    assert proc.returncode == 0, proc.stderr
    with open(out / "walk.csv") as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(out / "walk.csv", delimiter=",", skiprows=1)
    col = {n: k for k, n in enumerate(header)}
    c, o, names = walk2["closed_loop"], walk2["open_loop"], walk2["joint_names"]
    n = c["t"].shape[0]
    assert data.shape[0] == n

    def cols(*names_):
        return data[:, [col[x] for x in names_]]

    qn = [f"q:floating_base:{k}" for k in ("x", "y", "z", "qx", "qy", "qz", "qw")] + [f"q:{j}" for j in names]
    vn = [f"floating_base:{k}" for k in ("vx", "vy", "vz", "wx", "wy", "wz")] + list(names)
    tol = dict(rtol=0, atol=1e-9)
    np.testing.assert_allclose(c["t"], data[:, 0], **tol)
    np.testing.assert_allclose(c["q"], cols(*qn), **tol)
    np.testing.assert_allclose(c["v"], cols(*[f"qd:{x}" for x in vn]), **tol)
    np.testing.assert_allclose(c["tau"], cols(*[f"tau:{j}" for j in names]), rtol=0, atol=1e-8)
    np.testing.assert_array_equal(c["contact"], cols("contact:left", "contact:right") != 0)
    for f, foot in enumerate(("left", "right")):
        wrench = cols(*[f"F:{foot}:{a}" for a in "xyz"] + [f"M:{foot}:{a}" for a in "xyz"])
        np.testing.assert_allclose(c["wrench"][:, f], wrench, rtol=0, atol=1e-8)
    np.testing.assert_allclose(c["com"], cols("com:x", "com:y", "com:z"), **tol)
    np.testing.assert_allclose(c["pelvis"], cols("pelvis:x", "pelvis:y", "pelvis:z"), **tol)
    np.testing.assert_allclose(c["margin"], data[:, col["margin"]], **tol)
    np.testing.assert_allclose(o["zmp_reference"][:n], cols("zmp_ref:x", "zmp_ref:y"), **tol)
    np.testing.assert_allclose(o["first_stage_zmp"][:n], cols("zmp_ct:x", "zmp_ct:y"), **tol)
    np.testing.assert_allclose(o["first_pass_zmp_multibody"][:n], cols("zmp_mb0:x", "zmp_mb0:y"), **tol)
    np.testing.assert_allclose(o["com"][:n], cols("com_plan:x", "com_plan:y", "com_plan:z"), **tol)
    np.testing.assert_allclose(o["zmp_multibody"][:n], cols("zmp_mb:x", "zmp_mb:y"), **tol)
    summary = json.loads((out / "walk.json").read_text())["closed_loop"]
    cs = walk2["closed_loop_summary"]
    for k in ("walked", "steps_completed", "impacts", "pulls", "slips", "failed_steps"):
        assert cs[k] == summary[k], k
    for k in ("cop_min_margin", "min_normal_force", "max_friction_ratio", "pelvis_final_error"):
        assert cs[k] == pytest.approx(summary[k], rel=1e-6, abs=1e-9), k


def test_walk_succeeds_and_is_physical(walk2):
    m = spatial.hoap3_floating()
    w = walk2
    assert w["joint_names"] == list(m.joint_names)
    c, o = w["closed_loop"], w["open_loop"]
    cs, os_ = w["closed_loop_summary"], w["open_loop_summary"]
    assert cs["walked"] and cs["completed"] and cs["steps_completed"] == STEPS and cs["impacts"] == STEPS
    n = c["t"].shape[0]
    assert c["q"].shape == (n, m.nq) and c["v"].shape == (n, m.nv) and c["tau"].shape == (n, m.njoints)
    assert c["wrench"].shape == (n, 2, 6) and c["contact"].dtype == bool and o["ok"].dtype == bool
    np.testing.assert_allclose(np.diff(c["t"]), w["dt"], rtol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(c["q"][:, 3:7], axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(o["q"][:, 3:7], axis=1), 1.0, atol=1e-12)
    # Standing still at the start: the soles carry the weight (sum of the normal forces = m g within 1 %).
    standing = c["t"] < 0.5
    fz = c["wrench"][standing][:, :, 2].sum(axis=1)
    np.testing.assert_allclose(fz, m.total_mass * 9.81, rtol=0.01)
    # Open loop: every tick's contact split is physical and supplies the whole root wrench.
    assert o["ok"].all() and os_["contact_ok"] == os_["ticks"]
    assert np.abs(o["tau"][:, :6]).max() <= max(os_["root_residual_max"], 1e-9) * (1 + 1e-12)
    assert os_["root_residual_max"] < 1e-6
    # The second stage brings the multibody ZMP closer to the reference than the first pass left it.
    passes = os_["passes"]
    assert len(passes) == 4 and passes[-1]["zmp_error_max"] < passes[0]["zmp_error_max"]
    # Both feet down at the start and the end, one swing at a time in between, the right foot first.
    assert c["contact"][0].all() and c["contact"][-1].all()
    assert not c["contact"].sum(axis=1).min() == 0
    first_lift = np.argmax(~c["contact"].all(axis=1))
    assert c["contact"][first_lift].tolist() == [True, False]
    # The robot moved forward about the plan's length (two half steps: one step length).
    assert c["pelvis"][-1, 0] - c["pelvis"][0, 0] == pytest.approx(0.05, abs=0.01)


def test_walk_options():
    a = spatial.walk(steps=0, closed_loop=False)
    b = spatial.walk(steps=0, closed_loop=False)
    assert "closed_loop" not in a and "closed_loop_summary" not in a
    for k, v in a["open_loop"].items():  # deterministic, bit for bit
        np.testing.assert_array_equal(v, b["open_loop"][k], err_msg=k)
    left = spatial.walk(steps=1, first_swing="left", closed_loop=False)["open_loop"]
    first_lift = np.argmax(~left["contact"].all(axis=1))
    assert left["contact"][first_lift].tolist() == [False, True]
    pend = spatial.walk(steps=1, zmp_model="double_pendulum", second_stage=1)
    assert pend["closed_loop_summary"]["walked"] and len(pend["open_loop_summary"]["passes"]) == 2
    back = spatial.walk(steps=2, length=-0.03, closed_loop=False)["open_loop"]
    assert back["com"][-1, 0] - back["com"][0, 0] == pytest.approx(-0.03, abs=0.005)


@pytest.mark.parametrize("kwargs, match", [
    (dict(steps=-1), "steps must be >= 0"),
    (dict(period=0.0), "period must be finite and > 0"),
    (dict(double_support=1.0), "double_support_ratio must be in"),
    (dict(width=-0.1), "step_width"),
    (dict(zmp_model="lipm"), "zmp_model 'lipm'"),
    (dict(first_swing="up"), "first_swing 'up'"),
    (dict(com_height=0.0), "com_height must be > 0"),
    (dict(second_stage=-1), "second_stage must be >= 0"),
])
def test_walk_errors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        spatial.walk(**kwargs)
