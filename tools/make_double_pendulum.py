#!/usr/bin/env python3
"""Write urdf/double_pendulum.urdf: the 2-DoF double inverted pendulum of the reference study, derived from the
whole-body HOAP-3 description urdf/hoap3.urdf (python3 standard library only).

The pendulum lives in the sagittal plane (x forward, z up) of the stance foot; both joints turn about +y (a positive
angle leans the pendulum forward):
  sole --(ankle_pitch)--> leg --(hip_pitch)--> trunk
  - the root link `sole` is the stance sole frame (R_SOLE or L_SOLE: z up at q = 0), massless;
  - ankle_pitch sits at the robot's ankle pitch axis, hip_pitch at its hip pitch axis (positions at q = 0,
    projected on the sagittal plane: the y offsets are dropped);
  - `leg` (link 1, length l1 = ankle-to-hip distance) carries the point mass m1 at the hip;
  - `trunk` (link 2, from the hip to the whole-body centre of mass, length l2) carries the point mass m2 at the
    whole-body centre of mass at q = 0 (its sagittal offset from the hip, not only its distance);
  - m1 = mass of the stance leg below the hip pitch joint (thigh, shank, ankle and foot links: the part of the robot
    that link 1 stands for), m2 = total mass - m1, so m1 + m2 = the robot's mass.
The reference study (chapters 4.5, 5.5.3, 6.4 of the thesis) gives the structure (link 1 = stance leg from ankle
to hip, link 2 = trunk to the centre of mass, point masses m1 at the hip and m2 at the centre of mass, m1 + m2 =
total mass) but not how m1 is chosen; the stance-leg choice above is ours (see urdf/README.md).

Usage: tools/make_double_pendulum.py [--urdf urdf/hoap3.urdf] [--side R|L] [--out urdf/double_pendulum.urdf]
"""

import argparse
import math
import os
import sys
import xml.etree.ElementTree as ET


def rpy_matrix(r, p, y):
    """R = Rz(y) Ry(p) Rx(r) (URDF fixed-axis roll, pitch, yaw)."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def apply(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def add(a, b):
    return [a[i] + b[i] for i in range(3)]


def numbers(text, default):
    return [float(t) for t in text.split()] if text is not None else list(default)


def load(path):
    root = ET.parse(path).getroot()
    links = {}
    for link in root.findall('link'):
        inertial = link.find('inertial')
        if inertial is None:
            links[link.get('name')] = None
            continue
        origin = inertial.find('origin')
        xyz = numbers(origin.get('xyz') if origin is not None else None, (0, 0, 0))
        links[link.get('name')] = (float(inertial.find('mass').get('value')), xyz)
    joints = {}
    for joint in root.findall('joint'):
        origin = joint.find('origin')
        xyz = numbers(origin.get('xyz') if origin is not None else None, (0, 0, 0))
        rpy = numbers(origin.get('rpy') if origin is not None else None, (0, 0, 0))
        axis_el = joint.find('axis')
        axis = numbers(axis_el.get('xyz') if axis_el is not None else None, (1, 0, 0))
        joints[joint.get('name')] = dict(type=joint.get('type'), parent=joint.find('parent').get('link'),
                                         child=joint.find('child').get('link'), xyz=xyz, rpy=rpy, axis=axis)
    return links, joints


def poses_at_zero(links, joints):
    """Pose (R, p) of every link in the URDF root frame with every joint at 0."""
    children = {}
    for name, j in joints.items():
        children.setdefault(j['parent'], []).append(name)
    child_links = {j['child'] for j in joints.values()}
    roots = [l for l in links if l not in child_links]
    if len(roots) != 1:
        sys.exit('expected one root link, found %s' % roots)
    pose = {roots[0]: ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0.0, 0.0, 0.0])}
    stack = [roots[0]]
    while stack:
        link = stack.pop()
        R, p = pose[link]
        for name in children.get(link, []):
            j = joints[name]
            pose[j['child']] = (matmul(R, rpy_matrix(*j['rpy'])), add(p, apply(R, j['xyz'])))
            stack.append(j['child'])
    return pose


def subtree(joints, link):
    out, stack = [], [link]
    while stack:
        l = stack.pop()
        out.append(l)
        stack.extend(j['child'] for j in joints.values() if j['parent'] == l)
    return out


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--urdf', default=os.path.join(here, '..', 'urdf', 'hoap3.urdf'))
    ap.add_argument('--side', default='R', choices=['R', 'L'], help='stance side (default R)')
    ap.add_argument('--out', default=os.path.join(here, '..', 'urdf', 'double_pendulum.urdf'))
    args = ap.parse_args()
    s = args.side

    links, joints = load(args.urdf)
    pose = poses_at_zero(links, joints)
    ankle_joint, hip_joint, sole = s + '_KN_' + s + '_AFE_joint', s + '_LAA_' + s + '_LFE_joint', s + '_SOLE'
    ankle, hip = joints[ankle_joint]['child'], joints[hip_joint]['child']  # joint frames = child link frames
    for name in (ankle_joint, hip_joint):  # both pitch axes must be the sagittal plane's normal (+/- y)
        R, _ = pose[joints[name]['child']]
        a = apply(R, joints[name]['axis'])
        if abs(abs(a[1]) - 1) > 1e-12:
            sys.exit('%s: axis %s is not along y at q = 0' % (name, a))
    R_sole, p_sole = pose[sole]
    if any(abs(R_sole[i][j] - (i == j)) > 1e-12 for i in range(3) for j in range(3)):
        sys.exit('%s is not parallel to the root frame at q = 0' % sole)

    total, first = 0.0, [0.0, 0.0, 0.0]
    for name, data in links.items():
        if data is None:
            continue
        m, c = data
        R, p = pose[name]
        total += m
        first = add(first, [m * x for x in add(p, apply(R, c))])
    com = [x / total for x in first]
    m1 = sum(links[l][0] for l in subtree(joints, hip) if links[l] is not None)
    m2 = total - m1

    p_ankle, p_hip = pose[ankle][1], pose[hip][1]
    ankle_in_sole = [p_ankle[0] - p_sole[0], p_ankle[2] - p_sole[2]]  # sagittal (x, z)
    hip_in_ankle = [p_hip[0] - p_ankle[0], p_hip[2] - p_ankle[2]]
    com_in_hip = [com[0] - p_hip[0], com[2] - p_hip[2]]
    l1, l2 = math.hypot(*hip_in_ankle), math.hypot(*com_in_hip)
    legs = ', '.join(l for l in subtree(joints, hip) if links[l] is not None)

    def r(x):  # lengths to 1e-12 m and masses to 1e-12 kg: removes the 1e-17 noise of cos(pi/2)
        return round(x, 12) + 0.0

    def v(x, z):
        return '%r 0 %r' % (r(x), r(z))

    l1, l2, m1, m2, total = r(l1), r(l2), r(m1), r(m2), r(total)

    text = f'''<?xml version="1.0"?>
<!--
  HOAP-3 double inverted pendulum (2 DoF, sagittal plane), as in the reference study: link 1 from the ankle to the
  hip (the stance leg), link 2 from the hip to the whole-body centre of mass (the trunk); point masses m1 at the hip
  and m2 at the centre of mass, m1 + m2 = the robot's mass; massless rods. Both joints turn about +y (x forward,
  z up): a positive angle leans the pendulum forward. Gravity: -z of the root link `sole`.

  GENERATED by tools/make_double_pendulum.py from {os.path.relpath(args.urdf, os.path.dirname(args.out))} (stance side {s}); do not edit, regenerate.
  Derivation, with every joint of the whole-body model at 0:
    sole         = the {sole} frame (z up at q = 0), the root.
    ankle_pitch  = at the {ankle_joint} axis: {v(*ankle_in_sole)} m from the sole (x, z; the y offset is dropped).
    hip_pitch    = at the {hip_joint} axis: {v(*hip_in_ankle)} m from the ankle, so l1 = {l1!r} m.
    m1           = {m1!r} kg, the stance leg below the hip pitch joint ({legs}), at the hip.
    m2           = {m2!r} kg = total mass {total!r} kg - m1, at the whole-body centre of mass,
                   {v(*com_in_hip)} m from the hip (x, z), so l2 = {l2!r} m.
  Numbers rounded to 1e-12 (m, kg). The point masses have no rotational inertia.
-->
<robot name="hoap3_double_pendulum">
  <link name="sole"/>
  <joint name="ankle_pitch" type="continuous">
    <parent link="sole"/>
    <child link="leg"/>
    <origin xyz="{v(*ankle_in_sole)}" rpy="0 0 0"/>
    <axis xyz="0 1 0"/>
  </joint>
  <link name="leg">
    <inertial>
      <origin xyz="{v(*hip_in_ankle)}" rpy="0 0 0"/>
      <mass value="{m1!r}"/>
      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>
    </inertial>
  </link>
  <joint name="hip_pitch" type="continuous">
    <parent link="leg"/>
    <child link="trunk"/>
    <origin xyz="{v(*hip_in_ankle)}" rpy="0 0 0"/>
    <axis xyz="0 1 0"/>
  </joint>
  <link name="trunk">
    <inertial>
      <origin xyz="{v(*com_in_hip)}" rpy="0 0 0"/>
      <mass value="{m2!r}"/>
      <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>
    </inertial>
  </link>
</robot>
'''
    with open(args.out, 'w') as f:
        f.write(text)
    print('%s: l1 = %.6f m, l2 = %.6f m, m1 = %.4f kg, m2 = %.4f kg' % (os.path.relpath(args.out), l1, l2, m1, m2))


if __name__ == '__main__':
    main()
