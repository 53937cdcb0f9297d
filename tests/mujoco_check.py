"""Loads an MJCF exported by prbfit into MuJoCo, applies a fixed-direction tip load at the
`tip` site, lets the model settle, and prints the settled tip pose as JSON.

usage: mujoco_check.py MODEL.xml FX FY MZ LENGTH

The load (N, N m) is ramped up from zero so the model follows the same equilibrium branch as
prbfit's continuation; joint damping (about twice critical, from each joint's stiffness and
the mass matrix) settles it. Output: {"x": .., "y": .., "angle": .., "steps": ..} with x, y
in units of LENGTH and the tip frame's angle in radians.
"""
import json
import math
import sys

import mujoco
import numpy as np


def main():
    path, fx, fy, mz, length = sys.argv[1], *map(float, sys.argv[2:6])
    model = mujoco.MjModel.from_xml_path(path)
    data = mujoco.MjData(model)
    site = model.site("tip").id
    body = model.site_bodyid[site]

    # Time scales from each joint's stiffness and its diagonal of the mass matrix.
    mujoco.mj_forward(model, data)
    full = np.zeros((model.nv, model.nv))
    try:
        mujoco.mj_fullM(model, data, full)  # MuJoCo >= 3.3
    except TypeError:
        mujoco.mj_fullM(model, full, data.qM)  # older releases
    inertia = np.diag(full).copy()
    stiffness = np.array([model.jnt_stiffness[model.dof_jntid[i]] for i in range(model.nv)])
    omega = np.sqrt(stiffness / inertia)
    model.dof_damping[:] = 4.0 * np.sqrt(stiffness * inertia)
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    model.opt.timestep = 0.02 / omega.max()
    ramp = 4000
    force = np.array([fx, fy, 0.0])
    torque = np.array([0.0, 0.0, mz])
    last = None
    for step in range(2_000_000):
        s = min(1.0, step / ramp)
        data.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(
            model, data, s * force, s * torque, data.site_xpos[site], body, data.qfrc_applied
        )
        mujoco.mj_step(model, data)
        if step > ramp and step % 200 == 0:
            tip = data.site_xpos[site].copy()
            if last is not None and np.max(np.abs(tip - last)) < 1e-13 * length:
                break
            last = tip
    xmat = data.site_xmat[site].reshape(3, 3)
    angle = math.atan2(xmat[1, 0], xmat[0, 0])
    # Unwrap past +-pi with the joint angles (their sum is the tip angle for a planar chain).
    hinge_sum = sum(
        data.qpos[model.jnt_qposadr[j]]
        for j in range(model.njnt)
        if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_HINGE
    )
    angle += 2.0 * math.pi * round((hinge_sum - angle) / (2.0 * math.pi))
    tip = data.site_xpos[site]
    print(json.dumps({"x": tip[0] / length, "y": tip[1] / length, "angle": angle, "steps": step}))


if __name__ == "__main__":
    main()
