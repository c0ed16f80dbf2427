#!/usr/bin/env python3
"""Forward-dynamics rollouts from MuJoCo, an independent check of hya's rigid-body simulator.

For each robot (hya, iiwa14) the URDF in robots/urdf/ is loaded with MuJoCo's own URDF importer
and set up as an ideal rigid-body chain: gravity 9.81 m/s^2 along the base's -z, no joint limits,
contacts, constraints, damping, armature, friction loss, springs or actuators. Joint torques enter
through data.qfrc_applied. Starting at rest at q0, a deterministic torque sequence is applied with
a zero-order hold, one row every 0.01 s for 1 s:

    tau_i(t_k) = g_i(q0) + A_i * sin(2*pi*f_i*t_k + phi_i),   t_k = k * 0.01 s, k = 0..99

where g(q0) is MuJoCo's generalized gravity force at q0 (mj_inverse with qvel = qacc = 0), which
makes q0 an equilibrium. For both arms that equilibrium is unstable (a linearization at q0 has
modes growing like exp(8.8 t) for hya and exp(5.3 t) for iiwa14), so the amplitudes are kept small
enough that the arm swings by about 0.05 to 1 rad per joint within the second rather than falling
over. The state is integrated with RK4 at a 1e-4 s step and sampled every 1e-3 s. Writes, under
hya-sim/tests/data/:

    mujoco_<robot>_torque.csv   '#' comment lines, then rows t,tau1..taun (t: when the row starts)
    mujoco_<robot>_rollout.csv  '#' comment lines, then rows t,q1..qn,qd1..qdn, t = 0..1 s

Numbers are written with repr() so they round-trip. As a self-check the rollout is repeated
at a 1e-5 s step; the largest |q| difference (MuJoCo's own integration error) is printed and
recorded in the headers. Two energy checks are printed (not saved): with zero torque the total
energy must stay constant, and in the driven run its change must equal the work of the torques.

Checks made before any rollout (the script stops if one fails): MuJoCo's joints are the URDF's
movable joints in chain order, one dof each; the total mass equals the URDF's sum of link
masses; at q0 every body's origin, orientation, centre of mass and inertia tensor (in the
world frame) equal those computed from the URDF by this script; joint axes and anchors agree.
MuJoCo's compiler refuses inertias that break the triangle inequality A + B >= C (HyA's
Wrist_FE does); such a model is compiled with balanceinertia="true" and the inertias MuJoCo
changed are then put back from the URDF into the compiled model, and the change is recorded.

Usage:
    python3 -m venv tools/.venv
    tools/.venv/bin/pip install -r tools/requirements-mujoco.txt
    tools/.venv/bin/python tools/mujoco_rollout.py [--robots hya iiwa14] [--out DIR]
"""
import argparse
import math
import platform
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

try:
    import mujoco
except ImportError:  # pragma: no cover - install hint only
    sys.exit("mujoco is missing: pip install -r tools/requirements-mujoco.txt (in a virtualenv)")

ROOT = Path(__file__).resolve().parent.parent
GRAVITY = (0.0, 0.0, -9.81)
DT = 1e-4  # integration step of the saved rollout, s
DT_CHECK = 1e-5  # integration step of the self-check, s
ROW_PERIOD = 0.01  # torque row period, s
SAMPLE_PERIOD = 0.001  # output sample period, s
DURATION = 1.0  # s

# q0 (rad), and the sine terms: amplitudes A (N·m), frequencies f (Hz), phases phi (rad).
ROBOTS = {
    "hya": {
        "q0": [0.0, 0.0, -0.7854, 0.7854, 0.7854, 0.0],
        "A": [0.1, 0.2, 0.003, 0.003, 0.001, 0.0005],
        "f": [0.7, 1.1, 0.9, 1.3, 1.7, 1.5],
        "phi": [0.0, 0.7, 1.4, 2.1, 2.8, 3.5],
    },
    "iiwa14": {
        "q0": [0.0, 0.5, 0.0, -1.0, 0.0, 0.8, 0.0],
        "A": [4.0, 0.5, 0.4, 0.06, 0.3, 0.12, 0.025],
        "f": [0.7, 1.1, 0.9, 1.3, 1.7, 1.5, 1.9],
        "phi": [0.0, 0.7, 1.4, 2.1, 2.8, 3.5, 4.2],
    },
}

COMPILER = (
    '<mujoco><compiler balanceinertia="{balance}" fusestatic="true" discardvisual="true" '
    'inertiafromgeom="false" angle="radian"/></mujoco>'
)
DISABLED = [
    "mjDSBL_CONSTRAINT",
    "mjDSBL_CONTACT",
    "mjDSBL_LIMIT",
    "mjDSBL_EQUALITY",
    "mjDSBL_FRICTIONLOSS",
    "mjDSBL_SPRING",
    "mjDSBL_DAMPER",
    "mjDSBL_ACTUATION",
    "mjDSBL_AUTORESET",  # a blow-up must show, not be reset silently
]
TOL = 1e-12
NUDGE = 1e-9  # rad, perturbation of q0 for the sensitivity figure


# ---------------------------------------------------------------- the URDF, read by this script


def rpy_matrix(rpy):
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


def axis_matrix(axis, angle):
    """Rotation by angle about a unit axis (Rodrigues)."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def floats(text, default):
    return [float(v) for v in text.split()] if text else list(default)


def origin(element):
    o = element.find("origin") if element is not None else None
    if o is None:
        return np.zeros(3), np.eye(3)
    return np.array(floats(o.get("xyz"), [0, 0, 0])), rpy_matrix(floats(o.get("rpy"), [0, 0, 0]))


class Urdf:
    def __init__(self, path):
        tree = ET.parse(path).getroot()
        self.links = {}  # name -> (mass, com in link frame, inertia about com in link frame)
        for link in tree.findall("link"):
            inertial = link.find("inertial")
            if inertial is None:
                self.links[link.get("name")] = (0.0, np.zeros(3), np.zeros((3, 3)))
                continue
            xyz, rot = origin(inertial)
            mass = float(inertial.find("mass").get("value"))
            i = {k: float(v) for k, v in inertial.find("inertia").attrib.items()}
            tensor = np.array(
                [
                    [i["ixx"], i["ixy"], i["ixz"]],
                    [i["ixy"], i["iyy"], i["iyz"]],
                    [i["ixz"], i["iyz"], i["izz"]],
                ]
            )
            self.links[link.get("name")] = (mass, xyz, rot @ tensor @ rot.T)
        self.joints = {}  # child link -> joint
        for joint in tree.findall("joint"):
            xyz, rot = origin(joint)
            axis = np.array(floats(joint.find("axis").get("xyz") if joint.find("axis") is not None else None, [1, 0, 0]))
            self.joints[joint.find("child").get("link")] = {
                "name": joint.get("name"),
                "type": joint.get("type"),
                "parent": joint.find("parent").get("link"),
                "xyz": xyz,
                "rot": rot,
                "axis": axis / np.linalg.norm(axis),
            }
        roots = [name for name in self.links if name not in self.joints]
        if len(roots) != 1:
            raise ValueError(f"expected one root link, found {roots}")
        self.root = roots[0]
        self.order = []  # links, parents before children, in file order
        pending = [self.root]
        while pending:
            link = pending.pop(0)
            self.order.append(link)
            pending = [c for c, j in self.joints.items() if j["parent"] == link] + pending
        self.movable = [self.joints[c]["name"] for c in self.order[1:] if self.joints[c]["type"] != "fixed"]
        if any(self.joints[c]["type"] not in ("fixed", "revolute", "continuous") for c in self.order[1:]):
            raise ValueError("only revolute, continuous and fixed joints are handled")

    def total_mass(self):
        return sum(mass for mass, _, _ in self.links.values())

    def frames(self, q):
        """World pose of every link, and each movable joint's world axis and anchor, at q."""
        angle = dict(zip(self.movable, q))
        pose = {self.root: (np.zeros(3), np.eye(3))}
        axes = {}
        for link in self.order[1:]:
            j = self.joints[link]
            p, r = pose[j["parent"]]
            p, r = p + r @ j["xyz"], r @ j["rot"]
            if j["type"] != "fixed":
                axes[j["name"]] = (r @ j["axis"], p)
                r = r @ axis_matrix(j["axis"], angle[j["name"]])
            pose[link] = (p, r)
        return pose, axes


# ---------------------------------------------------------------- MuJoCo's model


def name(m, kind, index):
    return mujoco.mj_id2name(m, kind, index)


def compile_urdf(path):
    """MuJoCo's model of the URDF; returns (model, balanced), balanced telling whether the
    compiler had to be allowed to balance inertias."""
    text = path.read_text()
    text = re.sub(r"<visual\b.*?</visual>|<visual\b[^>]*/>", "", text, flags=re.S)
    text = re.sub(r"<collision\b.*?</collision>|<collision\b[^>]*/>", "", text, flags=re.S)
    text = re.sub(r"<mujoco\b.*?</mujoco>", "", text, flags=re.S)
    for balance in ("false", "true"):
        patched = re.sub(r"(<robot\b[^>]*>)", r"\1" + COMPILER.format(balance=balance), text, count=1)
        try:
            return mujoco.MjModel.from_xml_string(patched), balance == "true"
        except ValueError as error:
            if "balanceinertia" not in str(error) or balance == "true":
                raise
            print(f"  MuJoCo refuses the URDF as it is: {str(error).splitlines()[0]}")


def urdf_bodies(m, urdf, q):
    """For each MuJoCo body, the mass, world COM and world inertia (about that COM) that the
    URDF gives it: the URDF links fused into a body (fixed, static) are lumped into it."""
    bodies = {name(m, mujoco.mjtObj.mjOBJ_BODY, b): b for b in range(m.nbody)}
    pose, _ = urdf.frames(q)
    lumps = {b: [] for b in range(m.nbody)}
    for link in urdf.order:
        owner = link
        while owner not in bodies:
            owner = urdf.joints[owner]["parent"] if owner in urdf.joints else None
            if owner is None:
                owner = "world"
                break
        mass, com, inertia = urdf.links[link]
        p, r = pose[link]
        lumps[bodies[owner]].append((mass, p + r @ com, r @ inertia @ r.T))
    result = {}
    for b, parts in lumps.items():
        mass = sum(pm for pm, _, _ in parts)
        com = sum(pm * pc for pm, pc, _ in parts) / mass if mass > 0 else np.zeros(3)
        inertia = np.zeros((3, 3))
        for pm, pc, pi in parts:
            d = pc - com
            inertia += pi + pm * (d @ d * np.eye(3) - np.outer(d, d))
        result[b] = (mass, com, inertia)
    return result, pose


def inertia_mismatches(m, d, urdf, q):
    """Bodies whose mass, COM or inertia differ from the URDF's at q, as (body, what, error)."""
    expect, _ = urdf_bodies(m, urdf, q)
    d.qpos[:] = q
    mujoco.mj_kinematics(m, d)
    bad = []
    for b in range(1, m.nbody):
        mass, com, inertia = expect[b]
        r = d.ximat[b].reshape(3, 3)
        got = r @ np.diag(m.body_inertia[b]) @ r.T
        for what, err in (
            ("mass", abs(m.body_mass[b] - mass)),
            ("com", np.abs(d.xipos[b] - com).max()),
            ("inertia", np.abs(got - inertia).max()),
        ):
            if err > TOL * max(1.0, mass):
                bad.append((b, what, err))
    return bad


def restore_inertias(m, d, urdf, q, bodies):
    """Puts the URDF's inertia back into the compiled model for the given bodies."""
    expect, _ = urdf_bodies(m, urdf, q)
    d.qpos[:] = q
    mujoco.mj_kinematics(m, d)
    for b in bodies:
        mass, com, inertia = expect[b]
        r = d.xmat[b].reshape(3, 3)
        local = r.T @ inertia @ r
        local = (local + local.T) / 2
        moments, vectors = np.linalg.eigh(local)
        if np.linalg.det(vectors) < 0:
            vectors[:, 0] = -vectors[:, 0]
        if moments.min() <= 0:
            raise ValueError(f"body {name(m, mujoco.mjtObj.mjOBJ_BODY, b)}: inertia not positive definite")
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, vectors.reshape(-1))
        m.body_mass[b] = mass
        m.body_ipos[b] = r.T @ (com - d.xpos[b])
        m.body_iquat[b] = quat
        m.body_inertia[b] = moments
    mujoco.mj_setConst(m, d)


def configure(m, dt):
    m.opt.timestep = dt
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    m.opt.gravity[:] = GRAVITY
    m.opt.density = 0.0
    m.opt.viscosity = 0.0
    m.opt.wind[:] = 0.0
    m.opt.magnetic[:] = 0.0
    m.opt.disableflags = 0
    for flag in DISABLED:
        m.opt.disableflags |= int(getattr(mujoco.mjtDisableBit, flag))
    m.opt.enableflags = 0
    m.jnt_limited[:] = 0
    m.jnt_actfrclimited[:] = 0
    m.jnt_stiffness[:] = 0.0
    m.dof_damping[:] = 0.0
    m.dof_armature[:] = 0.0
    m.dof_frictionloss[:] = 0.0
    m.body_gravcomp[:] = 0.0


def load(robot):
    """MuJoCo's model of robots/urdf/<robot>.urdf, checked against the URDF; returns
    (model, urdf, notes) where notes list what the import changed."""
    path = ROOT / "robots" / "urdf" / f"{robot}.urdf"
    urdf = Urdf(path)
    m, balanced = compile_urdf(path)
    d = mujoco.MjData(m)
    q0 = np.array(ROBOTS[robot]["q0"])
    notes = []
    fused = [link for link in urdf.order if link not in {name(m, mujoco.mjtObj.mjOBJ_BODY, b) for b in range(m.nbody)}]
    if fused:
        notes.append(f"links fused into their parent (static, massless here): {', '.join(fused)}")
    bad = inertia_mismatches(m, d, urdf, q0)
    if bad:
        changed = sorted({b for b, _, _ in bad})
        if not balanced or any(what != "inertia" for _, what, _ in bad):
            raise SystemExit(f"{robot}: MuJoCo's inertias differ from the URDF's: {bad}")
        for b in changed:
            body = name(m, mujoco.mjtObj.mjOBJ_BODY, b)
            moments = np.linalg.eigvalsh(urdf_bodies(m, urdf, q0)[0][b][2])
            notes.append(
                f"{body}: URDF principal moments {[float(f'{x:.6g}') for x in moments]} break A+B>=C "
                f"(by {moments[2] - moments[0] - moments[1]:.3g} kg m^2); MuJoCo's balanceinertia set them to "
                f"{float(m.body_inertia[b][0]):.6g} each; the URDF's tensor was put back into the compiled model"
            )
        restore_inertias(m, d, urdf, q0, changed)
        bad = inertia_mismatches(m, d, urdf, q0)
        if bad:
            raise SystemExit(f"{robot}: restoring inertias failed: {bad}")
    configure(m, DT)
    check_model(m, d, urdf, q0)
    return m, urdf, notes, balanced


def check_model(m, d, urdf, q0):
    joints = [name(m, mujoco.mjtObj.mjOBJ_JOINT, j) for j in range(m.njnt)]
    if joints != urdf.movable:
        raise SystemExit(f"joint order {joints} != URDF chain order {urdf.movable}")
    hinge = mujoco.mjtJoint.mjJNT_HINGE
    if not (m.nq == m.nv == m.njnt and all(m.jnt_type == hinge) and list(m.jnt_qposadr) == list(range(m.nq))
            and list(m.jnt_dofadr) == list(range(m.nv))):
        raise SystemExit("expected one hinge per joint, qpos and dof in joint order")
    if m.nu or m.neq or m.ngeom or m.ntendon:
        raise SystemExit(f"unexpected elements: nu={m.nu} neq={m.neq} ngeom={m.ngeom} ntendon={m.ntendon}")
    if abs(m.body_mass.sum() - urdf.total_mass()) > 1e-12:
        raise SystemExit(f"total mass {m.body_mass.sum()} != URDF {urdf.total_mass()}")
    for q in (np.zeros(m.nq), q0):
        d.qpos[:] = q
        mujoco.mj_kinematics(m, d)
        pose, axes = urdf.frames(q)
        for b in range(1, m.nbody):
            p, r = pose[name(m, mujoco.mjtObj.mjOBJ_BODY, b)]
            if np.abs(d.xpos[b] - p).max() > TOL or np.abs(d.xmat[b].reshape(3, 3) - r).max() > 1e-9:
                raise SystemExit(f"body {b} pose differs from the URDF's")
        mujoco.mj_comPos(m, d)
        for j, joint in enumerate(joints):
            axis, anchor = axes[joint]
            if np.abs(d.xaxis[j] - axis).max() > 1e-9 or np.abs(d.xanchor[j] - anchor).max() > TOL:
                raise SystemExit(f"joint {joint} axis or anchor differs from the URDF's")
    if inertia_mismatches(m, d, urdf, q0):
        raise SystemExit("inertias differ from the URDF's")


def pinocchio_agreement(m, robot):
    """Largest relative difference between MuJoCo's inverse dynamics, mass matrix and gravity
    torque and Pinocchio's reference vectors in tests/reference/<robot>.csv, if that file exists."""
    path = ROOT / "tests" / "reference" / f"{robot}.csv"
    if not path.exists():
        return None
    n, d, worst = m.nv, mujoco.MjData(m), 0.0
    for line in path.read_text().splitlines():
        kind, *values = line.split(",")
        if kind not in ("id", "mass", "gravity"):
            continue
        v = np.array([float(x) for x in values])
        d.qpos[:], d.qvel[:], d.qacc[:] = v[:n], v[n : 2 * n], v[2 * n : 3 * n]
        mujoco.mj_inverse(m, d)
        if kind == "mass":
            got = np.zeros((n, n))
            mujoco.mj_fullM(m, d, got)
            got = got.reshape(-1)
        else:
            got = d.qfrc_inverse
        worst = max(worst, np.abs(got - v[3 * n :]).max() / max(1.0, np.abs(v[3 * n :]).max()))
    return worst


# ---------------------------------------------------------------- rollouts


def gravity_torque(m, q):
    d = mujoco.MjData(m)
    d.qpos[:] = q
    d.qvel[:] = 0.0
    d.qacc[:] = 0.0
    mujoco.mj_inverse(m, d)
    g = d.qfrc_inverse.copy()
    mujoco.mj_forward(m, d)
    assert np.allclose(g, d.qfrc_bias, rtol=0, atol=1e-12), "qfrc_inverse != qfrc_bias at rest"
    return g


def torque_rows(m, robot):
    spec = ROBOTS[robot]
    g = gravity_torque(m, np.array(spec["q0"]))
    rows = []
    for k in range(round(DURATION / ROW_PERIOD)):
        t = k / round(1 / ROW_PERIOD)
        tau = [g[i] + spec["A"][i] * math.sin(2 * math.pi * spec["f"][i] * t + spec["phi"][i]) for i in range(m.nv)]
        rows.append((t, tau))
    return g, rows


def rollout(m, q0, rows, dt, energy=False):
    """Samples (t, q, qd) every SAMPLE_PERIOD; with energy, also the largest drift of
    total energy minus the torques' work over the run."""
    configure(m, dt)
    if energy:
        m.opt.enableflags |= int(mujoco.mjtEnableBit.mjENBL_ENERGY)
    d = mujoco.MjData(m)
    d.qpos[:] = q0
    d.qvel[:] = 0.0
    mujoco.mj_forward(m, d)
    per_row = round(ROW_PERIOD / dt)
    per_sample = round(SAMPLE_PERIOD / dt)
    steps = round(DURATION / dt)
    samples_per_second = round(1 / SAMPLE_PERIOD)
    samples, work, e0, drift = [], 0.0, d.energy.sum(), 0.0
    for s in range(steps + 1):
        if s % per_sample == 0:
            samples.append((s // per_sample / samples_per_second, d.qpos.copy(), d.qvel.copy()))
        if s == steps:
            break
        if s % per_row == 0:
            d.qfrc_applied[:] = rows[s // per_row][1]
        qd_before = d.qvel.copy()
        mujoco.mj_step(m, d)
        if energy:
            mujoco.mj_forward(m, d)  # energy of the new state
            work += d.qfrc_applied @ (qd_before + d.qvel) / 2 * dt
            drift = max(drift, abs(d.energy.sum() - e0 - work))
    if any(d.warning[i].number for i in range(len(d.warning))):
        raise SystemExit("MuJoCo raised warnings during the rollout")
    if not np.all(np.isfinite(d.qpos)):
        raise SystemExit("rollout blew up")
    return samples, drift


def fmt(x):
    return repr(float(x))


def header(robot, m, urdf, notes, g, checks):
    spec = ROBOTS[robot]
    disabled = ", ".join(f.removeprefix("mjDSBL_").lower() for f in DISABLED)
    lines = [
        f"MuJoCo {mujoco.__version__} (mj_versionString {mujoco.mj_versionString()}), numpy {np.__version__}, "
        f"Python {platform.python_version()}; written by tools/mujoco_rollout.py",
        f"model: robots/urdf/{robot}.urdf through MuJoCo's URDF importer, compiler "
        + COMPILER.format(balance="true" if checks["balanced"] else "false").removeprefix("<mujoco>").removesuffix("</mujoco>"),
        f"joint order (= URDF chain order): {', '.join(urdf.movable)}; total mass {fmt(m.body_mass.sum())} kg "
        "(= URDF sum of link masses)",
        *[f"import: {n}" for n in notes],
        "checked at q=0 and q0 against the URDF: body poses, joint axes and anchors, every body's mass, COM and "
        "inertia tensor (world frame)"
        + (
            f"; inverse dynamics, mass matrix and gravity agree with Pinocchio's tests/reference/{robot}.csv "
            f"to {checks['agreement']:.3g} (relative)"
            if checks["agreement"] is not None
            else ""
        ),
        f"settings: integrator RK4, timestep {DT} s, gravity {GRAVITY} m/s^2 (base -z); disabled: {disabled}; "
        "jnt_limited = 0, actuatorfrclimited = 0; damping, armature, frictionloss, stiffness, gravcomp = 0; "
        "density = viscosity = 0; no actuators: torques through qfrc_applied",
        f"start: at rest, q0 = {spec['q0']} rad",
        f"torque: tau_i(t_k) = g_i(q0) + A_i*sin(2*pi*f_i*t_k + phi_i), t_k = k*{ROW_PERIOD} s, k = 0..{round(DURATION / ROW_PERIOD) - 1}, "
        "held constant until the next row (zero-order hold)",
        f"  g(q0) = MuJoCo's gravity torque at q0 (mj_inverse, qvel = qacc = 0) = [{', '.join(map(fmt, g))}] N m",
        f"  A = {spec['A']} N m; f = {spec['f']} Hz; phi = {spec['phi']} rad",
        f"self-check: the same rollout at timestep {DT_CHECK} s differs by at most {checks['err']:.3g} rad in q "
        f"and {checks['err_qd']:.3g} rad/s in qd",
        f"energy: total energy minus the work of tau stays within {checks['work']:.3g} J of its start (trapezoidal work); "
        f"with zero torque (falling from q0) energy stays within {checks['free']:.3g} J",
        f"sensitivity: q0 is an unstable equilibrium; starting at q0 + {NUDGE} rad (every joint) changes q by up to "
        f"{checks['growth']:.3g} x {NUDGE} rad within the 1 s, so differences in a compared simulator grow about as much",
    ]
    return ["# " + line for line in lines]


def write(path, comments, rows):
    with path.open("w") as f:
        for line in comments:
            f.write(line + "\n")
        for row in rows:
            f.write(",".join(map(fmt, row)) + "\n")
    print(f"  wrote {path} ({path.stat().st_size} bytes)")


def run(robot, out):
    print(f"{robot}:")
    m, urdf, notes, balanced = load(robot)
    for n in notes:
        print(f"  import: {n}")
    print(f"  joint order: {', '.join(urdf.movable)}")
    print(f"  total mass: MuJoCo {float(m.body_mass.sum())!r} kg, URDF {urdf.total_mass()!r} kg")
    agreement = pinocchio_agreement(m, robot)
    if agreement is not None:
        print(f"  tests/reference/{robot}.csv (Pinocchio): inverse dynamics, mass matrix, gravity agree to {agreement:.3g} (relative)")
        if agreement > 1e-9:
            raise SystemExit("MuJoCo's model disagrees with Pinocchio's reference vectors")
    q0 = np.array(ROBOTS[robot]["q0"])
    g, rows = torque_rows(m, robot)
    print(f"  g(q0) = {np.array2string(g, precision=4)}")

    samples, _ = rollout(m, q0, rows, DT)
    _, work_drift = rollout(m, q0, rows, DT, energy=True)
    fine, _ = rollout(m, q0, rows, DT_CHECK)
    err = max(np.abs(a[1] - b[1]).max() for a, b in zip(samples, fine))
    err_qd = max(np.abs(a[2] - b[2]).max() for a, b in zip(samples, fine))
    qs = np.array([s[1] for s in samples])
    print(f"  motion: max |q - q0| per joint = {np.array2string(np.abs(qs - q0).max(axis=0), precision=3)} rad")
    print(f"  max |qd| = {max(np.abs(s[2]).max() for s in samples):.3g} rad/s")
    print(f"  self-check: max |q(dt={DT}) - q(dt={DT_CHECK})| = {err:.3g} rad, qd: {err_qd:.3g} rad/s")
    print(f"  energy (driven): max |E(t) - E(0) - work of tau| = {work_drift:.3g} J")
    nudged, _ = rollout(m, q0 + NUDGE, rows, DT)
    growth = max(np.abs(a[1] - b[1]).max() for a, b in zip(samples, nudged)) / NUDGE
    print(f"  sensitivity: q0 + {NUDGE} rad (every joint) moves q by up to {growth:.3g} x {NUDGE} rad")
    zero = [(t, [0.0] * m.nv) for t, _ in rows]
    free, free_drift = rollout(m, q0, zero, DT, energy=True)
    d = mujoco.MjData(m)
    d.qpos[:] = free[-1][1]
    d.qvel[:] = free[-1][2]
    mujoco.mj_forward(m, d)
    print(f"  energy (zero torque, falling): max |E(t) - E(0)| = {free_drift:.3g} J; kinetic energy at 1 s = {d.energy[1]:.4g} J")

    checks = {"err": err, "err_qd": err_qd, "growth": growth, "agreement": agreement, "work": work_drift,
              "free": free_drift, "balanced": balanced}
    comments = header(robot, m, urdf, notes, g, checks)
    n = m.nv
    write(
        out / f"mujoco_{robot}_torque.csv",
        ["# torque sequence applied to " + robot + " in mujoco_" + robot + "_rollout.csv", *comments,
         "# columns: t (s, when the row starts to act), " + ", ".join(f"tau{i + 1}" for i in range(n)) + " (N m)"],
        [(t, *tau) for t, tau in rows],
    )
    write(
        out / f"mujoco_{robot}_rollout.csv",
        [f"# MuJoCo forward-dynamics rollout of {robot} under mujoco_{robot}_torque.csv", *comments,
         f"# columns: t (s, every {SAMPLE_PERIOD} s), " + ", ".join(f"q{i + 1}" for i in range(n)) + " (rad), "
         + ", ".join(f"qd{i + 1}" for i in range(n)) + " (rad/s)"],
        [(t, *q, *qd) for t, q, qd in samples],
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="*", default=list(ROBOTS), choices=list(ROBOTS))
    parser.add_argument("--out", type=Path, default=ROOT / "hya-sim" / "tests" / "data")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for robot in args.robots:
        run(robot, args.out)


if __name__ == "__main__":
    main()
