#!/usr/bin/env python3
"""Writes robots/urdf/ur5.urdf from Universal Robots' published UR5 figures.

Standard DH (UR's "DH parameters for calculations of kinematics and dynamics"), link masses and
centres of mass in the DH link frames (UR's "actual center of mass" support article). UR
publishes no inertia tensors: each link gets the tensor of a solid cylinder (radius and length
below) about its centre of mass, an approximation stated in the URDF's header.

DH to URDF: the URDF frame of link i is DH frame i-1 turned by q_i about its z, so joint i+1 sits
at Tz(d_i) Tx(a_i) Rx(alpha_i) in link i: origin xyz = (a_i, 0, d_i), rpy = (alpha_i, 0, 0). A
point c given in DH frame i is (a_i, 0, d_i) + Rx(alpha_i) c in the link frame.
"""
import math
from pathlib import Path

PI_2 = math.pi / 2
A = [0.0, -0.425, -0.39225, 0.0, 0.0, 0.0]
D = [0.089159, 0.0, 0.0, 0.10915, 0.09465, 0.0823]
ALPHA = [PI_2, 0.0, 0.0, PI_2, -PI_2, 0.0]
MASS = [3.7, 8.393, 2.33, 1.219, 1.219, 0.1897]
COM = [(0, -0.02561, 0.00193), (0.2125, 0, 0.11336), (0.15, 0, 0.0265),
       (0, -0.0018, 0.01634), (0, 0.0018, 0.01634), (0, 0, -0.001159)]
# Solid cylinder per link: (radius, length, axis in the DH frame).
CYLINDER = [(0.06, 0.15, "z"), (0.06, 0.425, "x"), (0.06, 0.39225, "x"),
            (0.06, 0.12, "z"), (0.06, 0.12, "z"), (0.0375, 0.0345, "z")]
NAMES = ["shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3"]
LINKS = ["shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link", "wrist_2_link", "wrist_3_link"]
LIMIT = 2 * math.pi
EFFORT = [150.0, 150.0, 150.0, 28.0, 28.0, 28.0]
VELOCITY = [3.15, 3.15, 3.15, 3.2, 3.2, 3.2]


def rot_x(alpha, v):
    c, s = math.cos(alpha), math.sin(alpha)
    return (v[0], c * v[1] - s * v[2], s * v[1] + c * v[2])


def cylinder(m, r, length, axis):
    along = 0.5 * m * r * r
    across = m * (3 * r * r + length * length) / 12
    return {"x": (along, across, across), "z": (across, across, along)}[axis]


def fmt(v):
    """Lengths, rounded to 1e-12 m to drop the noise of the DH arithmetic."""
    return " ".join(repr(round(x, 12) + 0.0) for x in v)


def fmt_angles(v):
    """Angles at full precision, so pi/2 stays the double nearest pi/2."""
    return " ".join(repr(x + 0.0) for x in v)


def main():
    out = ['<?xml version="1.0"?>',
           "<!-- UR5 (Universal Robots), written for hya by tools/ur5_urdf_from_dh.py.",
           "     Kinematics: UR's published standard DH table (d1 = 0.089159, a2 = -0.425,",
           "     a3 = -0.39225, d4 = 0.10915, d5 = 0.09465, d6 = 0.0823). Masses and centres of mass:",
           "     UR's published figures. Inertia tensors: UR publishes none; each link carries a solid",
           "     cylinder's tensor about its centre of mass (see the script), an approximation.",
           "     Limits: +-2 pi, UR's joint speed and torque ratings. -->",
           '<robot name="ur5">', '  <link name="base_link"/>']
    parent = "base_link"
    for i in range(6):
        if i == 0:
            origin_xyz, origin_rpy = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        else:
            origin_xyz, origin_rpy = (A[i - 1], 0.0, D[i - 1]), (ALPHA[i - 1], 0.0, 0.0)
        com = tuple(p + q for p, q in zip((A[i], 0.0, D[i]), rot_x(ALPHA[i], COM[i])))
        ixx, iyy, izz = cylinder(MASS[i], *CYLINDER[i])
        out += [f'  <link name="{LINKS[i]}">', "    <inertial>",
                f'      <origin xyz="{fmt(com)}" rpy="{fmt_angles((ALPHA[i], 0.0, 0.0))}"/>',
                f'      <mass value="{MASS[i]}"/>',
                f'      <inertia ixx="{ixx:.12g}" iyy="{iyy:.12g}" izz="{izz:.12g}" ixy="0" ixz="0" iyz="0"/>',
                "    </inertial>", "  </link>",
                f'  <joint name="{NAMES[i]}_joint" type="revolute">',
                f'    <parent link="{parent}"/>', f'    <child link="{LINKS[i]}"/>',
                f'    <origin xyz="{fmt(origin_xyz)}" rpy="{fmt_angles(origin_rpy)}"/>', '    <axis xyz="0 0 1"/>',
                f'    <limit lower="{-LIMIT!r}" upper="{LIMIT!r}" effort="{EFFORT[i]}" velocity="{VELOCITY[i]}"/>',
                "  </joint>"]
        parent = LINKS[i]
    out += ['  <link name="tool0"/>', '  <joint name="flange_fixed" type="fixed">', '    <parent link="wrist_3_link"/>',
            '    <child link="tool0"/>', f'    <origin xyz="{fmt((A[5], 0.0, D[5]))}" rpy="0 0 0"/>', "  </joint>",
            "</robot>", ""]
    path = Path(__file__).resolve().parent.parent / "robots" / "urdf" / "ur5.urdf"
    path.write_text("\n".join(out))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
