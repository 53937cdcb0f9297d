"""Free vibration of an MJCF exported by prbfit (DESIGN §10): pushes the site SITE with a
small force FY (N, along y) until the model settles (joint damping about twice critical, as
tests/mujoco_check.py does), then releases it with no force, no damping and no gravity, and
measures the frequency of the site's y motion. Prints {"hz": .., "steps": .., "amplitude": ..}.

usage: mujoco_modes_check.py MODEL.xml SITE FY GUESS_HZ

The frequency is the peak of the Hann-windowed discrete-time Fourier transform of y over 30
periods, located by golden-section search within 0.5 to 2 times GUESS_HZ (GUESS_HZ only
sizes the record and the search band: the peak found is the simulation's). The released
shape is the static deflection under a tip force, so the higher modes ring too; over 30
periods with the window their leakage moves the first mode's peak by far less than 1e-4.
The file's own time step and integrator are used unchanged.
"""
import json
import math
import sys

import mujoco
import numpy as np


def mass_diagonal(model, data):
    full = np.zeros((model.nv, model.nv))
    try:
        mujoco.mj_fullM(model, data, full)  # MuJoCo >= 3.3
    except TypeError:
        mujoco.mj_fullM(model, full, data.qM)  # older releases
    return np.diag(full).copy()


def main():
    path, site_name, fy, guess = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
    model = mujoco.MjModel.from_xml_path(path)
    data = mujoco.MjData(model)
    site = model.site(site_name).id
    body = model.site_bodyid[site]
    mujoco.mj_forward(model, data)
    inertia = mass_diagonal(model, data)
    stiffness = np.array([model.jnt_stiffness[model.dof_jntid[i]] for i in range(model.nv)])
    model.dof_damping[:] = 4.0 * np.sqrt(stiffness * inertia)
    dt = model.opt.timestep
    period = 1.0 / guess
    # Settle under the force, ramped over two guessed periods.
    ramp = max(1, int(2.0 * period / dt))
    force = np.array([0.0, fy, 0.0])
    last = None
    steps = 0
    # During the ramp the force is set every step; once it is whole, every `chunk` steps
    # (the site moves by less than 1e-9 of its deflection per chunk by then: the force's
    # point of application lags by that much at most).
    chunk = 500
    while steps < 20_000_000:
        s = min(1.0, steps / ramp)
        data.qfrc_applied[:] = 0.0
        mujoco.mj_applyFT(model, data, s * force, np.zeros(3), data.site_xpos[site], body,
                          data.qfrc_applied)
        if steps < ramp:
            mujoco.mj_step(model, data)
            steps += 1
            continue
        mujoco.mj_step(model, data, chunk)
        steps += chunk
        y = data.site_xpos[site][1]
        if not np.isfinite(y) or data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0:
            sys.exit("unstable: MuJoCo's acceleration guard tripped while settling")
        if last is not None and abs(y - last) < 1e-9 * abs(y):
            break
        last = y
    y0 = data.site_xpos[site][1]
    # Release.
    data.qfrc_applied[:] = 0.0
    data.qvel[:] = 0.0
    model.dof_damping[:] = 0.0
    # Record about 200 samples per guessed period (the Fourier transform needs the first
    # mode only; a light link's fast modes alias but stay out of the search band's peak).
    stride = max(1, int(period / dt / 200))
    n = int(30.0 * period / dt / stride)
    ys = np.empty(n)
    for k in range(n):
        mujoco.mj_step(model, data, stride)
        ys[k] = data.site_xpos[site][1]
    if not np.all(np.isfinite(ys)) or data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0:
        sys.exit("unstable: MuJoCo's acceleration guard tripped during the free vibration")
    ys -= ys.mean()
    t = np.arange(n) * dt * stride
    window = np.hanning(n)
    wy = ys * window

    def power(f):
        z = np.exp(-2j * math.pi * f * t)
        return -abs(np.dot(wy, z))

    lo, hi = 0.5 * guess, 2.0 * guess
    # Coarse scan, then golden-section search around the best.
    grid = np.linspace(lo, hi, 400)
    best = grid[int(np.argmin([power(f) for f in grid]))]
    a, b = best - (hi - lo) / 399, best + (hi - lo) / 399
    g = (math.sqrt(5) - 1) / 2
    c, d = b - g * (b - a), a + g * (b - a)
    for _ in range(80):
        if power(c) < power(d):
            b = d
        else:
            a = c
        c, d = b - g * (b - a), a + g * (b - a)
    print(json.dumps({"hz": (a + b) / 2, "steps": steps + n * stride, "amplitude": y0,
                      "timestep": dt}))


if __name__ == "__main__":
    main()
