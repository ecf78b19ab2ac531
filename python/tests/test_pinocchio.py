"""Against Pinocchio's Python API on the HOAP-3 URDF, fixed base (rooted at base_link, as Pinocchio's fixed model)
and floating (Pinocchio's free-flyer, the same q, v, tau conventions: README "Floating base"). The head and wrists are
locked at 0 in both (pin.buildReducedModel); joints are matched by name, since the joint orders differ.
RNEA (with and without external forces), CRBA, ABA, H^-1, the derivatives, frame placements, Jacobians, velocities,
accelerations (spatial and classical) and Jacobian time variations in the three reference frames, centre of mass,
centroidal momentum and its rate, and energies (~1e-10)."""

import numpy as np
import pytest

import spatial
from conftest import LOCKS, assert_close, get_model, hoap3_path, states

pin = pytest.importorskip("pinocchio")

REFS = {"local": "LOCAL", "world": "WORLD", "local_world_aligned": "LOCAL_WORLD_ALIGNED"}
TOL = 1e-10


class Pair:
    """Our model and Pinocchio's reduced model of the same robot, with the coordinate maps."""

    def __init__(self, ours, floating):
        path = hoap3_path()
        full = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
        qref = pin.neutral(full)
        lock_ids = []
        for name, angle in LOCKS.items():
            jid = full.getJointId(name)
            assert jid < full.njoints, name
            lock_ids.append(jid)
            qref[full.joints[jid].idx_q] = angle
        self.pm = pin.buildReducedModel(full, lock_ids, qref)
        self.pd = self.pm.createData()
        self.ours = ours
        self.floating = floating
        assert self.pm.nq == ours.nq and self.pm.nv == ours.nv, (self.pm.nq, ours.nq, self.pm.nv, ours.nv)
        off_q, off_v = (7, 6) if floating else (0, 0)
        iq = list(range(off_q))
        iv = list(range(off_v))
        self.joint_ids = []
        for name in ours.joint_names:
            jid = self.pm.getJointId(name)
            assert jid < self.pm.njoints, f"Pinocchio's model has no joint {name}"
            j = self.pm.joints[jid]
            assert j.nq == 1 and j.nv == 1, name
            iq.append(j.idx_q)
            iv.append(j.idx_v)
            self.joint_ids.append(jid)
        if floating:
            assert self.pm.names[1] == "root_joint" and self.pm.joints[1].idx_q == 0 and self.pm.joints[1].idx_v == 0
        self.iq = np.array(iq)  # our coordinate k is Pinocchio's coordinate iq[k]
        self.iv = np.array(iv)
        assert sorted(iq) == list(range(ours.nq)) and sorted(iv) == list(range(ours.nv))

    def q(self, q):
        out = np.zeros(self.pm.nq)
        out[self.iq] = q
        return out

    def v(self, v):
        out = np.zeros(self.pm.nv)
        out[self.iv] = v
        return out

    def vec(self, x):
        """Pinocchio's tangent vector in our order."""
        return np.asarray(x)[self.iv]

    def mat(self, M):
        return np.asarray(M)[np.ix_(self.iv, self.iv)]

    def cols(self, J):
        return np.asarray(J)[:, self.iv]

    def frame(self, name):
        fid = self.pm.getFrameId(name)
        assert fid < len(self.pm.frames), f"Pinocchio's model has no frame {name}"
        return fid


def sym(M):
    """Pinocchio fills the upper triangle of H and H^-1 only."""
    M = np.asarray(M)
    return np.triu(M) + np.triu(M, 1).T


_PAIRS = {}


def get_pair(key):
    if key not in _PAIRS:
        floating = key.startswith("floating")
        _PAIRS[key] = Pair(get_model(key), floating)
    return _PAIRS[key]


KEYS = ["pelvis_urdf", "floating_gen", "floating_urdf"]


@pytest.fixture(params=KEYS, scope="module")
def pair(request):
    return request.param, get_pair(request.param)


def test_model_matches(pair):
    key, p = pair
    m = p.ours
    pm = p.pm
    jq = p.iq[7:] if p.floating else p.iq
    jv = p.iv[6:] if p.floating else p.iv
    assert_close(m.lower, pm.lowerPositionLimit[jq], 1e-12)
    assert_close(m.upper, pm.upperPositionLimit[jq], 1e-12)
    assert_close(m.effort, pm.effortLimit[jv], 1e-12)
    assert_close(m.gravity, pm.gravity.linear, 1e-15)
    # the whole robot (a fixed model's base link is in Pinocchio's universe, inertias[0])
    assert m.total_mass == pytest.approx(sum(I.mass for I in pm.inertias), rel=1e-12)


def test_dynamics(pair):
    key, p = pair
    m, pm, pd = p.ours, p.pm, p.pd
    s = states(m, 3, seed=501)
    for k in range(3):
        q, v, a, t = p.q(s.Q[k]), p.v(s.V[k]), p.v(s.A[k]), p.v(s.T[k])
        assert_close(spatial.rnea(m, s.Q[k], s.V[k], s.A[k]), p.vec(pin.rnea(pm, pd, q, v, a)), TOL,
                     err_msg=f"{key} rnea")
        assert_close(spatial.gravity(m, s.Q[k]), p.vec(pin.computeGeneralizedGravity(pm, pd, q)), TOL,
                     err_msg=f"{key} gravity")
        assert_close(spatial.bias(m, s.Q[k], s.V[k]), p.vec(pin.nonLinearEffects(pm, pd, q, v)), TOL,
                     err_msg=f"{key} bias")
        assert_close(spatial.crba(m, s.Q[k]), p.mat(sym(pin.crba(pm, pd, q))), TOL, err_msg=f"{key} crba")
        assert_close(spatial.aba(m, s.Q[k], s.V[k], s.T[k]), p.vec(pin.aba(pm, pd, q, v, t)), TOL,
                     err_msg=f"{key} aba")
        assert_close(spatial.forward_dynamics(m, s.Q[k], s.V[k], s.T[k]), p.vec(pin.aba(pm, pd, q, v, t)), TOL,
                     err_msg=f"{key} forward_dynamics")
        assert_close(spatial.inverse_inertia(m, s.Q[k]), p.mat(sym(pin.computeMinverse(pm, pd, q))), TOL,
                     err_msg=f"{key} inverse_inertia")
        assert_close(spatial.kinetic_energy(m, s.Q[k], s.V[k]), pin.computeKineticEnergy(pm, pd, q, v), TOL,
                     err_msg=f"{key} kinetic_energy")
    # potential energy: the same up to its reference (compare differences between states)
    U = spatial.potential_energy(m, s.Q)
    Up = np.array([pin.computePotentialEnergy(pm, pd, p.q(x)) for x in s.Q])
    assert_close(U - U[0], Up - Up[0], TOL, err_msg=f"{key} potential_energy")


def test_external_forces(pair):
    """fext in body coordinates, [f; n]: Pinocchio's per-joint forces in the joint frames (the moving links' frames:
    no body frame of these models is turned, and none is reversed)."""
    key, p = pair
    m, pm, pd = p.ours, p.pm, p.pd
    s = states(m, 2, seed=502)
    nb = m.njoints + (1 if m.floating else 0)
    F = np.random.default_rng(7).normal(size=(2, nb, 6))
    bodies = ([1] if p.floating else []) + p.joint_ids  # our fext row -> Pinocchio joint id
    for k in range(2):
        fext = [pin.Force.Zero() for _ in range(pm.njoints)]
        for row, jid in enumerate(bodies):
            fext[jid] = pin.Force(F[k, row, :3], F[k, row, 3:])
        q, v, a, t = p.q(s.Q[k]), p.v(s.V[k]), p.v(s.A[k]), p.v(s.T[k])
        fv = pin.StdVec_Force()
        for f in fext:
            fv.append(f)
        assert_close(spatial.rnea(m, s.Q[k], s.V[k], s.A[k], fext=F[k]), p.vec(pin.rnea(pm, pd, q, v, a, fv)), TOL,
                     err_msg=f"{key} rnea fext")
        assert_close(spatial.aba(m, s.Q[k], s.V[k], s.T[k], fext=F[k]), p.vec(pin.aba(pm, pd, q, v, t, fv)), TOL,
                     err_msg=f"{key} aba fext")


def test_derivatives(pair):
    key, p = pair
    m, pm, pd = p.ours, p.pm, p.pd
    s = states(m, 2, seed=503)
    for k in range(2):
        q, v, a, t = p.q(s.Q[k]), p.v(s.V[k]), p.v(s.A[k]), p.v(s.T[k])
        dq, dv = spatial.rnea_derivatives(m, s.Q[k], s.V[k], s.A[k])
        pdq, pdv, _ = pin.computeRNEADerivatives(pm, pd, q, v, a)
        assert_close(dq, p.mat(pdq), TOL, err_msg=f"{key} dtau_dq")
        assert_close(dv, p.mat(pdv), TOL, err_msg=f"{key} dtau_dv")
        dq, dv, dtau = spatial.aba_derivatives(m, s.Q[k], s.V[k], s.T[k])
        pdq, pdv, pminv = pin.computeABADerivatives(pm, pd, q, v, t)
        pdq, pdv, pminv = np.array(pdq), np.array(pdv), sym(pminv)
        assert_close(dq, p.mat(pdq), 1e-9, err_msg=f"{key} dqdd_dq")
        assert_close(dv, p.mat(pdv), 1e-9, err_msg=f"{key} dqdd_dv")
        assert_close(dtau, p.mat(pminv), TOL, err_msg=f"{key} dqdd_dtau")


def frames_to_check(m):
    names = [f for f in ("L_SOLE", "R_SOLE", "R_HAND", "L_HAND", "HEAD", "L_FOOT", "base_link") if f in m.frame_names]
    # moving links: their body frames are the links' frames here (no reversed or turned joint)
    names += [b for b in ("R_KN", "L_EB", "CHEST") if b in m.body_names]
    return names


@pytest.mark.parametrize("reference", sorted(REFS))
def test_frame_jacobians(pair, reference):
    key, p = pair
    m, pm, pd = p.ours, p.pm, p.pd
    s = states(m, 2, seed=504)
    rf = getattr(pin.ReferenceFrame, REFS[reference])
    for k in range(2):
        q = p.q(s.Q[k])
        v = p.v(s.V[k])
        pin.forwardKinematics(pm, pd, q, v)
        pin.updateFramePlacements(pm, pd)
        for frame in frames_to_check(m):
            fid = p.frame(frame)
            Jp = pin.computeFrameJacobian(pm, pd, q, fid, rf)
            assert_close(spatial.frame_jacobian(m, s.Q[k], frame, reference=reference), p.cols(Jp), TOL,
                         err_msg=f"{key} {frame} {reference}")
            pin.forwardKinematics(pm, pd, q, v)
            vel = pin.getFrameVelocity(pm, pd, fid, rf).vector  # linear first
            assert_close(spatial.frame_velocity(m, s.Q[k], s.V[k], frame, reference=reference), vel, TOL,
                         err_msg=f"{key} frame_velocity {frame} {reference}")


@pytest.mark.parametrize("reference", sorted(REFS))
def test_frame_accelerations_and_jacobian_time_variation(pair, reference):
    """getFrameAcceleration, getFrameClassicalAcceleration (LOCAL and LOCAL_WORLD_ALIGNED: Pinocchio's WORLD variant
    is the point at the world origin, ours the frame's origin, as for LOCAL_WORLD_ALIGNED) and
    getFrameJacobianTimeVariation."""
    key, p = pair
    m, pm, pd = p.ours, p.pm, p.pd
    s = states(m, 2, seed=509)
    rf = getattr(pin.ReferenceFrame, REFS[reference])
    for k in range(2):
        q, v, a = p.q(s.Q[k]), p.v(s.V[k]), p.v(s.A[k])
        pin.forwardKinematics(pm, pd, q, v, a)
        pin.updateFramePlacements(pm, pd)
        for frame in frames_to_check(m):
            fid = p.frame(frame)
            what = f"{key} {frame} {reference}"
            acc = pin.getFrameAcceleration(pm, pd, fid, rf).vector  # linear first
            assert_close(spatial.frame_acceleration(m, s.Q[k], s.V[k], s.A[k], frame, reference=reference), acc,
                         TOL, err_msg=f"{what} frame_acceleration")
            if reference != "world":
                pdd = pin.getFrameClassicalAcceleration(pm, pd, fid, rf).linear
                assert_close(spatial.frame_classical_acceleration(m, s.Q[k], s.V[k], s.A[k], frame,
                                                                  reference=reference), pdd, TOL,
                             err_msg=f"{what} frame_classical_acceleration")
        pin.computeJointJacobiansTimeVariation(pm, pd, q, v)
        pin.updateFramePlacements(pm, pd)
        for frame in frames_to_check(m):
            dJ = pin.getFrameJacobianTimeVariation(pm, pd, p.frame(frame), rf)
            assert_close(spatial.frame_jacobian_time_variation(m, s.Q[k], s.V[k], frame, reference=reference),
                         p.cols(dJ), TOL, err_msg=f"{key} {frame} {reference} frame_jacobian_time_variation")


def test_frame_placements(pair):
    key, p = pair
    m, pm, pd = p.ours, p.pm, p.pd
    s = states(m, 2, seed=505)
    for k in range(2):
        pin.framesForwardKinematics(pm, pd, p.q(s.Q[k]))
        for frame in frames_to_check(m):
            assert_close(spatial.frame_placement(m, s.Q[k], frame), pd.oMf[p.frame(frame)].homogeneous, TOL,
                         err_msg=f"{key} frame_placement {frame}")


def test_com_and_centroidal(pair):
    key, p = pair
    m, pm, pd = p.ours, p.pm, p.pd
    s = states(m, 2, seed=506)
    for k in range(2):
        q, v = p.q(s.Q[k]), p.v(s.V[k])
        if p.floating:
            c = pin.centerOfMass(pm, pd, q)
            assert_close(spatial.center_of_mass(m, s.Q[k]), c, TOL, err_msg=f"{key} center_of_mass")
            Jc = pin.jacobianCenterOfMass(pm, pd, q)
            assert_close(spatial.com_jacobian(m, s.Q[k]), p.cols(Jc), TOL, err_msg=f"{key} com_jacobian")
            Ag = pin.ccrba(pm, pd, q, v)
            assert_close(spatial.centroidal_momentum_matrix(m, s.Q[k]), p.cols(Ag), TOL, err_msg=f"{key} A_G")
            assert_close(spatial.centroidal_momentum(m, s.Q[k], s.V[k]), pd.hg.vector, TOL, err_msg=f"{key} h_G")
            a = p.v(s.A[k])
            pin.computeCentroidalMomentumTimeVariation(pm, pd, q, v, a)
            dh, _ = spatial.centroidal_momentum_time_variation(m, s.Q[k], s.V[k], s.A[k])
            assert_close(dh, pd.dhg.vector, TOL, err_msg=f"{key} dh_G")
        else:
            # the moving bodies' CoM in base coordinates (Pinocchio's universe carries the base link)
            pin.forwardKinematics(pm, pd, q)
            mass = sum(pm.inertias[j].mass for j in range(1, pm.njoints))
            c = sum(pm.inertias[j].mass * (pd.oMi[j].act(pm.inertias[j].lever)) for j in range(1, pm.njoints)) / mass
            assert_close(spatial.center_of_mass(m, s.Q[k]), c, TOL, err_msg=f"{key} center_of_mass")


@pytest.mark.parametrize("key", ["floating_gen", "floating_urdf"])
def test_integrate_difference(key):
    p = get_pair(key)
    m, pm = p.ours, p.pm
    s = states(m, 3, seed=507)
    Q2 = states(m, 3, seed=508).Q
    for k in range(3):
        qi = pin.integrate(pm, p.q(s.Q[k]), p.v(s.V[k]))
        ours = spatial.integrate(m, s.Q[k], s.V[k])
        theirs = np.asarray(qi)[p.iq]
        if np.dot(ours[3:7], theirs[3:7]) < 0:
            theirs[3:7] *= -1
        assert_close(ours, theirs, TOL, err_msg=f"{key} integrate")
        d = pin.difference(pm, p.q(s.Q[k]), p.q(Q2[k]))
        assert_close(spatial.difference(m, s.Q[k], Q2[k]), p.vec(d), TOL, err_msg=f"{key} difference")
