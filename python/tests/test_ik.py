"""spatial.IkSolver: targets made by forward kinematics are reached, limits hold, failures are reported, batches on
threads equal single solves, compile-time and run-time models agree, bad input is refused."""

import numpy as np
import pytest

import spatial

HEAD_WRISTS = {"CHEST_H_PAN_joint": 0.0, "H_PAN_H_TILT_joint": 0.0, "H_TILT_H_ROLL_joint": 0.0,
               "R_EB_R_WR_joint": 0.0, "L_EB_L_WR_joint": 0.0}


def floating_models():
    return [spatial.hoap3_floating(),
            spatial.load_urdf(spatial.urdf_path("hoap3.urdf"), floating=True, lock=HEAD_WRISTS)]


def pose(model, q, frame):
    T = spatial.frame_placement(model, q, frame)
    return T[:3, 3], T[:3, :3]


@pytest.mark.parametrize("model", floating_models(), ids=["compile_time", "run_time"])
def test_reaches_poses_made_by_forward_kinematics(model):
    rng = np.random.default_rng(4)
    for seed in range(3):
        target = spatial.random_configuration(model, seed=seed, position_range=0.2)
        tasks = [spatial.ik_pose(f, *pose(model, target, f)) for f in ("R_SOLE", "L_SOLE")]
        tasks.append(spatial.ik_center_of_mass(spatial.center_of_mass(model, target)))
        ik = spatial.IkSolver(model, tasks)
        q0 = spatial.integrate(model, target, 0.05 * rng.standard_normal(model.nv))
        q, st = ik.solve(q0)
        assert st.converged and st.reason == "converged", st
        assert st.residual <= 1e-12
        for f in ("R_SOLE", "L_SOLE"):
            p, R = pose(model, q, f)
            p0, R0 = pose(model, target, f)
            assert np.abs(p - p0).max() < 1e-11 and np.abs(R - R0).max() < 1e-11
        assert np.abs(spatial.center_of_mass(model, q) - spatial.center_of_mass(model, target)).max() < 1e-11
        assert abs(np.linalg.norm(q[3:7]) - 1) < 1e-12  # on the manifold
        norm, r = ik.residual(q)
        assert r.shape == (ik.rows,) and norm == pytest.approx(np.linalg.norm(r), abs=1e-18)


def test_fixed_base_position_and_orientation_tasks():
    model = spatial.hoap3_stance_right()
    target = spatial.random_configuration(model, seed=11)
    p, R = pose(model, target, "L_SOLE")
    ik = spatial.IkSolver(model, [spatial.ik_position("L_SOLE", p), spatial.ik_orientation("L_SOLE", R)])
    q, st = ik.solve(np.zeros(model.nq))
    assert st.converged, st
    p1, R1 = pose(model, q, "L_SOLE")
    assert np.abs(p1 - p).max() < 1e-11 and np.abs(R1 - R).max() < 1e-11


def test_limits_hold_and_default_to_the_model_limits():
    model = spatial.hoap3_stance_right()
    # A target far out of reach pulls every joint to its limits.
    ik = spatial.IkSolver(model, [spatial.ik_position("L_SOLE", [2.0, 2.0, 2.0])], max_iterations=50)
    q, st = ik.solve(np.zeros(model.nq))
    assert not st.converged and st.reason in ("stalled", "max_iterations")
    assert np.isfinite(st.residual)
    assert np.all(q >= model.lower - 1e-15) and np.all(q <= model.upper + 1e-15)
    # Without limits the same solve leaves them.
    free = spatial.IkSolver(model, [spatial.ik_position("L_SOLE", [2.0, 2.0, 2.0])], max_iterations=50,
                            lower=np.full(model.njoints, -np.inf), upper=np.full(model.njoints, np.inf))
    qf, _ = free.solve(np.zeros(model.nq))
    assert np.any(qf < model.lower) or np.any(qf > model.upper)


def test_active_coordinates_and_axes():
    model = spatial.hoap3_stance_right()
    target = spatial.random_configuration(model, seed=5)
    p, _ = pose(model, target, "L_SOLE")
    active = [model.joint_index(n) for n in model.joint_names[:6]]
    ik = spatial.IkSolver(model, [spatial.ik_position("L_SOLE", p, axes=(0, 0, 1))], active=active)
    q0 = np.zeros(model.nq)
    q, st = ik.solve(q0)
    assert st.converged, st
    assert pose(model, q, "L_SOLE")[0][2] == pytest.approx(p[2], abs=1e-11)
    frozen = [i for i in range(model.nv) if i not in active]
    # Inactive joints keep their start, clamped into the limits (a knee's lower limit is 0.0873 rad).
    assert np.array_equal(q[frozen], np.clip(q0, model.lower, model.upper)[frozen])
    assert np.any(q[frozen] != q0[frozen])


def test_batch_of_starts_on_threads_equals_single_solves():
    model = spatial.hoap3_floating()
    target = spatial.random_configuration(model, seed=3, position_range=0.2)
    tasks = [spatial.ik_pose(f, *pose(model, target, f)) for f in ("R_SOLE", "L_SOLE")]
    ik = spatial.IkSolver(model, tasks)
    starts = np.stack([spatial.integrate(model, target, 0.05 * np.random.default_rng(k).standard_normal(model.nv))
                       for k in range(9)])  # two threads get at least 4 starts each
    Q1, st1 = ik.solve(starts)
    Q2, st2 = ik.solve(starts, threads=2)
    assert Q1.shape == (9, model.nq) and len(st1) == 9
    assert np.array_equal(Q1, Q2) and st1 == st2
    for k in range(9):
        qk, sk = ik.solve(starts[k])
        assert np.array_equal(qk, Q1[k]) and sk == st1[k]


def test_set_task_moves_the_target():
    model = spatial.hoap3_floating()
    target = spatial.random_configuration(model, seed=8, position_range=0.2)
    p, R = pose(model, target, "L_SOLE")
    ik = spatial.IkSolver(model, [spatial.ik_pose("L_SOLE", p, R)])
    q, st = ik.solve(target)
    assert st.converged and st.iterations <= 1
    ik.set_task(0, spatial.ik_pose("L_SOLE", p + [0.01, 0, 0], R))
    q, st = ik.solve(target)
    assert st.converged and np.abs(pose(model, q, "L_SOLE")[0] - p - [0.01, 0, 0]).max() < 1e-11
    with pytest.raises(ValueError, match="only its target"):
        ik.set_task(0, spatial.ik_position("L_SOLE", p))


def test_non_finite_start_is_reported_not_raised():
    model = spatial.hoap3_stance_right()
    ik = spatial.IkSolver(model, [spatial.ik_position("L_SOLE", [np.nan, 0, 0])])
    q, st = ik.solve(np.zeros(model.nq))
    assert not st.converged and st.reason == "non_finite"


def test_errors():
    model = spatial.hoap3_stance_right()
    with pytest.raises(KeyError, match="did you mean 'L_SOLE'"):
        spatial.IkSolver(model, [spatial.ik_position("L_SOLEE", [0, 0, 0])])
    with pytest.raises(ValueError, match="limits"):
        spatial.IkSolver(model, [spatial.ik_position("L_SOLE", [0, 0, 0])], lower=np.zeros(3))
    with pytest.raises(ValueError, match="active"):
        spatial.IkSolver(model, [spatial.ik_position("L_SOLE", [0, 0, 0])], active=[99])
    with pytest.raises(ValueError, match="axes"):
        spatial.ik_position("L_SOLE", [0, 0, 0], axes=(1, 1))
    ik = spatial.IkSolver(model, [spatial.ik_position("L_SOLE", [0, 0, 0])])
    with pytest.raises(ValueError, match="q0"):
        ik.solve(np.zeros(model.nq + 1))
