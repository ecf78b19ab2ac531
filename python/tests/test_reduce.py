"""Model reduction from Python (lock_joints, keep_joints, keep_branches): a reduced model gives the kept joints'
torques, inertia and accelerations of the full model held at the locked positions; names, limits and source_joints
follow; floating models and bad names are refused."""

import numpy as np
import pytest

import spatial

HEAD_WRISTS = {"CHEST_H_PAN_joint": 0.0, "H_PAN_H_TILT_joint": 0.0, "H_TILT_H_ROLL_joint": 0.0,
               "R_EB_R_WR_joint": 0.0, "L_EB_L_WR_joint": 0.0}


def stance_models():
    return [spatial.hoap3_stance_right(),
            spatial.load_urdf(spatial.urdf_path("hoap3.urdf"), root="R_SOLE", lock=HEAD_WRISTS)]


def check_reduced(full, red, q, rng):
    """Kept joints move (v, a random); the others are still at q: the reduced model must give the full model's
    torques of the kept joints, and the kept block of H."""
    keep = red.source_joints
    assert [full.joint_names[j] for j in keep] == red.joint_names
    assert np.array_equal(red.lower, full.lower[keep]) and np.array_equal(red.upper, full.upper[keep])
    v, a = np.zeros(full.nv), np.zeros(full.nv)
    v[keep], a[keep] = rng.standard_normal(len(keep)), rng.standard_normal(len(keep))
    tau = spatial.rnea(full, q, v, a)
    tau_r = spatial.rnea(red, q[keep], v[keep], a[keep])
    np.testing.assert_allclose(tau_r, tau[keep], rtol=0, atol=1e-12 * max(1.0, np.abs(tau).max()))
    H = spatial.crba(full, q)
    np.testing.assert_allclose(spatial.crba(red, q[keep]), H[np.ix_(keep, keep)], rtol=0, atol=1e-13)
    # the reduced model's forward dynamics undo its inverse dynamics
    np.testing.assert_allclose(spatial.aba(red, q[keep], v[keep], tau_r), a[keep], rtol=0, atol=1e-9)


@pytest.mark.parametrize("full", stance_models(), ids=["compile_time", "run_time"])
def test_lock_joints(full):
    rng = np.random.default_rng(1)
    q = spatial.random_configuration(full, seed=2)
    locked = {full.joint_names[k]: q[k] for k in (3, 8, 17)}
    red = spatial.lock_joints(full, locked)
    assert red.njoints == full.njoints - 3 and not red.compile_time and not red.floating
    assert not set(locked) & set(red.joint_names)
    check_reduced(full, red, q, rng)


@pytest.mark.parametrize("full", stance_models(), ids=["compile_time", "run_time"])
def test_keep_joints_and_branches(full):
    rng = np.random.default_rng(3)
    q = spatial.random_configuration(full, seed=4)
    moving = full.joint_names[15:18]
    red = spatial.keep_joints(full, moving, q)
    assert red.joint_names == moving and red.source_joints == [15, 16, 17]
    check_reduced(full, red, q, rng)
    # the subtree of body 15 (a branch off the chest) moves, the rest is held at q
    branch = spatial.keep_branches(full, [full.body_names[15]], q)
    assert branch.source_joints[0] == 15 and branch.njoints >= 2
    check_reduced(full, branch, q, rng)


def test_reduced_twice_maps_to_its_parent():
    full = spatial.hoap3_stance_right()
    q = spatial.random_configuration(full, seed=6)
    red = spatial.lock_joints(full, {full.joint_names[0]: q[0]})
    red2 = spatial.lock_joints(red, {red.joint_names[0]: q[1]})
    assert red2.source_joints == list(range(red.njoints))[1:]
    check_reduced(red, red2, q[red.source_joints], np.random.default_rng(7))


def test_errors():
    full = spatial.hoap3_stance_right()
    q = np.zeros(full.nq)
    with pytest.raises(spatial.ModelError, match="did you mean"):
        spatial.lock_joints(full, {full.joint_names[0] + "x": 0.0})
    with pytest.raises(spatial.ModelError):
        spatial.lock_joints(full, {n: 0.0 for n in full.joint_names})  # nothing would move
    with pytest.raises(spatial.ModelError, match="did you mean"):
        spatial.keep_branches(full, [full.body_names[3] + "x"], q)
    with pytest.raises(ValueError, match="q"):
        spatial.keep_joints(full, full.joint_names[:2], np.zeros(full.nq - 1))
    with pytest.raises(spatial.ModelError, match="fixed-base"):
        spatial.lock_joints(spatial.hoap3_floating(), {"R_KN_R_AFE_joint": 0.0})
